#include "kinds/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "io/oiio.h"

namespace lockstep {

namespace {

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
  // ImageBufAlgo::compare, in lockstep_oiio.so (io/oiio.h).
  const oiio::ModuleApi& io = oiio::api();
  oiio::CompareStats r;
  io.compare(a, b, float(opt.fail_threshold), float(opt.warn_threshold), &r);
  e.max_error = r.max_error;
  e.max_x = r.max_x;
  e.max_y = r.max_y;
  e.mean_error = r.mean_error;
  e.rms_error = r.rms_error;
  e.psnr = r.rms_error > 0 ? r.psnr : kInfinity;
  e.pixels_failed = r.failed;
  e.pixels_warned = r.warned;
  if (std::isfinite(opt.hard_fail)) {
    oiio::CompareStats hard;
    io.compare(a, b, float(opt.hard_fail), float(opt.hard_fail), &hard);
    e.over_hard = hard.failed;
  }
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
  // absdiff, maxchan, color_map: in lockstep_oiio.so (io/oiio.h).
  Image out;
  oiio::Error err;
  if (!oiio::api().heatmap(a, b, scale, &out, &err)) oiio::raise(err);
  const int w = out.width, h = out.height;
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
