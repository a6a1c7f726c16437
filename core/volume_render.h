// lockstep core: volume rendering -- the contract every implementation shares:
// the settings, the view (which rays, which sample points), trilinear
// reconstruction, opacity correction and the isosurface shading.
//
// Three families draw a volume into an image (registry/volume_rows.cpp):
//   volume      V-buffer ray casting (Levoy 1988; Upson and Keeler, "V-BUFFER:
//               Visible Volume Rendering", SIGGRAPH 1988): one ray per pixel,
//               samples every dt, each classified by the transfer function and
//               composited front to back with premultiplied `over`;
//   splat       splatting (Westover, "Footprint Evaluation for Volume
//               Rendering", SIGGRAPH 1990): each voxel a Gaussian footprint,
//               composited in depth order -- another method, compared with ray
//               casting (a stated difference, not an agreement);
//   volume_iso  the isosurface of the trilinear interpolant: the first point
//               along each ray where it equals iso, shaded from its gradient.
//
// The view is a parallel projection (as VolPack's shear-warp, the peer row):
// the camera looks at the volume's centre from azimuth `az` (degrees, about
// the world z axis, from +x towards +y) and elevation `el` (degrees above the
// x-y plane); image up is the world z axis projected (y when looking along z),
// turned by `roll` degrees about the viewing direction (the CT head's z runs
// from the crown down: roll 180 stands it up).
// The image's shorter side spans the volume's bounding sphere, row 0 at the
// top. Every ray starts on one plane in front of the volume; sample k of a ray
// sits at distance k dt from that plane, so samples of all rays lie on shared
// planes parallel to the image (no "wood grain" from per-ray starting points)
// and every implementation samples the same points.
//
// The volume's box is [origin, origin + (n - 1) spacing] per axis: sample
// points outside it are not taken. The value at a point is the trilinear
// interpolant of the 8 surrounding samples.
//
// Output: premultiplied RGBA, linear float; the background is (0, 0, 0, 0), so
// an image's alpha says how opaque the volume is there.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/family.h"
#include "core/image.h"
#include "core/math.h"
#include "core/transfer_function.h"
#include "core/volume.h"

namespace lockstep::vr {

// ---------------------------------------------------------------- settings

enum class Mode { kRaycast, kSplat, kIso };

struct Settings {
  TransferFunction tf;        // raycast, splat: required; iso: the surface's colour at iso when given
  bool has_tf = false;
  double step = 0.5;          // dt in voxels (the smallest spacing); raycast and iso
  double azimuth = 30, elevation = 20, roll = 0;  // degrees
  double eps = 1.0 / 256;     // raycast: a ray stops once its opacity reaches 1 - eps (0: never)
  double iso = 0;             // iso: the value (required)
  bool skip = true;           // implementations that skip empty space may (false: they must not)
  double error = 0;           // raycast: > 0 asks for the step and eps whose error against the
                              // converged image stays under it (choose_for_error; registry/volume_rows.cpp)
};

// The settings each mode takes (read from Params by vr::settings, io/volume_settings.h).
std::vector<ParamSpec> params(Mode mode);

// ---------------------------------------------------------------- the view

struct View {
  int width = 0, height = 0;
  Vec3 dir;          // unit direction every ray travels
  Vec3 corner;       // the ray origin of pixel (0, 0)'s corner: pixel (x, y)'s origin is corner + (x + 0.5) du + (y + 0.5) dv
  Vec3 du, dv;       // one pixel right, one pixel down, in world units
  Vec3 lo, hi;       // the volume's box
  double dt = 0;     // the step in world units (step x smallest spacing)
  double ratio = 1;  // dt / dt0: the exponent of the opacity correction
};

View make_view(const Volume& v, const Settings& s, int width, int height);

// The origin of pixel (x, y)'s ray.
inline Vec3 ray_origin(const View& view, int x, int y) {
  return view.corner + (x + 0.5) * view.du + (y + 0.5) * view.dv;
}

// The samples of the ray from o that lie in the box: k in [k0, k1] (none when
// k0 > k1), sample k at o + k dt dir. Slab clipping (Kay and Kajiya 1986) in double.
void ray_samples(const View& view, const Vec3& o, long& k0, long& k1);

// ---------------------------------------------------------------- sampling

// The trilinear interpolant at world point p (clamped to the box).
double trilinear(const Volume& v, const Vec3& p);
// Its gradient estimated the classic way: central differences at the 8
// surrounding samples (one-sided at the border), interpolated trilinearly.
Vec3 gradient(const Volume& v, const Vec3& p);

// alpha' = 1 - (1 - alpha)^ratio: the opacity of a slab ratio reference steps thick.
inline double correct_opacity(double alpha, double ratio) {
  return alpha >= 1 ? 1.0 : 1.0 - std::pow(1.0 - alpha, ratio);
}

// The isosurface's shade at a hit: base colour times (ambient + diffuse) from
// a light at the eye, two-sided (a surface seen from inside is lit too):
//   c = base (0.2 + 0.8 |n . dir|), n = gradient / |gradient| (0 gradient: ambient only).
Vec3 iso_shade(const Vec3& base, const Vec3& grad, const Vec3& dir);
// The base colour of the isosurface: the transfer function's colour at iso when
// one was given, else a light grey.
Vec3 iso_base(const Settings& s);

// When iso lies outside the volume's values (not an error: the surface is not
// there), the note that says so for FrameStats::notes; "" otherwise.
std::string empty_note(const Volume& v, double iso);

// ---------------------------------------------------------------- error=E

// error=E (raycast) bounds a frame's total error: the step along the ray and
// the early-termination threshold eps are both chosen so that the frame's
// error against the converged image -- the same view at step 1/16 (the finest
// of the search, kConvergedStep) with no early termination (eps 0) -- is at
// most E. Both sources count: the step's (sampling) and the termination's (a
// ray stopped at opacity 1 - eps misses up to eps per channel of what lies
// behind; on a CT with an opaque transfer function that alone is ~2e-4 per
// channel at eps 1/256, more than a fine step's error).
//
// The error: the mean absolute difference per channel (R, G, B and A) over the
// covered pixels, those whose converged alpha is > 0. The empty background
// (converged alpha 0) is left out of the count, which would otherwise dilute
// the mean by the share of empty pixels; its differences still enter the sum
// (they are 0 but for rounding: every step's sample points are among step
// 1/16's, on the same planes, so a pixel empty at 1/16 is empty at every
// step), so the figure is never below the covered pixels' own mean. No
// covered pixel: the sum over 4 channels alone.
inline constexpr double kConvergedStep = 1.0 / 16;
// The steps tried, largest (cheapest) first, and for a step that meets E
// without early termination the eps values tried, largest first (then 0).
inline constexpr double kErrorSteps[] = {4, 2, 1, 0.5, 0.25, 0.125};
inline constexpr double kErrorEps[] = {1.0 / 256, 1.0 / 1024, 1.0 / 4096, 1.0 / 16384, 1.0 / 65536};

struct CoveredError {
  double mean = 0;       // per channel over the covered pixels (above)
  uint64_t covered = 0;  // pixels whose converged alpha is > 0
};
CoveredError covered_error(const Image& image, const Image& converged);

struct ErrorChoice {
  bool met = false;      // false: not even the finest step without termination meets E
  double step = 0, eps = 0;
  CoveredError error;    // of `image` against the converged image
  Image image;           // the frame at (step, eps) (met), else the best one measured
};

// The search: render(step, eps) draws the frame; the converged image first,
// then for each step of kErrorSteps, largest first, the frame without early
// termination; the first step whose error is <= target is taken, with the
// largest eps of kErrorEps whose frame is still <= target (else eps 0). The
// frame returned is one of those measured, so its error is the one reported.
// Not met: the finest step's frame and its error (the best achievable).
ErrorChoice choose_for_error(double target, const std::function<Image(double step, double eps)>& render);

// "1/1024", "0", or the number: how the stats line names an eps or a step.
std::string fraction_text(double x);

// Bisection steps the reference takes between the two samples that bracket a
// crossing: the hit is then within dt 2^-kIsoBisections of the interpolant's.
// Not below float resolution: the 24th still changes 29-464 pixels of the
// corpus' vi-* frames by an ulp (measured: tests/volume_render_test.cpp,
// VolumeIso.SimdEqualsTheReferenceBitForBit), so fewer would change goldens.
inline constexpr int kIsoBisections = 24;

// Splatting's blob: its standard deviation, in spacings, and the footprint's
// cut-off, in standard deviations (reference/volume_splat.cpp says why; every
// splatting row draws the same footprints).
inline constexpr double kSplatSigma = 0.6;
inline constexpr double kSplatCutoff = 3.0;

}  // namespace lockstep::vr
