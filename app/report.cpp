// lockstep verify: the table on stdout and report.md.
#include <algorithm>
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
    const bool have = r.err.samples > 0;
    std::printf("%-22s %-10s %10s %9s %8s %9s %8s  %-6s %s\n", r.case_name.c_str(), r.impl.c_str(),
                have ? fmt("%.3g", r.err.worst).c_str() : "-",
                have ? fmt("%.3f", r.err.percent_over()).c_str() : "-",
                have ? fmt("%.1f", r.err.score).c_str() : "-", fmt("%.3f", r.seconds).c_str(),
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
  md << "* Reference rows: the reference against its golden `golden/<case>` (written by the reference only), "
        "every sample within "
     << kGoldenTolerance << ".\n"
     << "* Other rows: the implementation against the reference at the case's thresholds "
        "(*% over*: share of samples whose error exceeds the case's `fail` threshold; *score*: the output "
        "kind's figure of merit).\n"
     << "* Analytic judges (the family's, e.g. ray_cast's `disk` and `convex`: registry/ray_cast_judges.h): a "
        "closed-form answer computed without any implementation; there the optimized implementations must match "
        "it (and the reference where both show something), and the reference must do what the manifest expects "
        "(ref=right / ref=wrong).\n";
  // What each kind's files show (images: heat maps, judge masks), once per kind present.
  std::vector<const OutputKind*> kinds;
  for (const Case& c : cases)
    if (std::find(kinds.begin(), kinds.end(), c.family->kind) == kinds.end()) kinds.push_back(c.family->kind);
  for (const OutputKind* k : kinds) md << "* " << k->name << " outputs: " << k->legend << "\n";
  md << "\n";
  md << "| case | impl | max err | % over | score | time s | speedup | result | note |\n"
     << "|---|---|---:|---:|---:|---:|---:|---|---|\n";
  for (const Row& r : rows) {
    const bool have = r.ran && r.err.samples > 0;
    md << "| " << r.case_name << " | " << r.impl << " | " << (have ? fmt("%.3g", r.err.worst) : "-") << " | "
       << (have ? fmt("%.3f", r.err.percent_over()) : "-") << " | " << (have ? fmt("%.1f", r.err.score) : "-")
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
       << ", fail " << fmt("%.6g", c.tol.abs) << " on more than " << fmt("%.4g", 100.0 * (1.0 - c.tol.fraction))
       << "% of the " << c.family->kind->samples << ", judge " << (c.judge ? std::string(c.judge->name) : std::string("reference")) << ".\n\n";
    const bool masks = c.judge != nullptr;
    md << "| impl | output | difference" << (masks ? " | judge" : "") << " |\n|---|---|---"
       << (masks ? "|---" : "") << "|\n";
    for (const Row& r : rows) {
      if (r.case_name != c.name) continue;
      auto img = [](const std::string& p) { return p.empty() ? std::string("-") : "![](" + p + ")"; };
      md << "| " << r.impl << " | " << img(r.view) << " | " << img(r.difference);
      if (masks) md << " | " << img(r.judged);
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
