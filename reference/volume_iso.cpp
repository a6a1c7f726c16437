// lockstep reference: the isosurface of the trilinear interpolant, ray cast.
//
// Levoy 1988 ("surfaces from volume data"); Parker et al., "Interactive Ray
// Tracing for Isosurface Rendering", IEEE Visualization 1998 (the first
// crossing of the interpolant along the ray). For every pixel:
//   1. march the ray's samples (core/volume_render.h: every dt on shared planes);
//   2. the first pair of neighbouring samples on opposite sides of iso (one
//      below, one at or above) brackets a crossing of the interpolant;
//   3. refine it by bisection, kIsoBisections halvings of the bracket: the hit
//      is then as exact as the arithmetic (a crossing the samples step over,
//      a thin sliver entered and left within dt, is missed: that is the
//      step's error, the same in every implementation);
//   4. shade it from the gradient (central differences, interpolated), a light
//      at the eye, two-sided.
// A ray that meets no crossing shows the background (0, 0, 0, 0).
#include <cmath>
#include <string>

#include "core/volume_render.h"
#include "io/volume_settings.h"
#include "reference/volume_render.h"

namespace lockstep::ref {

Image volume_iso(const Volume& volume, const FrameOptions& options, FrameStats* stats) {
  const vr::Settings s = vr::settings(options.params, volume.source, vr::Mode::kIso);
  const vr::View view = vr::make_view(volume, s, options.width, options.height);
  const Vec3 base = vr::iso_base(s);
  Image image(options.width, options.height);
  for (int y = 0; y < view.height; ++y) {
    for (int x = 0; x < view.width; ++x) {
      const Vec3 o = vr::ray_origin(view, x, y);
      long k0, k1;
      vr::ray_samples(view, o, k0, k1);
      auto above = [&](double t) { return vr::trilinear(volume, o + t * view.dir) >= s.iso; };
      // 1, 2. The first bracket.
      bool hit = false;
      double t_lo = 0, t_hi = 0;
      for (long k = k0 + 1; k <= k1 && !hit; ++k) {
        t_lo = double(k - 1) * view.dt;
        t_hi = double(k) * view.dt;
        hit = above(t_lo) != above(t_hi);
      }
      if (!hit) continue;
      // 3. Bisection: keep the half whose ends still differ.
      const bool first_above = above(t_lo);
      for (int n = 0; n < vr::kIsoBisections; ++n) {
        const double mid = 0.5 * (t_lo + t_hi);
        (above(mid) == first_above ? t_lo : t_hi) = mid;
      }
      const Vec3 p = o + (0.5 * (t_lo + t_hi)) * view.dir;
      // 4. Shading.
      image.set(x, y, vr::iso_shade(base, vr::gradient(volume, p), view.dir), 1.0f);
    }
    if (options.progress) options.progress(double(y + 1) / view.height);
  }
  if (stats) stats->items = uint64_t(view.width) * uint64_t(view.height);
  return image;
}

}  // namespace lockstep::ref
