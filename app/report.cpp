// lockstep verify: the table on stdout and report.md.
#include <cstdio>
#include <fstream>
#include <thread>

#include "app/verify.h"

namespace lockstep::cli {

namespace fs = std::filesystem;

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

namespace {

std::string md_escape(std::string s) {
  std::string out;
  for (char ch : s) {
    if (ch == '|') out += "\\|";
    else out += ch;
  }
  return out;
}

}  // namespace

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
     << "* Analytic judges (the family's, e.g. ray_cast's `disk` and `convex`: pairs/ray_cast_judges.h): a closed-form hit/miss per pixel centre; "
        "there the optimized implementations must match it (and the reference's colour where both cover a pixel), "
        "and the reference must do what the manifest expects (ref=right / ref=wrong).\n"
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
    md << c.family->name << ", `" << fs::path(c.input_path).filename().string() << "`, " << c.frame_width() << "x"
       << c.frame_height()
       << ", fail " << fmt("%.6g", c.cmp.fail_threshold) << " on more than " << fmt("%.4g", c.cmp.fail_percent)
       << "% of the pixels, judge " << (c.judge ? std::string(c.judge->name) : std::string("reference")) << ".\n\n";
    const bool masks = c.judge != nullptr;
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

}  // namespace lockstep::cli
