#include "core/metrics.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lockstep {

namespace {

// An ImageBuf over the image's own pixels (no copy; read only).
OIIO::ImageBuf wrap(const Image& img) {
  const OIIO::ImageSpec spec(img.width, img.height, 4, OIIO::TypeDesc::FLOAT);
  return OIIO::ImageBuf(spec, const_cast<float*>(img.rgba.data()));
}

bool has_nan(const float* p) { return std::isnan(p[0]) || std::isnan(p[1]) || std::isnan(p[2]) || std::isnan(p[3]); }

}  // namespace

ImageError compare_images(const Image& a, const Image& b, const CompareOptions& opt) {
  ImageError e;
  if (a.width != b.width || a.height != b.height) {
    e.same_size = false;
    e.pass = false;
    e.max_error = kInfinity;
    return e;
  }
  e.pixels = long(a.width) * long(a.height);
  if (e.pixels == 0) return e;
  const OIIO::ImageBuf A = wrap(a), B = wrap(b);
  const auto r = OIIO::ImageBufAlgo::compare(A, B, float(opt.fail_threshold), float(opt.warn_threshold));
  e.max_error = r.maxerror;
  e.max_x = r.maxx;
  e.max_y = r.maxy;
  e.mean_error = r.meanerror;
  e.rms_error = r.rms_error;
  e.psnr = r.rms_error > 0 ? r.PSNR : kInfinity;
  e.pixels_failed = long(r.nfail);
  e.pixels_warned = long(r.nwarn);
  if (std::isfinite(opt.hard_fail))
    e.over_hard = long(OIIO::ImageBufAlgo::compare(A, B, float(opt.hard_fail), float(opt.hard_fail)).nfail);
  // NaN: idiff skips it; here it is the worst possible error, and fails every threshold.
  for (long i = 0; i < e.pixels; ++i) {
    const float *p = &a.rgba[size_t(i) * 4], *q = &b.rgba[size_t(i) * 4];
    if (!has_nan(p) && !has_nan(q)) continue;
    if (!(e.max_error == kInfinity)) {
      e.max_x = int(i % a.width);
      e.max_y = int(i / a.width);
    }
    e.max_error = kInfinity;
    ++e.pixels_failed;
    ++e.pixels_warned;
    ++e.over_hard;
  }
  e.pass = e.percent_failed() <= opt.fail_percent && e.over_hard == 0 && e.max_error <= opt.hard_fail;
  return e;
}

Image error_heatmap(const Image& a, const Image& b, double scale) {
  namespace iba = OIIO::ImageBufAlgo;
  const int w = std::min(a.width, b.width), h = std::min(a.height, b.height);
  const OIIO::ROI roi(0, w, 0, h, 0, 1, 0, 4);
  const OIIO::ImageBuf err = iba::maxchan(iba::absdiff(wrap(a), wrap(b), roi));
  if (scale <= 0) {
    const auto stats = iba::computePixelStats(err);
    scale = !stats.max.empty() && stats.max[0] > 0 ? stats.max[0] : 1;
  }
  // black, blue, green, yellow, red: 0 .. scale
  static constexpr float kKnots[] = {0, 0, 0, 0, 0, 1, 0, 1, 0, 1, 1, 0, 1, 0, 0};
  const OIIO::ImageBuf map = iba::color_map(iba::clamp(iba::mul(err, float(1 / scale)), 0.0f, 1.0f), 0, 5, 3, kKnots);
  Image out(w, h);
  map.get_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, 3), OIIO::TypeDesc::FLOAT, out.rgba.data(), 4 * sizeof(float));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = out.pixel(x, y);
      p[3] = 1;
      if (has_nan(a.pixel(x, y)) || has_nan(b.pixel(x, y))) p[0] = 1, p[1] = 0, p[2] = 1;
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
