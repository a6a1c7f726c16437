// lockstep reference: V-buffer ray casting, as the lecture notes give it.
//
// Levoy, "Display of Surfaces from Volume Data", IEEE CG&A 1988; Upson and
// Keeler, "V-BUFFER: Visible Volume Rendering", SIGGRAPH 1988; Engel et al.,
// "Real-Time Volume Graphics" (2006), ch. 1 and 3. For every pixel:
//   1. cast a ray through the volume's box (parallel projection);
//   2. take a sample every dt along it (core/volume_render.h: the shared planes);
//   3. reconstruct the value there by trilinear interpolation;
//   4. classify it: the transfer function gives a colour and an opacity for a
//      reference step, corrected for dt: alpha' = 1 - (1 - alpha)^(dt/dt0);
//   5. composite front to back with premultiplied `over` (Porter and Duff,
//      the compositing family's operator): the sample goes *under* what is
//      in front, C += (1 - A) alpha' c, A += (1 - A) alpha';
//   6. stop once A >= 1 - eps: nothing behind can show by more than eps.
#include <algorithm>
#include <cmath>
#include <string>

#include "core/volume_render.h"
#include "io/volume_settings.h"
#include "reference/volume_render.h"

namespace lockstep::ref {

Image volume_raycast(const Volume& volume, const FrameOptions& options, FrameStats* stats) {
  const vr::Settings s = vr::settings(options.params, volume.source, vr::Mode::kRaycast);
  const vr::View view = vr::make_view(volume, s, options.width, options.height);
  Image image(options.width, options.height);
  for (int y = 0; y < view.height; ++y) {
    for (int x = 0; x < view.width; ++x) {
      // 1. The ray, and the samples of it inside the box.
      const Vec3 o = vr::ray_origin(view, x, y);
      long k0, k1;
      vr::ray_samples(view, o, k0, k1);
      double c[3] = {0, 0, 0}, a = 0;
      for (long k = k0; k <= k1; ++k) {
        // 2, 3. The sample.
        const double value = vr::trilinear(volume, o + (double(k) * view.dt) * view.dir);
        // 4. Classification and opacity for this step.
        double rgba[4];
        s.tf.eval(value, rgba);
        const double alpha = vr::correct_opacity(rgba[3], view.ratio);
        // 5. Under what is already in front.
        const double w = (1 - a) * alpha;
        for (int ch = 0; ch < 3; ++ch) c[ch] += w * rgba[ch];
        a += w;
        // 6. Early ray termination.
        if (s.eps > 0 && a >= 1 - s.eps) break;
      }
      float* p = image.pixel(x, y);
      p[0] = float(c[0]);
      p[1] = float(c[1]);
      p[2] = float(c[2]);
      p[3] = float(a);
    }
    if (options.progress) options.progress(double(y + 1) / view.height);
  }
  if (stats) stats->items = uint64_t(view.width) * uint64_t(view.height);
  return image;
}

}  // namespace lockstep::ref
