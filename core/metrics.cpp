#include "core/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lockstep {

ImageError compare_images(const Image& a, const Image& b, const CompareOptions& opt) {
  ImageError e;
  if (a.width != b.width || a.height != b.height) {
    e.same_size = false;
    e.pass = false;
    e.max_error = kInfinity;
    return e;
  }
  e.pixels = long(a.width) * long(a.height);
  double sum = 0, sum2 = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const float* p = a.pixel(x, y);
      const float* q = b.pixel(x, y);
      double worst = 0;
      for (int c = 0; c < 4; ++c) {
        double d = std::abs(double(p[c]) - double(q[c]));
        if (std::isnan(d)) d = kInfinity;  // NaN in one image is the worst possible error
        worst = std::max(worst, d);
        if (c < 3) {
          sum += std::min(d, 1e30);
          sum2 += std::min(d * d, 1e30);
        }
      }
      if (worst > e.max_error) {
        e.max_error = worst;
        e.max_x = x;
        e.max_y = y;
      }
      if (worst > opt.fail_threshold) ++e.pixels_failed;
      if (worst > opt.warn_threshold) ++e.pixels_warned;
    }
  const double n = double(e.pixels) * 3;
  e.mean_error = n > 0 ? sum / n : 0;
  e.rms_error = n > 0 ? std::sqrt(sum2 / n) : 0;
  e.psnr = e.rms_error > 0 ? 20.0 * std::log10(1.0 / e.rms_error) : kInfinity;
  e.pass = e.percent_failed() <= opt.fail_percent && e.max_error <= opt.hard_fail;
  return e;
}

Image error_heatmap(const Image& a, const Image& b, double scale) {
  const int w = std::min(a.width, b.width), h = std::min(a.height, b.height);
  Image out(w, h);
  std::vector<double> err(size_t(w) * size_t(h));
  double mx = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double worst = 0;
      for (int c = 0; c < 4; ++c) worst = std::max(worst, double(std::abs(a.pixel(x, y)[c] - b.pixel(x, y)[c])));
      err[size_t(y) * size_t(w) + size_t(x)] = worst;
      mx = std::max(mx, worst);
    }
  if (scale <= 0) scale = mx > 0 ? mx : 1;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double e = err[size_t(y) * size_t(w) + size_t(x)];
      if (e == 0) {
        out.set(x, y, {0, 0, 0});
        continue;
      }
      // Even a tiny error stays visible: start at dim blue.
      const double t = std::clamp(e / scale, 0.0, 1.0);
      Vec3 c;
      if (t < 1.0 / 3) c = {0, 3 * t, 0.4 + 0.6 * (1 - 3 * t)};
      else if (t < 2.0 / 3) c = {3 * t - 1, 1, 0};
      else c = {1, 1 - (3 * t - 2), 0};
      out.set(x, y, c);
    }
  return out;
}

std::string describe(const ImageError& e) {
  if (!e.same_size) return "images differ in size";
  char buf[200];
  std::snprintf(buf, sizeof buf, "max %.3g mean %.3g rms %.3g psnr %.1f dB failed %.3f%%", e.max_error,
                e.mean_error, e.rms_error, e.psnr, e.percent_failed());
  return buf;
}

}  // namespace lockstep
