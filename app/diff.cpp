// lockstep diff: two images, idiff style (kinds/image_metrics.h); or many pairs in
// one call (a list file, or two folders), so that scripts pay the process's
// start-up once, not once per image (issue #21, "One-shot cost").
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "app/cli.h"
#include "core/image.h"
#include "kinds/image_kind.h"
#include "kinds/image_metrics.h"
#include "io/image_io.h"
#include "io/tokenizer.h"

namespace lockstep::cli {

namespace {

void print_help(const CompareOptions& d) {
  std::printf(
      "usage: lockstep diff A B [--fail T] [--failpercent P] [--warn W] [--hardfail H] [--heatmap OUT]\n"
      "       lockstep diff --list FILE [options]   (many pairs: one line 'A B' each)\n"
      "       lockstep diff DIR_A DIR_B [options]   (every image of DIR_A against DIR_B's of the same name)\n"
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
      "Many pairs: --list FILE reads one pair per line, 'A B' (paths without spaces, relative\n"
      "ones from the current folder); blank lines and lines starting with '#' are skipped.\n"
      "DIR_A DIR_B pairs the images (.png .exr .tif .tiff .jpg .jpeg .hdr .ppm .pfm .bmp .tga\n"
      ".webp) under DIR_A with those of the same relative name under DIR_B; an image on one\n"
      "side only is bad input. One line per pair (PASS or FAIL, the two paths, max error and\n"
      "failed pixels) and a summary line; --heatmap takes one pair only.\n"
      "\n"
      "Exit codes: 0 the images agree (PASS; every pair), 1 they differ (FAIL, also for\n"
      "different sizes; any pair), 2 bad usage, unreadable image, or a list or folder naming\n"
      "a missing image (nothing is compared then).\n",
      d.fail_threshold, d.fail_percent, d.warn_threshold);
}

namespace fs = std::filesystem;

using Pair = std::pair<std::string, std::string>;

// The pairs of a list file: 'A B' per line, '#' comments; errors name file:line.
std::vector<Pair> read_list(const std::string& path) {
  const std::string text = text::read_text_file(path,
                                                {.missing = "cannot read the list: no such file",
                                                 .folder = "cannot read the list: is a folder",
                                                 .unreadable = "cannot read the list",
                                                 .read_error = "cannot read the list"},
                                                text::kMaxListBytes);
  std::vector<Pair> pairs;
  text::Tokenizer in(text, path, {.comments = text::Comments::line_start});
  std::error_code ec;
  while (in.next()) {
    const auto& w = in.words();
    if (w.size() != 2)
      in.fail("expected two image paths 'A B', got " + std::to_string(w.size()) + " field" + (w.size() == 1 ? "" : "s"));
    for (const std::string_view f : w)
      if (!fs::is_regular_file(f, ec)) in.fail("image " + std::string(f) + " does not exist");
    pairs.emplace_back(w[0], w[1]);
  }
  if (pairs.empty()) throw InputError(path, 0, "the list names no pair");
  return pairs;
}

bool is_image_name(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  static constexpr std::string_view kExt[] = {".png", ".exr", ".tif", ".tiff", ".jpg", ".jpeg",
                                              ".hdr", ".ppm", ".pfm", ".bmp",  ".tga", ".webp"};
  return std::find(std::begin(kExt), std::end(kExt), e) != std::end(kExt);
}

// The images under dir, as paths relative to it, sorted.
std::set<std::string> images_under(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file() && is_image_name(e.path()))
      names.insert(fs::relative(e.path(), dir).generic_string());
  return names;
}

// Every image of a under b by the same relative name; one side only is bad input.
std::vector<Pair> folder_pairs(const std::string& a, const std::string& b) {
  const std::set<std::string> in_a = images_under(a), in_b = images_under(b);
  for (const std::string& n : in_a)
    if (!in_b.count(n))
      throw InputError((fs::path(b) / n).string(), 0,
                       "missing: " + (fs::path(a) / n).string() + " has no counterpart");
  for (const std::string& n : in_b)
    if (!in_a.count(n))
      throw InputError((fs::path(a) / n).string(), 0,
                       "missing: " + (fs::path(b) / n).string() + " has no counterpart");
  if (in_a.empty()) throw InputError(a, 0, "no images in this folder (nor in " + b + ")");
  std::vector<Pair> pairs;
  for (const std::string& n : in_a)
    pairs.emplace_back((fs::path(a) / n).string(), (fs::path(b) / n).string());
  return pairs;
}

// One line per pair and a summary; exit 1 when any pair differs.
int diff_many(const std::vector<Pair>& pairs, const CompareOptions& opt) {
  size_t failed = 0;
  for (const auto& [pa, pb] : pairs) {
    const Image a = read_image(pa);
    const Image b = read_image(pb);
    const ImageError e = compare_images(a, b, opt);
    if (!e.same_size) {
      std::printf("FAIL  %s  %s  sizes differ (%dx%d, %dx%d)\n", pa.c_str(), pb.c_str(), a.width,
                  a.height, b.width, b.height);
      ++failed;
      continue;
    }
    if (!e.pass) ++failed;
    std::printf("%s  %s  %s  max %.6g  failed %ld of %ld (%.4f%%)\n", e.pass ? "PASS" : "FAIL",
                pa.c_str(), pb.c_str(), e.max_error, e.pixels_failed, e.pixels, e.percent_failed());
  }
  std::printf("%zu pairs: %zu pass, %zu fail\n%s\n", pairs.size(), pairs.size() - failed, failed,
              failed ? "FAIL" : "PASS");
  return failed ? kExitFail : kExitOk;
}

}  // namespace

int diff_main(Args args) {
  CompareOptions opt;
  // Defaults from the registry's first family (ray_cast): a pixel within
  // abs on fraction of the image.
  const Tolerance& tol = registry().families.front().tol;
  opt.fail_threshold = tol.abs;
  opt.fail_percent = 100.0 * (1.0 - tol.fraction);
  std::string a_path, b_path, heat_path, list_path, value;
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
    } else if (take_option(args, i, "--list", value)) {
      list_path = value;
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
  if (!list_path.empty()) {
    if (!a_path.empty()) throw UsageError("--list takes no images of its own ('" + a_path + "')");
    if (!heat_path.empty()) throw UsageError("--heatmap takes one pair, not a list");
    return diff_many(read_list(list_path), opt);
  }
  if (b_path.empty())
    throw UsageError(a_path.empty() ? "missing images A and B" : "missing image B");
  {
    std::error_code ec;
    const bool da = fs::is_directory(a_path, ec), db = fs::is_directory(b_path, ec);
    if (da != db)
      throw InputError(da ? a_path : b_path, 0,
                       "is a folder, the other argument is not (two images or two folders)");
    if (da) {
      if (!heat_path.empty()) throw UsageError("--heatmap takes one pair, not folders");
      return diff_many(folder_pairs(a_path, b_path), opt);
    }
  }
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
