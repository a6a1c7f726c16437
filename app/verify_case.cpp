// lockstep verify: one case of any image family.
//
//   1. the reference against its golden image golden/<case>.exr (written by the
//      reference only, --regolden): every pixel within kGoldenTolerance;
//   2. every other implementation the case lists against the reference at the
//      case's thresholds (default: the family's tolerance), and never a pixel
//      off by more than the family's hard limit or NaN, whatever the budget;
//   3. with an analytic judge (the family's, e.g. ray_cast's disk and convex),
//      every implementation, the reference included, against the closed form:
//      the optimized ones must match it; the reference must do what the
//      manifest expects (ref=right / ref=wrong), and a run where it does not
//      fails. On the pixels both cover, colours are compared with the
//      reference too.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/run.h"
#include "app/verify.h"

namespace lockstep::cli {

namespace fs = std::filesystem;

namespace {

struct JudgeResult {
  long expected_hit = 0;   // pixels that must be covered
  long expected_miss = 0;  // pixels that must be background
  long skipped = 0;        // on the boundary
  long missed = 0;         // must be covered, shows background (a hole, a leak)
  long spurious = 0;       // must be background, shows something
  long wrong() const { return missed + spurious; }
};

bool is_background(const float* p, const Vec3& bg) {
  return p[0] == float(bg.x) && p[1] == float(bg.y) && p[2] == float(bg.z);
}

// Checks img against coverage; mask becomes a picture of it: green covered as
// it must, dark grey background as it must, red a missing hit, magenta a
// spurious hit, blue skipped.
JudgeResult judge_image(const Image& img, const std::vector<Cover>& cover, const Vec3& bg, Image* mask) {
  JudgeResult r;
  if (mask) *mask = Image(img.width, img.height);
  for (int j = 0; j < img.height; ++j)
    for (int i = 0; i < img.width; ++i) {
      const bool bgp = is_background(img.pixel(i, j), bg);
      Vec3 colour;
      switch (cover[size_t(j) * size_t(img.width) + size_t(i)]) {
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
      if (mask) mask->set(i, j, colour);
    }
  return r;
}

std::string judge_summary(const JudgeResult& j) {
  return std::to_string(j.wrong()) + " px differ from analytic (" + std::to_string(j.missed) + " missing, " +
         std::to_string(j.spurious) + " spurious; " + std::to_string(j.expected_hit) + " must hit, " +
         std::to_string(j.skipped) + " on the boundary skipped)";
}

// Colour agreement on the pixels both images cover (neither shows the
// background): how many there are and how many exceed the case's threshold.
struct BothCovered {
  long pixels = 0, over = 0;
  double max_error = 0;
};
BothCovered compare_covered(const Image& a, const Image& b, const Vec3& bg, double threshold) {
  BothCovered r;
  for (int j = 0; j < a.height; ++j)
    for (int i = 0; i < a.width; ++i) {
      const float *p = a.pixel(i, j), *q = b.pixel(i, j);
      if (is_background(p, bg) || is_background(q, bg)) continue;
      ++r.pixels;
      double e = 0;
      for (int k = 0; k < 4; ++k) {
        const double d = std::abs(double(p[k]) - double(q[k]));
        e = std::isnan(d) ? kInfinity : std::max(e, d);
      }
      r.max_error = std::max(r.max_error, e);
      r.over += e > threshold;
    }
  return r;
}

}  // namespace

std::vector<Row> verify_case(const Case& c, const VerifyOptions& o, std::vector<std::string>& verdicts) {
  const ImageFamily& fam = *c.family;
  const ImageImpl& ref = fam.reference();
  const int w = c.frame_width(), h = c.frame_height();
  FrameOptions opts;
  opts.width = w;
  opts.height = h;
  opts.threads = o.threads;
  opts.params = c.params;
  std::vector<Row> rows;
  const fs::path case_dir = o.report_dir / c.name;
  std::error_code ec;
  if (!o.no_report) {
    fs::create_directories(case_dir, ec);
    if (ec) throw InputError(case_dir.string(), 0, "cannot create the report folder: " + ec.message());
  }
  auto save = [&](const Image& img, const std::string& file) -> std::string {
    if (o.no_report) return {};
    write_image(img, (case_dir / file).string());
    return c.name + "/" + file;
  };
  const std::string golden_path = (o.golden_dir / (c.name + ".exr")).string();

  // 1. The reference, against its golden image (or making it).
  const Run r_ref = run_frame(fam, ref, c.input, opts, true);
  Row rr;
  rr.case_name = c.name;
  rr.family = std::string(fam.name);
  rr.impl = std::string(ref.name);
  rr.ran = r_ref.ok;
  rr.seconds = r_ref.seconds;
  rr.speedup = 1.0;
  if (!r_ref.ok) {
    rr.note = r_ref.error;
  } else if (o.regolden) {
    write_image(r_ref.image, golden_path, kGoldenCompression);
    CompareOptions g;
    g.fail_threshold = kGoldenTolerance / 4;
    g.fail_percent = 0;
    if (!compare_images(r_ref.image, read_image(golden_path), g).pass)
      throw InputError(golden_path, 0, "the golden image does not read back within " +
                                           fmt("%g", kGoldenTolerance / 4) + " (values too large for pxr24?)");
    rr.pass = true;
    rr.note = "golden written: " + golden_path;
    std::printf("%-22s %dx%d  %.3f s  -> %s\n", c.name.c_str(), w, h, r_ref.seconds, golden_path.c_str());
    rows.push_back(rr);
    return rows;
  } else if (!fs::exists(golden_path)) {
    rr.note = "no golden image " + golden_path + " (make it with scripts/regolden.sh)";
  } else {
    const Image golden = read_image(golden_path);
    CompareOptions g;
    g.fail_threshold = kGoldenTolerance;
    g.warn_threshold = kGoldenTolerance;
    g.fail_percent = 0;
    rr.err = compare_images(golden, r_ref.image, g);
    rr.pass = rr.err.pass;
    rr.note = !rr.err.same_size ? "golden image has another size"
              : rr.pass         ? "= golden (within " + fmt("%g", kGoldenTolerance) + ")"
                                : "differs from golden (tolerance " + fmt("%g", kGoldenTolerance) + ")";
    if (rr.err.same_size) rr.heat = save(error_heatmap(golden, r_ref.image, kGoldenTolerance), "reference-heat.png");
  }
  if (r_ref.ok) rr.image = save(r_ref.image, "reference.png");

  // The analytic judge, if any: the reference must do what the manifest expects.
  std::vector<Cover> cover;
  std::string verdict;
  if (c.judge) {
    cover = c.judge->coverage(c.input, w, h);
    verdict = c.name + ": ";
    if (r_ref.ok) {
      Image mask;
      const JudgeResult j = judge_image(r_ref.image, cover, c.input.background, &mask);
      rr.mask = save(mask, "reference-judge.png");
      std::string what;
      bool unexpected = false;
      if (j.wrong() > 0) {
        what = "reference WRONG" + (c.ref_reason.empty() ? "" : " (" + c.ref_reason + ")") + ": " + judge_summary(j);
        unexpected = c.ref_expect == RefExpect::kRight;
        if (unexpected) what += " UNEXPECTED: the manifest says ref=right";
        else if (c.ref_expect == RefExpect::kWrong) what += ", as expected";
      } else {
        what = "reference right: matches analytic (" + std::to_string(j.expected_hit) + " must hit, " +
               std::to_string(j.skipped) + " skipped)";
        unexpected = c.ref_expect == RefExpect::kWrong;
        if (unexpected)
          what += " UNEXPECTED: the manifest says ref=wrong" + (c.ref_reason.empty() ? "" : ":" + c.ref_reason);
      }
      if (unexpected) rr.pass = false;
      rr.note += "; " + what;
      verdict += what;
    } else {
      verdict += "reference did not render";
    }
  }
  print_row(rr);
  rows.push_back(rr);

  // 2. Every other implementation, against the reference (and the judge).
  for (const ImageImpl& impl : fam.impls) {
    const std::string name(impl.name);
    if (&impl == &ref) continue;
    if (!c.impls.empty() && std::find(c.impls.begin(), c.impls.end(), name) == c.impls.end()) continue;
    if (!o.only.empty() && std::find(o.only.begin(), o.only.end(), name) == o.only.end()) continue;
    // A peer that cannot draw this case's settings is not run (no row), and says why.
    if (impl.unsupported) {
      const std::string why = impl.unsupported(opts.params);
      if (!why.empty()) {
        std::printf("%-22s %-10s n/a: %s\n", c.name.c_str(), name.c_str(), why.c_str());
        continue;
      }
    }
    const Run r = run_frame(fam, impl, c.input, opts, true);
    Row row;
    row.case_name = c.name;
    row.family = std::string(fam.name);
    row.impl = name;
    row.ran = r.ok;
    row.seconds = r.seconds;
    row.speedup = r.seconds > 0 ? r_ref.seconds / r.seconds : 0;
    if (!r.ok) {
      row.note = r.error;
      if (!cover.empty()) verdict += "; " + name + " " + r.error;
    } else {
      row.image = save(r.image, name + ".png");
      if (r_ref.ok) {
        row.err = compare_images(r_ref.image, r.image, c.cmp);
        row.heat = save(error_heatmap(r_ref.image, r.image, c.cmp.fail_threshold), name + "-heat.png");
      }
      if (cover.empty()) {
        row.pass = r_ref.ok && row.err.pass;
        if (!r_ref.ok) row.note = "no reference to compare with";
        else if (row.err.over_hard > 0)
          row.note = "differs from reference: " + std::to_string(row.err.over_hard) + " px over the hard limit " +
                     fmt("%.3g", c.cmp.hard_fail) + " (or NaN), which no budget excuses";
        else if (!row.err.pass)
          row.note = "differs from reference: " + std::to_string(row.err.pixels_failed) + " px over " +
                     fmt("%.4g", c.cmp.fail_threshold);
      } else {
        Image mask;
        const JudgeResult j = judge_image(r.image, cover, c.input.background, &mask);
        row.mask = save(mask, name + "-judge.png");
        row.pass = j.wrong() == 0;
        row.note = row.pass ? "analytic: right (" + std::to_string(j.expected_hit) + " must hit, " +
                                  std::to_string(j.skipped) + " skipped)"
                            : "analytic: WRONG, " + judge_summary(j);
        if (r_ref.ok) {
          // Where both cover a pixel, the colour must agree with the reference.
          const BothCovered b = compare_covered(r_ref.image, r.image, c.input.background, c.cmp.fail_threshold);
          const long allowed = long(std::floor(c.cmp.fail_percent / 100.0 * double(b.pixels) + 1e-9));
          const bool colour_ok = b.over <= allowed && b.max_error <= c.cmp.hard_fail;
          // A reference expected wrong (cancellation moves its t, so its shading)
          // is no yardstick for colour: then the comparison is only reported.
          const bool enforced = c.ref_expect != RefExpect::kWrong;
          if (enforced) row.pass = row.pass && colour_ok;
          row.note += "; colour vs reference on " + std::to_string(b.pixels) + " px both cover: " +
                      std::to_string(b.over) + " over " + fmt("%.4g", c.cmp.fail_threshold) +
                      (colour_ok ? "" : enforced ? " (FAIL, " + std::to_string(allowed) + " allowed)"
                                                 : " (not enforced: the reference is expected wrong)");
        }
        verdict += "; " + name + (row.pass ? " right" : " WRONG (" + std::to_string(j.wrong()) + " px)");
      }
    }
    if (!r.stats.chosen.empty()) row.note += (row.note.empty() ? "" : "; ") + std::string("chose ") + r.stats.chosen;
    print_row(row);
    rows.push_back(row);
  }
  if (!cover.empty()) {
    std::printf("  => %s\n", verdict.c_str());
    verdicts.push_back(verdict);
  }
  return rows;
}

}  // namespace lockstep::cli
