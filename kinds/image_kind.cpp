// lockstep kinds: the image output kind (see kinds/image_kind.h).
#include "kinds/image_kind.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "core/error.h"
#include "core/family.h"
#include "io/image_io.h"
#include "io/oiio.h"

namespace lockstep {

namespace {

const Image& img(const Output& o) { return output_as<Image>(o); }

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

// ---------------------------------------------------------------- files

void write(const Output& o, const std::string& path) { write_image(img(o), path); }

Output read(const std::string& path) { return make_output<Image>(read_image(path)); }

// Goldens are stored as OpenEXR pxr24: floats rounded to 24 bits (relative error
// <= 2^-16, so within 1e-4 for values up to 6), a quarter of zip's size.
// pxr24 (24-bit floats, lossy: 2^-16 relative) keeps display values within
// the golden tolerance; larger values (radiosity's emitters, 53 in the Cornell
// box) are stored losslessly (zip).
void write_golden(const Output& o, const std::string& path) {
  const Image& im = img(o);
  bool large = false;
  for (float v : im.rgba) large = large || !(std::abs(v) <= 1);
  write_image(im, path, large ? "zip" : "pxr24");
}

// Fails (InputError) before any work is done when path cannot become an image:
// its folder does not exist or no writer is known for its extension.
void check_path(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path p(path);
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(path, 0, "cannot write image: folder " + dir.string() + " does not exist");
  if (fs::is_directory(p, ec)) throw InputError(path, 0, "cannot write image: is a folder");
  if (p.extension().empty()) throw InputError(path, 0, "cannot write image: no extension to pick the format (.png, .exr, .tif, ...)");
  if (!image_has_writer(path))  // .exr, .png; else lockstep_oiio.so (io/oiio.h)
    throw InputError(path, 0, "cannot write image: unknown format '" + p.extension().string() + "'");
}

// ---------------------------------------------------------------- comparison

Agreement agreement_of(const ImageError& e) {
  Agreement a;
  a.comparable = e.same_size;
  a.samples = e.pixels;
  a.over = e.pixels_failed;
  a.over_hard = e.over_hard;
  a.worst = e.max_error;
  a.score = e.psnr;
  a.pass = e.pass;
  return a;
}

Agreement compare(const Output& a, const Output& b, const Tolerance& tol) {
  return agreement_of(compare_images(img(a), img(b), compare_options(tol)));
}

std::string describe(const Agreement& a, const Tolerance& tol) {
  if (!a.comparable) return "images differ in size";
  if (a.over_hard > 0)
    return std::to_string(a.over_hard) + " px over the hard limit " + fmt("%.3g", tol.hard) +
           " (or NaN), which no budget excuses";
  if (a.over > 0) return std::to_string(a.over) + " px over " + fmt("%.4g", tol.abs);
  return {};
}

std::string describe_tolerance(const Tolerance& t) {
  return fmt("%.6g", t.abs) + " per channel on >= " + fmt("%.4g", 100.0 * t.fraction) + "% of the pixels, hard limit " +
         fmt("%.3g", t.hard);
}

// ---------------------------------------------------------------- report

// The report's pictures: PNG (8 bits), which every browser shows.
constexpr std::string_view kPictureExtension = ".png";

std::string save_view(const Output& o, const std::string& stem) {
  return save_picture(img(o), stem);
}

// Heat map: black = identical, blue to red = 0 to tol.abs (red: at or over it).
std::string save_difference(const Output& a, const Output& b, const Tolerance& tol, const std::string& stem) {
  return save_picture(error_heatmap(img(a), img(b), tol.abs), stem);
}

// ---------------------------------------------------------------- counts

std::string shape(const Output& o) { return std::to_string(img(o).width) + "x" + std::to_string(img(o).height); }

uint64_t count(const Output& o) { return uint64_t(img(o).width) * uint64_t(img(o).height); }

std::string check_frame(const Output& o, const FrameOptions& opts) {
  const Image& i = img(o);
  return i.width == opts.width && i.height == opts.height ? std::string() : "returned an image of the wrong size";
}

const void* data(const Output& o) { return img(o).rgba.data(); }

// ---------------------------------------------------------------- coverage judges

bool is_background(const float* p, const Vec3& bg) {
  return p[0] == float(bg.x) && p[1] == float(bg.y) && p[2] == float(bg.z);
}

struct Coverage {
  long expected_hit = 0;   // pixels that must be covered
  long expected_miss = 0;  // pixels that must be background
  long skipped = 0;        // on the boundary
  long missed = 0;         // must be covered, shows background (a hole, a leak)
  long spurious = 0;       // must be background, shows something
  long wrong() const { return missed + spurious; }
};

// Checks image against cover; mask becomes a picture of it (colours: the header).
Coverage judge_coverage(const Image& image, const std::vector<Cover>& cover, const Vec3& bg, Image& mask) {
  Coverage r;
  mask = Image(image.width, image.height);
  for (int j = 0; j < image.height; ++j)
    for (int i = 0; i < image.width; ++i) {
      const bool bgp = is_background(image.pixel(i, j), bg);
      Vec3 colour;
      switch (cover[size_t(j) * size_t(image.width) + size_t(i)]) {
        case Cover::kSkip:
          ++r.skipped;
          colour = {0.2, 0.3, 1.0};
          break;
        case Cover::kHit:
          ++r.expected_hit;
          if (bgp) ++r.missed;
          colour = bgp ? Vec3{1, 0, 0} : Vec3{0, 0.6, 0};
          break;
        case Cover::kMiss:
          ++r.expected_miss;
          if (!bgp) ++r.spurious;
          colour = bgp ? Vec3{0.15, 0.15, 0.15} : Vec3{1, 0, 1};
          break;
      }
      mask.set(i, j, colour);
    }
  return r;
}

// Colour agreement on the pixels both images cover (neither shows the
// background): how many there are and how many exceed the threshold.
Agreement compare_covered(const Image& a, const Image& b, const Vec3& bg, const Tolerance& tol) {
  Agreement r;
  for (int j = 0; j < a.height; ++j)
    for (int i = 0; i < a.width; ++i) {
      const float *p = a.pixel(i, j), *q = b.pixel(i, j);
      if (is_background(p, bg) || is_background(q, bg)) continue;
      ++r.samples;
      double e = 0;
      for (int k = 0; k < 4; ++k) {
        const double d = std::abs(double(p[k]) - double(q[k]));
        e = std::isnan(d) ? kInfinity : std::max(e, d);
      }
      r.worst = std::max(r.worst, e);
      r.over += e > tol.abs;
    }
  const long allowed = long(std::floor((1.0 - tol.fraction) * double(r.samples) + 1e-9));
  r.pass = r.over <= allowed && r.worst <= tol.hard;
  return r;
}

}  // namespace

std::string save_picture(const Image& image, const std::string& path_stem) {
  const std::string path = path_stem + std::string(kPictureExtension);
  write_image(image, path);
  return path;
}

std::string save_picture_scaled(const std::string& picture, int width, int height,
                                const std::string& path_stem) {
  const std::string path = path_stem + std::string(kPictureExtension);
  // OpenImageIO's resize, in lockstep_oiio.so (io/oiio.h).
  oiio::Error err;
  if (!oiio::api().write_resized(picture, path, width, height, &err)) oiio::raise(err);
  return path;
}

CompareOptions compare_options(const Tolerance& tol) {
  CompareOptions c;
  c.fail_threshold = tol.abs;
  c.fail_percent = 100.0 * (1.0 - tol.fraction);
  c.hard_fail = tol.hard;
  return c;
}

const OutputKind& image_kind() {
  static const OutputKind k{
      .name = "image",
      .samples = "pixels",
      .sample = "px",
      .score = "PSNR dB",
      .legend = "score = PSNR in dB (peak 1); goldens are OpenEXR (pxr24). Heat maps: black = identical, blue to "
                "red = 0 to the case's threshold (red: at or over it); judge masks: green hit as it must, grey "
                "background as it must, red a missing hit, magenta a spurious hit, blue on the boundary (skipped).",
      .write = write,
      .check_path = check_path,
      .read = read,
      .golden_extension = ".exr",
      .write_golden = write_golden,
      .compare = compare,
      .describe = describe,
      .describe_tolerance = describe_tolerance,
      .save_view = save_view,
      .save_difference = save_difference,
      .save_beside = save_picture_scaled,
      .picture_extension = kPictureExtension,
      .picture_type = "image/png",
      .shape = shape,
      .count = count,
      .check_frame = check_frame,
      .data = data,
  };
  return k;
}

Judge image_judge(std::string_view name, std::string_view what, std::function<void(const Input&)> check,
                  CoverageFn coverage) {
  Judge j;
  j.name = name;
  j.what = what;
  j.check = std::move(check);
  j.prepare = [coverage = std::move(coverage)](const Input& in, const FrameOptions& o) -> JudgeFrame {
    auto cover = std::make_shared<const std::vector<Cover>>(coverage(in, o.width, o.height));
    return [cover, bg = in.background](const Output& out, const Output* ref, const Tolerance& tol) {
      JudgeVerdict v;
      Image mask;
      const Coverage c = judge_coverage(img(out), *cover, bg, mask);
      v.picture = make_output<Image>(std::move(mask));
      v.wrong = c.wrong();
      v.detail = c.wrong() > 0 ? std::to_string(c.wrong()) + " px differ from analytic (" + std::to_string(c.missed) +
                                     " missing, " + std::to_string(c.spurious) + " spurious; " +
                                     std::to_string(c.expected_hit) + " must hit, " + std::to_string(c.skipped) +
                                     " on the boundary skipped)"
                               : std::to_string(c.expected_hit) + " must hit, " + std::to_string(c.skipped) + " skipped";
      if (ref) v.with_reference = compare_covered(img(*ref), img(out), bg, tol);
      return v;
    };
  };
  return j;
}

}  // namespace lockstep
