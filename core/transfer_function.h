// lockstep core: transfer functions -- what a volume's value looks like.
//
// Volume rendering classifies each sample by a transfer function: a value
// goes to a colour and an opacity (Levoy, "Display of Surfaces from Volume
// Data", IEEE CG&A 1988; Engel et al., "Real-Time Volume Graphics", ch. 4).
// Here it is piecewise linear between control points (value, r, g, b, alpha),
// constant beyond the first and the last, in the volume's own units (CT
// numbers, MRI intensities, a field's values).
//
// What alpha means. A control point's alpha is the opacity of a slab one
// *reference step* thick, dt0 = 1 voxel (the volume's smallest spacing). A
// renderer that steps dt corrects it (Engel et al. 1.4.3):
//     alpha' = 1 - (1 - alpha)^(dt / dt0),
// so an image converges as dt shrinks instead of growing more opaque. Colours
// are straight (not premultiplied); the renderer weights them by alpha'.
//
// A transfer function file (.tf, read by io/transfer_function_io.h): text, '#' starts a comment, one control
// point per line, five numbers: value r g b alpha. Values strictly increase
// from line to line; r, g, b and alpha lie in [0, 1]; at least one point and
// at most kMaxControlPoints. Anything else (a missing or extra number, text,
// NaN, values out of order or out of range) is an InputError naming the line.
//
// Presets, by name instead of a file (the values are the CT head's 12-bit
// numbers and the MRI's 8-bit intensities, ../shared/volumes/README.md):
//   ct-bone  bone (1250 and up) opaque, everything below transparent
//   ct-skin  the skin's edge (400-950) faint, bone behind it
//   mri      the Colin27 brain: skin faint, white matter brighter
//   ramp     grey, alpha 0 at 0 rising to 1 at 1 (analytic fields in [0, 1])
#pragma once

#include <string>
#include <vector>

namespace lockstep {

struct ControlPoint {
  double value = 0;
  float r = 0, g = 0, b = 0, a = 0;
};

inline constexpr int kMaxControlPoints = 4096;

struct TransferFunction {
  std::vector<ControlPoint> points;  // strictly increasing values, at least one
  std::string source;                // the file or the preset's name

  // The straight colour and the reference-step opacity at v: linear between
  // the two control points around v, constant outside them. Returns into out[4].
  void eval(double v, double out[4]) const;
  // Largest alpha over [lo, hi] (a control point's, or an end's): 0 means a
  // stretch of values is fully transparent and can be skipped.
  double max_alpha(double lo, double hi) const;
};

// The preset's name list for --help: "ct-bone|ct-skin|mri|ramp".
const char* transfer_presets();
// The preset of that name; no points when there is none.
TransferFunction transfer_preset(const std::string& name);

}  // namespace lockstep
