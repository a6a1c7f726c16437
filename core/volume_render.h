// lockstep core: volume rendering -- the contract every implementation shares:
// the settings, the view (which rays, which sample points), trilinear
// reconstruction, opacity correction and the isosurface shading.
//
// Three families draw a volume into an image (pairs/volume.cpp):
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

#include <string>
#include <vector>

#include "core/family.h"
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
  double error = 0;           // raycast: > 0 asks for the largest step whose error stays under it
                              // (the family's rows measure it: pairs/volume.cpp, ref::step_for_error)
};

// Throws InputError(source, 0, ...) naming a bad or missing setting (a bad .tf
// file: InputError(file, line, ...)).
Settings settings(const Params& p, const std::string& source, Mode mode);
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

// Bisection steps the reference takes between the two samples that bracket a
// crossing: the hit is then within dt 2^-kIsoBisections of the interpolant's.
// Not below float resolution: the 24th still changes 29-464 pixels of the
// corpus' vi-* frames by an ulp (measured: tests/volume_render_test.cpp,
// VolumeIso.SimdEqualsTheReferenceBitForBit), so fewer would change goldens.
inline constexpr int kIsoBisections = 24;

}  // namespace lockstep::vr
