// lockstep diff: two images, idiff style (core/metrics.h).
#include <cstdio>
#include <string>

#include "app/cli.h"
#include "core/image.h"
#include "core/output_image.h"
#include "core/metrics.h"

namespace lockstep::cli {

namespace {

void print_help(const CompareOptions& d) {
  std::printf(
      "usage: lockstep diff A B [--fail T] [--failpercent P] [--warn W] [--hardfail H] [--heatmap OUT]\n"
      "\n"
      "Compares two images per channel (R, G, B and alpha) by absolute difference. A pixel\n"
      "fails when its largest channel error exceeds T; the images agree when at most P percent\n"
      "of the pixels fail and no pixel exceeds H. Numbers may be written as fractions (1/255).\n"
      "\n"
      "  --fail T          per-pixel failure threshold (default %.6g = 1/255, ray_cast's)\n"
      "  --failpercent P   percent of pixels allowed to fail (default %.3g, ray_cast's)\n"
      "  --warn W          per-pixel warning threshold (default %.6g)\n"
      "  --hardfail H      any pixel above H fails outright (default: off)\n"
      "  --heatmap OUT     write a heat map of the error (black 0, blue, green, yellow, red at the max)\n"
      "\n"
      "Exit codes: 0 the images agree (PASS), 1 they differ (FAIL, also for different sizes),\n"
      "2 bad usage or unreadable image.\n",
      d.fail_threshold, d.fail_percent, d.warn_threshold);
}

}  // namespace

int diff_main(Args args) {
  CompareOptions opt;
  // Defaults from the registry's first family (ray_cast): a pixel within
  // abs on fraction of the image.
  const Tolerance& tol = registry().families.front().tol;
  opt.fail_threshold = tol.abs;
  opt.fail_percent = 100.0 * (1.0 - tol.fraction);
  std::string a_path, b_path, heat_path, value;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string_view a = args[i];
    if (a == "--help" || a == "-h") {
      print_help(opt);
      return kExitOk;
    } else if (take_option(args, i, "--fail", value)) {
      opt.fail_threshold = parse_number("--fail", value, 0, 1e30);
    } else if (take_option(args, i, "--failpercent", value)) {
      opt.fail_percent = parse_number("--failpercent", value, 0, 100);
    } else if (take_option(args, i, "--warn", value)) {
      opt.warn_threshold = parse_number("--warn", value, 0, 1e30);
    } else if (take_option(args, i, "--hardfail", value)) {
      opt.hard_fail = parse_number("--hardfail", value, 0, 1e30);
    } else if (take_option(args, i, "--heatmap", value)) {
      heat_path = value;
    } else if (is_option(a)) {
      unknown_option(a);
    } else if (a_path.empty()) {
      a_path = std::string(a);
    } else if (b_path.empty()) {
      b_path = std::string(a);
    } else {
      throw UsageError("unexpected argument '" + std::string(a) + "' (two images)");
    }
  }
  if (b_path.empty()) throw UsageError(a_path.empty() ? "missing images A and B" : "missing image B");
  if (!heat_path.empty()) image_kind().check_path(heat_path);
  const Image a = read_image(a_path);
  const Image b = read_image(b_path);

  const ImageError e = compare_images(a, b, opt);
  std::printf("A  %s  %dx%d\n", a_path.c_str(), a.width, a.height);
  std::printf("B  %s  %dx%d\n", b_path.c_str(), b.width, b.height);
  if (!e.same_size) {
    std::printf("images differ in size\nFAIL\n");
    return kExitFail;
  }
  if (!heat_path.empty()) write_image(error_heatmap(a, b), heat_path);
  std::printf("max error       %.6g", e.max_error);
  if (e.max_x >= 0) std::printf("  at (%d, %d)", e.max_x, e.max_y);
  std::printf("\nmean error      %.6g\nrms error       %.6g\n", e.mean_error, e.rms_error);
  std::printf("PSNR            %.2f dB\n", e.psnr);
  std::printf("pixels warned   %ld of %ld (%.4f%%) over %.6g\n", e.pixels_warned, e.pixels,
              e.pixels ? 100.0 * double(e.pixels_warned) / double(e.pixels) : 0.0, opt.warn_threshold);
  std::printf("pixels failed   %ld of %ld (%.4f%%) over %.6g, %.4g%% allowed\n", e.pixels_failed, e.pixels,
              e.percent_failed(), opt.fail_threshold, opt.fail_percent);
  if (!heat_path.empty()) std::printf("heat map        %s (red = %.6g)\n", heat_path.c_str(), e.max_error);
  std::printf("%s\n", e.pass ? "PASS" : "FAIL");
  return e.pass ? kExitOk : kExitFail;
}

}  // namespace lockstep::cli
