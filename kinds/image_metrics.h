// lockstep kinds: error metrics between two images, idiff's.
//
// The comparison is OpenImageIO's own ImageBufAlgo::compare (the code behind
// idiff, so `lockstep diff` and idiff agree by construction): errors are per
// channel (R, G, B and alpha) absolute differences; a pixel "fails" when any
// channel's error exceeds fail_threshold and "warns" above warn_threshold;
// mean, RMS and PSNR are over every channel. What idiff lacks is added here: a
// NaN in either image is the worst possible error (idiff skips it), and
// hard_fail, a limit no pixel may exceed whatever fail_percent allows. A
// comparison passes when the share of failing pixels is at most fail_percent
// and no pixel exceeds hard_fail (or is NaN).
#pragma once

#include <string>

#include "core/image.h"

namespace lockstep {

struct CompareOptions {
  double fail_threshold = 1.0 / 255.0;
  double fail_percent = 0.1;   // percent of pixels allowed over fail_threshold
  double warn_threshold = 0.5 / 255.0;
  double hard_fail = kInfinity;  // any pixel above this fails the comparison outright
};

struct ImageError {
  bool same_size = true;
  double max_error = 0;
  double mean_error = 0;
  double rms_error = 0;
  double psnr = kInfinity;  // dB, peak 1.0
  long pixels = 0;
  long pixels_failed = 0;  // over fail_threshold
  long pixels_warned = 0;  // over warn_threshold
  long over_hard = 0;      // over hard_fail, or NaN in either image
  int max_x = -1, max_y = -1;  // where max_error is
  bool pass = true;
  double percent_failed() const { return pixels ? 100.0 * double(pixels_failed) / double(pixels) : 0.0; }
};

ImageError compare_images(const Image& a, const Image& b, const CompareOptions& opt = {});

// Heat map of |a - b| (largest channel; ImageBufAlgo absdiff, maxchan and
// color_map): black 0, then blue, green, yellow, red at scale and above; NaN is
// magenta. scale <= 0 picks the maximum error.
Image error_heatmap(const Image& a, const Image& b, double scale = 0);

// One line: "max 0.0012 mean 1e-5 rms 3e-5 psnr 88.1 dB failed 0.01%".
std::string describe(const ImageError& e);

}  // namespace lockstep
