// lockstep verify: every corpus case, every implementation, one table.
//
// For each case of CORPUS_DIR/manifest.txt (format: the comment at the top of
// corpus/manifest.txt):
//   1. render with the reference and compare it with its golden image
//      golden/<case>.exr (written by the reference only, `--regolden`): every
//      pixel within kGoldenTolerance = 1e-4 per channel;
//   2. render with every other implementation the case lists and compare it
//      with the reference at the case's thresholds (default: the pair table's,
//      1/255 on >= 99.9% of the pixels);
//   3. for cases with an analytic judge (app/judge.h), check every
//      implementation, the reference included, against the closed form. There
//      the optimized implementations must match the judge; the reference is
//      expected to be wrong when the manifest says so (textbook cancellation),
//      which is reported, not failed.
// The report folder gets every image as PNG, a heat map per case and
// implementation, and report.md tabulating it all.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/cli.h"
#include "app/judge.h"
#include "core/image.h"
#include "core/metrics.h"
#include "core/nff.h"

namespace lockstep::cli {

namespace {

namespace fs = std::filesystem;

// Reference against its own golden image: the same code on the same input must
// give the same floats; 1e-4 leaves room for a different libm's pow/sqrt.
constexpr double kGoldenTolerance = 1e-4;
// Goldens are stored as OpenEXR pxr24: floats rounded to 24 bits (relative error
// <= 2^-16, so within 1e-4 for values up to 6), a quarter of zip's size.
// --regolden checks that what it wrote reads back within kGoldenTolerance / 4.
constexpr const char* kGoldenCompression = "pxr24";

enum class RefExpect { kAny, kRight, kWrong };

struct Case {
  std::string name;
  std::string scene_path;  // as resolved against the corpus folder
  int line = 0;            // in the manifest
  int width = 0, height = 0;  // 0: the scene's resolution
  std::vector<std::string> impls;  // to compare with the reference; empty: all in the table
  CompareOptions cmp;
  JudgeKind judge = JudgeKind::kReference;
  RefExpect ref_expect = RefExpect::kAny;
  std::string ref_reason;  // why the reference is expected to be wrong
  Scene scene;
};

struct Row {
  std::string case_name, impl;
  bool ran = false;        // rendered without throwing
  ImageError err;          // against the reference (the golden image for the reference row)
  double seconds = 0, speedup = 0;
  bool pass = false;
  std::string note;
  std::string image, heat, mask;  // report files, relative to the report folder
};

const char* judge_name(JudgeKind k) {
  return k == JudgeKind::kDisk ? "disk" : k == JudgeKind::kConvex ? "convex" : "reference";
}

void print_help() {
  const Tolerance& t = casters().tol;
  std::printf(
      "usage: lockstep verify [CORPUS_DIR] [--report DIR | --no-report] [--impl NAME]...\n"
      "                       [--filter SUBSTR] [--threads N] [--regolden]\n"
      "\n"
      "Runs every case of CORPUS_DIR/manifest.txt (default: %s):\n"
      "  * renders it with the reference and checks that against golden/<case>.exr\n"
      "    (every pixel within %g per channel);\n"
      "  * renders it with every other implementation the case lists and compares each\n"
      "    with the reference (default: %.6g per channel on >= %.4g%% of the pixels);\n"
      "  * for cases with an analytic judge ('disk', 'convex'), checks every implementation,\n"
      "    the reference included, against the closed-form answer: the optimized ones must\n"
      "    match it; a reference the manifest expects to be wrong is reported, not failed.\n"
      "Prints one row per case and implementation; writes PNGs, heat maps and report.md.\n"
      "\n"
      "  --report DIR     report folder (default ./lockstep-report)\n"
      "  --no-report      write no report\n"
      "  --impl NAME      only these implementations besides the reference (repeat, or a\n"
      "                   comma list); known: %s\n"
      "  --filter SUBSTR  only cases whose name contains SUBSTR\n"
      "  --threads N      worker threads for the optimized implementations (default: all cores)\n"
      "  --regolden       render the golden images (reference only) instead of verifying;\n"
      "                   goldens never come from optimized code (scripts/regolden.sh)\n"
      "\n"
      "Exit codes: 0 every case passes, 1 some fail, 2 bad usage or bad manifest/scene.\n",
      LOCKSTEP_CORPUS_DIR, kGoldenTolerance, t.color_abs, 100.0 * t.pixel_fraction, impl_names().c_str());
}

std::vector<std::string> split(std::string_view s, char sep) {
  std::vector<std::string> out;
  size_t i = 0;
  while (i <= s.size()) {
    size_t j = s.find(sep, i);
    if (j == std::string_view::npos) j = s.size();
    if (j > i) out.emplace_back(s.substr(i, j - i));
    i = j + 1;
  }
  return out;
}

// ---------------------------------------------------------------- manifest

std::vector<Case> read_manifest(const fs::path& dir) {
  const std::string path = (dir / "manifest.txt").string();
  std::ifstream f(path);
  if (!f) throw InputError(path, 0, fs::is_directory(dir) ? "cannot open the manifest" : "no such corpus folder");
  std::vector<Case> cases;
  std::string text;
  int line_no = 0;
  while (std::getline(f, text)) {
    ++line_no;
    if (const size_t hash = text.find('#'); hash != std::string::npos) text.resize(hash);
    std::istringstream words(text);
    std::vector<std::string> w;
    for (std::string x; words >> x;) w.push_back(x);
    if (w.empty()) continue;
    auto fail = [&](const std::string& what) -> void { throw InputError(path, line_no, what); };
    if (w.size() < 2 || w.size() > 8)
      fail("expected 'case scene [size [impls [fail [failpercent [judge [ref]]]]]]', got " +
           std::to_string(w.size()) + " fields");
    Case c;
    c.line = line_no;
    c.name = w[0];
    for (char ch : c.name)
      if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_' || ch == '.'))
        fail("case name '" + c.name + "' may only use letters, digits, '-', '_' and '.'");
    for (const Case& other : cases)
      if (other.name == c.name) fail("case '" + c.name + "' given twice (first on line " + std::to_string(other.line) + ")");
    c.scene_path = (dir / w[1]).string();
    c.cmp.fail_threshold = casters().tol.color_abs;
    c.cmp.fail_percent = 100.0 * (1.0 - casters().tol.pixel_fraction);
    auto given = [&](size_t i) { return w.size() > i && w[i] != "-"; };
    try {
      if (given(2)) parse_size(w[2], c.width, c.height);
      if (given(3)) {
        c.impls = split(w[3], ',');
        for (const std::string& n : c.impls) {
          (void)find_impl(n);
          if (n == reference_impl().name) fail("impls: the reference is always run; list the others");
        }
      }
      if (given(4)) c.cmp.fail_threshold = parse_number("fail", w[4], 0, 1e30);
      if (given(5)) c.cmp.fail_percent = parse_number("failpercent", w[5], 0, 100);
    } catch (const UsageError& e) {
      fail(e.what());
    }
    if (given(6)) {
      if (w[6] == "reference") c.judge = JudgeKind::kReference;
      else if (w[6] == "disk") c.judge = JudgeKind::kDisk;
      else if (w[6] == "convex") c.judge = JudgeKind::kConvex;
      else fail("judge must be 'reference', 'disk' or 'convex', got '" + w[6] + "'");
    }
    if (given(7)) {
      if (c.judge == JudgeKind::kReference) fail("a 'ref=' expectation needs an analytic judge");
      const std::string& r = w[7];
      if (r == "ref=right") {
        c.ref_expect = RefExpect::kRight;
      } else if (r.starts_with("ref=wrong")) {
        c.ref_expect = RefExpect::kWrong;
        if (r.size() > 9) {
          if (r[9] != ':') fail("expected 'ref=right', 'ref=wrong' or 'ref=wrong:REASON', got '" + r + "'");
          c.ref_reason = r.substr(10);
        }
      } else {
        fail("expected 'ref=right', 'ref=wrong' or 'ref=wrong:REASON', got '" + r + "'");
      }
    }
    cases.push_back(std::move(c));
  }
  if (f.bad()) throw InputError(path, 0, "cannot read the manifest");
  if (cases.empty()) throw InputError(path, 0, "no cases in the manifest");
  return cases;
}

// ---------------------------------------------------------------- rendering

struct Rendered {
  bool ok = false;
  Image image;
  double seconds = 0;
  std::string chosen, error;
};

Rendered render_with(const Impl<CasterFns>& impl, const Case& c, int threads) {
  RenderOptions opts;
  opts.width = c.width > 0 ? c.width : c.scene.view.xres;
  opts.height = c.height > 0 ? c.height : c.scene.view.yres;
  opts.threads = threads;
  Rendered r;
  RenderStats stats;
  const auto start = std::chrono::steady_clock::now();
  try {
    r.image = impl.fn.render(c.scene, opts, &stats);
    r.ok = r.image.width == opts.width && r.image.height == opts.height;
    if (!r.ok) r.error = "returned an image of the wrong size";
  } catch (const std::exception& e) {
    r.error = std::string("threw: ") + e.what();
  }
  r.seconds = seconds_since(start);
  r.chosen = stats.chosen;
  return r;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string judge_summary(const JudgeResult& j) {
  return std::to_string(j.wrong()) + " px differ from analytic (" + std::to_string(j.missed) + " missing, " +
         std::to_string(j.spurious) + " spurious; " + std::to_string(j.expected_hit) + " must hit, " +
         std::to_string(j.skipped) + " on the boundary skipped)";
}

// ---------------------------------------------------------------- output

void print_header() {
  std::printf("%-22s %-10s %10s %9s %8s %9s %8s  %-6s %s\n", "case", "impl", "max err", "% over", "PSNR",
              "time s", "speedup", "result", "note");
  std::fflush(stdout);
}

void print_row(const Row& r) {
  if (!r.ran) {
    std::printf("%-22s %-10s %10s %9s %8s %9s %8s  %-6s %s\n", r.case_name.c_str(), r.impl.c_str(), "-", "-",
                "-", fmt("%.3f", r.seconds).c_str(), "-", r.pass ? "PASS" : "FAIL", r.note.c_str());
  } else {
    const bool have = r.err.pixels > 0;
    std::printf("%-22s %-10s %10s %9s %8s %9s %8s  %-6s %s\n", r.case_name.c_str(), r.impl.c_str(),
                have ? fmt("%.3g", r.err.max_error).c_str() : "-",
                have ? fmt("%.3f", r.err.percent_failed()).c_str() : "-",
                have ? fmt("%.1f", r.err.psnr).c_str() : "-", fmt("%.3f", r.seconds).c_str(),
                fmt("%.1fx", r.speedup).c_str(), r.pass ? "PASS" : "FAIL", r.note.c_str());
  }
  std::fflush(stdout);
}

std::string md_escape(std::string s) {
  std::string out;
  for (char ch : s) {
    if (ch == '|') out += "\\|";
    else out += ch;
  }
  return out;
}

void write_report(const fs::path& dir, const std::vector<Case>& cases, const std::vector<Row>& rows,
                  const std::vector<std::string>& verdicts, bool all_pass, int threads) {
  std::ofstream md(dir / "report.md.tmp");
  md << "# lockstep verify\n\n";
  md << "lockstep " << LOCKSTEP_VERSION << ", " << cases.size() << " cases, "
     << (threads > 0 ? std::to_string(threads) : std::to_string(std::thread::hardware_concurrency()))
     << " threads for the optimized implementations (the reference is single-threaded). "
     << "Result: **" << (all_pass ? "PASS" : "FAIL") << "**.\n\n";
  md << "* Reference rows: the reference against its golden image `golden/<case>.exr`, every pixel within "
     << kGoldenTolerance << " per channel.\n"
     << "* Other rows: the implementation against the reference at the case's thresholds "
        "(*% over*: share of pixels whose largest channel error exceeds the case's `fail` threshold).\n"
     << "* Analytic judges (`disk`, `convex`, app/judge.h): a closed-form hit/miss per pixel centre; "
        "there the optimized implementations must match it, and the reference is reported against it.\n"
     << "* Heat maps: black = identical, blue to red = 0 to the case's threshold (red: at or over it); "
        "judge masks: green hit as it must, grey background as it must, red a missing hit, magenta a "
        "spurious hit, blue on the boundary (skipped).\n\n";
  md << "| case | impl | max err | % over | PSNR dB | time s | speedup | result | note |\n"
     << "|---|---|---:|---:|---:|---:|---:|---|---|\n";
  for (const Row& r : rows) {
    const bool have = r.ran && r.err.pixels > 0;
    md << "| " << r.case_name << " | " << r.impl << " | " << (have ? fmt("%.3g", r.err.max_error) : "-") << " | "
       << (have ? fmt("%.3f", r.err.percent_failed()) : "-") << " | " << (have ? fmt("%.1f", r.err.psnr) : "-")
       << " | " << fmt("%.3f", r.seconds) << " | " << (r.ran ? fmt("%.1fx", r.speedup) : "-") << " | "
       << (r.pass ? "PASS" : "**FAIL**") << " | " << md_escape(r.note) << " |\n";
  }
  if (!verdicts.empty()) {
    md << "\n## Analytic verdicts\n\n";
    for (const std::string& v : verdicts) md << "* " << md_escape(v) << "\n";
  }
  for (const Case& c : cases) {
    md << "\n## " << c.name << "\n\n";
    md << "`" << fs::path(c.scene_path).filename().string() << "`, "
       << (c.width > 0 ? c.width : c.scene.view.xres) << "x" << (c.height > 0 ? c.height : c.scene.view.yres)
       << ", fail " << fmt("%.6g", c.cmp.fail_threshold) << " on more than " << fmt("%.4g", c.cmp.fail_percent)
       << "% of the pixels, judge " << judge_name(c.judge) << ".\n\n";
    const bool masks = c.judge != JudgeKind::kReference;
    md << "| impl | image | heat map" << (masks ? " | judge mask" : "") << " |\n|---|---|---"
       << (masks ? "|---" : "") << "|\n";
    for (const Row& r : rows) {
      if (r.case_name != c.name) continue;
      auto img = [](const std::string& p) { return p.empty() ? std::string("-") : "![](" + p + ")"; };
      md << "| " << r.impl << " | " << img(r.image) << " | " << img(r.heat);
      if (masks) md << " | " << img(r.mask);
      md << " |\n";
    }
  }
  md.close();
  std::error_code ec;
  if (!md) throw InputError((dir / "report.md").string(), 0, "cannot write the report");
  fs::rename(dir / "report.md.tmp", dir / "report.md", ec);
  if (ec) throw InputError((dir / "report.md").string(), 0, "cannot write the report: " + ec.message());
}

}  // namespace

int verify_main(Args args) {
  std::string corpus = LOCKSTEP_CORPUS_DIR, report = "lockstep-report", filter, value;
  bool corpus_given = false, no_report = false, regolden = false;
  std::vector<std::string> only;
  int threads = 0;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string_view a = args[i];
    if (a == "--help" || a == "-h") {
      print_help();
      return kExitOk;
    } else if (take_option(args, i, "--report", value)) {
      if (value.empty()) throw UsageError("--report needs a folder");
      report = value;
    } else if (a == "--no-report") {
      no_report = true;
    } else if (take_option(args, i, "--impl", value)) {
      for (const std::string& n : split(value, ',')) {
        (void)find_impl(n);
        only.push_back(n);
      }
    } else if (take_option(args, i, "--filter", value)) {
      filter = value;
    } else if (take_option(args, i, "--threads", value)) {
      threads = int(parse_long("--threads", value, 1, 4096));
    } else if (a == "--regolden") {
      regolden = true;
    } else if (is_option(a)) {
      unknown_option(a);
    } else if (!corpus_given) {
      corpus = std::string(a);
      corpus_given = true;
    } else {
      throw UsageError("unexpected argument '" + std::string(a) + "' (one corpus folder)");
    }
  }

  // All input is checked before anything is rendered or written.
  const fs::path corpus_dir(corpus);
  std::vector<Case> cases = read_manifest(corpus_dir);
  std::erase_if(cases, [&](const Case& c) { return c.name.find(filter) == std::string::npos; });
  if (cases.empty()) throw UsageError("no case name contains '" + filter + "'");
  for (Case& c : cases) {
    c.scene = read_nff(c.scene_path);
    if (c.judge != JudgeKind::kReference) check_judgeable(c.scene, c.judge);
  }
  const fs::path golden_dir = corpus_dir / "golden";
  const fs::path report_dir(report);
  if (regolden) no_report = true;
  std::error_code ec;
  if (!no_report) {
    fs::create_directories(report_dir, ec);
    if (ec || !fs::is_directory(report_dir))
      throw InputError(report, 0, "cannot create the report folder" + (ec ? ": " + ec.message() : ""));
  }
  if (regolden) {
    fs::create_directories(golden_dir, ec);
    if (ec) throw InputError(golden_dir.string(), 0, "cannot create the golden folder: " + ec.message());
  }

  const Impl<CasterFns>& ref = reference_impl();
  std::vector<Row> rows;
  std::vector<std::string> verdicts;
  bool all_pass = true;
  if (!regolden) print_header();
  for (size_t ci = 0; ci < cases.size(); ++ci) {
    const Case& c = cases[ci];
    const int w = c.width > 0 ? c.width : c.scene.view.xres, h = c.height > 0 ? c.height : c.scene.view.yres;
    std::fprintf(stderr, "lockstep verify: [%zu/%zu] %s (%dx%d)\n", ci + 1, cases.size(), c.name.c_str(), w, h);
    const fs::path case_dir = report_dir / c.name;
    if (!no_report) {
      fs::create_directories(case_dir, ec);
      if (ec) throw InputError(case_dir.string(), 0, "cannot create the report folder: " + ec.message());
    }
    auto save = [&](const Image& img, const std::string& file) -> std::string {
      if (no_report) return {};
      write_image(img, (case_dir / file).string());
      return c.name + "/" + file;
    };
    const std::string golden_path = (golden_dir / (c.name + ".exr")).string();

    // 1. The reference, against its golden image (or making it).
    const Rendered r_ref = render_with(ref, c, threads);
    Row rr;
    rr.case_name = c.name;
    rr.impl = std::string(ref.name);
    rr.ran = r_ref.ok;
    rr.seconds = r_ref.seconds;
    rr.speedup = 1.0;
    if (!r_ref.ok) {
      rr.note = r_ref.error;
    } else if (regolden) {
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
      continue;
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
      if (rr.err.same_size && !no_report) {
        Image heat = error_heatmap(golden, r_ref.image, kGoldenTolerance);
        rr.heat = save(heat, "reference-heat.png");
      }
    }
    if (r_ref.ok) rr.image = save(r_ref.image, "reference.png");

    // The analytic judge, if any, for every implementation.
    std::vector<Cover> cover;
    std::string verdict;
    if (c.judge != JudgeKind::kReference) {
      cover = analytic_coverage(c.scene, c.judge, w, h);
      verdict = c.name + ": ";
      if (r_ref.ok) {
        Image mask;
        const JudgeResult j = judge_image(r_ref.image, cover, c.scene.background, &mask);
        rr.mask = save(mask, "reference-judge.png");
        std::string what;
        if (j.wrong() > 0) {
          what = "reference WRONG" + (c.ref_reason.empty() ? "" : " (" + c.ref_reason + ")") + ": " + judge_summary(j);
          if (c.ref_expect == RefExpect::kRight) what += " UNEXPECTED: the manifest says ref=right";
          else if (c.ref_expect == RefExpect::kWrong) what += ", as expected";
        } else {
          what = "reference right: matches analytic (" + std::to_string(j.expected_hit) + " must hit, " +
                 std::to_string(j.skipped) + " skipped)";
          if (c.ref_expect == RefExpect::kWrong)
            what += " UNEXPECTED: the manifest says ref=wrong" + (c.ref_reason.empty() ? "" : ":" + c.ref_reason);
        }
        rr.note += "; " + what;
        verdict += what;
      } else {
        verdict += "reference did not render";
      }
    }
    all_pass = all_pass && rr.pass;
    print_row(rr);
    rows.push_back(rr);

    // 2. Every other implementation, against the reference (and the judge).
    for (const auto& impl : casters().impls) {
      const std::string name(impl.name);
      if (&impl == &ref) continue;
      if (!c.impls.empty() && std::find(c.impls.begin(), c.impls.end(), name) == c.impls.end()) continue;
      if (!only.empty() && std::find(only.begin(), only.end(), name) == only.end()) continue;
      const Rendered r = render_with(impl, c, threads);
      Row row;
      row.case_name = c.name;
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
          else if (!row.err.pass) row.note = "differs from reference: " + std::to_string(row.err.pixels_failed) + " px over " + fmt("%.4g", c.cmp.fail_threshold);
        } else {
          Image mask;
          const JudgeResult j = judge_image(r.image, cover, c.scene.background, &mask);
          row.mask = save(mask, name + "-judge.png");
          row.pass = j.wrong() == 0;
          row.note = row.pass ? "analytic: right (" + std::to_string(j.expected_hit) + " must hit, " +
                                    std::to_string(j.skipped) + " skipped)"
                              : "analytic: WRONG, " + judge_summary(j);
          if (r_ref.ok) row.note += "; vs reference " + std::to_string(row.err.pixels_failed) + " px over";
          verdict += "; " + name + (row.pass ? " right" : " WRONG (" + std::to_string(j.wrong()) + " px)");
        }
      }
      if (!r.chosen.empty()) row.note += (row.note.empty() ? "" : "; ") + std::string("chose ") + r.chosen;
      all_pass = all_pass && row.pass;
      print_row(row);
      rows.push_back(row);
    }
    if (!cover.empty()) {
      std::printf("  => %s\n", verdict.c_str());
      verdicts.push_back(verdict);
    }
  }

  if (regolden) {
    std::fprintf(stderr, "lockstep verify: %zu golden images written by the reference to %s\n", cases.size(),
                 golden_dir.string().c_str());
    return kExitOk;
  }
  long failed = 0;
  for (const Row& r : rows) failed += r.pass ? 0 : 1;
  std::printf("%zu cases, %zu rows: %s\n", cases.size(), rows.size(),
              all_pass ? "all PASS" : (std::to_string(failed) + " FAIL").c_str());
  if (!no_report) {
    write_report(report_dir, cases, rows, verdicts, all_pass, threads);
    std::fprintf(stderr, "lockstep verify: report in %s\n", (report_dir / "report.md").string().c_str());
  }
  return all_pass ? kExitOk : kExitFail;
}

}  // namespace lockstep::cli
