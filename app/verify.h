// lockstep verify: the pieces (manifest, generic image verification, report).
//
//   app/manifest.cpp      reads CORPUS/manifest.txt into Cases (a family column;
//                         ray_cast is the default)
//   app/verify_case.cpp   one case of any family, through its output kind: the
//                         reference against its golden, every implementation
//                         against the reference, the analytic judge, the
//                         report's views, differences and judge pictures
//   app/report.cpp        the table on stdout and report.md
//   app/verify.cpp        verify_main: options, the loop over cases
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "app/cli.h"
#include "app/run.h"
#include "core/family.h"

namespace lockstep::cli {

// Reference against its own golden image: the same code on the same input must
// give the same floats; 1e-4 leaves room for a different libm's pow/sqrt.
inline constexpr double kGoldenTolerance = 1e-4;

enum class RefExpect { kAny, kRight, kWrong };

struct Case {
  const Family* family = nullptr;
  std::string name;
  std::string input_path;     // as resolved against the corpus folder
  int line = 0;               // in the manifest
  int width = 0, height = 0;  // 0: the input's own size
  std::vector<std::string> impls;  // to compare with the reference; empty: all of the family
  Tolerance tol;                   // the family's, or the manifest's fail / failpercent
  bool tol_given = false;          // the manifest's line set fail or failpercent (then rows' own agree is not used)
  const Judge* judge = nullptr;    // null: judged against the reference only
  RefExpect ref_expect = RefExpect::kAny;
  std::string ref_reason;  // why the reference is expected to be wrong
  Input input;             // loaded by the family
  Params params;           // the family's settings: the line's name=value fields
  // beside=FILE: a picture of the same scene made elsewhere (another renderer's),
  // shown beside the case's outputs in the report, never judged; "" when none.
  std::string beside;       // resolved against the corpus folder
  std::string beside_name;  // as the manifest gave it, for captions
  int frame_width() const { return width > 0 ? width : input.width; }
  int frame_height() const { return height > 0 ? height : input.height; }
};

struct Row {
  std::string case_name, family, impl;
  bool ran = false;  // ran without throwing
  Agreement err;     // against the reference (the golden for the reference row); samples 0: not compared
  double seconds = 0, speedup = 0;
  uint64_t items = 0;  // the work the run did (FrameStats::items, in its family's unit); 0: not counted
  bool pass = false;
  std::string note;
  std::string view, difference, judged;  // report files (output, difference, judge picture), relative to the report folder
  std::string golden;                    // the reference row only: the golden's picture (report file), "" when none
  // Primitives the run could not draw (FrameStats::dropped): how many, and
  // why ("2 dropped (reason); ..."); 0 and "" when it drew everything.
  uint64_t dropped = 0;
  std::string dropped_why;
};

struct VerifyOptions {
  std::vector<std::string> only;  // --impl: only these besides the reference
  int threads = 0;
  bool regolden = false;
  bool no_report = false;
  std::filesystem::path golden_dir, report_dir;
};

// app/manifest.cpp. Throws InputError naming manifest:line.
std::vector<Case> read_manifest(const std::filesystem::path& corpus_dir);
// Loads every case's input and checks its judge can judge it (InputError otherwise).
void load_inputs(std::vector<Case>& cases);

// app/verify_case.cpp: rows for one case (printed as they come); verdict
// lines of analytic judges are appended to verdicts.
// sessions: the run's (app/run.h RowSessions), kept from case to case.
std::vector<Row> verify_case(const Case& c, const VerifyOptions& o, std::vector<std::string>& verdicts,
                             RowSessions& sessions);

// The file of a case's beside picture in its report folder: kBesideStem and
// the kind's picture extension ("beside.png").
inline constexpr std::string_view kBesideStem = "beside";
inline std::string beside_file(const Case& c) {
  return std::string(kBesideStem) + std::string(c.family->kind->picture_extension);
}

// app/report.cpp
void print_header();
void print_row(const Row& r);
void write_report(const std::filesystem::path& dir, const std::vector<Case>& cases, const std::vector<Row>& rows,
                  const std::vector<std::string>& verdicts, bool all_pass, int threads);
std::string fmt(const char* f, double v);

// app/verify_export.cpp: the rows for CI dashboards (formats there); each file
// written whole or not at all (InputError naming it).
void write_json(const std::filesystem::path& path, size_t cases, const std::vector<Row>& rows);
void write_junit(const std::filesystem::path& path, const std::vector<Row>& rows);
// One row as a lockstep-verify/1 row object (one line); JSON pieces.
std::string row_json(const Row& r);
std::string json_string(const std::string& s);
std::string json_number(double x);  // null when not finite
// text to path.tmp, renamed to path (InputError naming path).
void write_whole(const std::filesystem::path& path, const std::string& text);

// app/report_page.cpp: DIR/index.html, the page people look at (template in
// app/report_page.h), filled from DIR/report.json (schema lockstep-report/1,
// documented there); each case folder gets pixels.js, its pictures (the kind's
// picture_extension) as data: URIs for the page's pixel readout.
std::string report_data(const std::vector<Case>& cases, const std::vector<Row>& rows,
                        const std::vector<std::string>& verdicts, int threads);
// Writes DIR/report.json (data as given), DIR/index.html, and DIR/<case>/pixels.js
// for every case of cases.
void write_page(const std::filesystem::path& dir, const std::string& data,
                const std::vector<Case>& cases);

// app/merge_reports.cpp
int merge_reports_main(Args args);

// app/verify_shard.cpp: splitting the cases over machines.
// CORPUS/costs.txt: 'case seconds' per line ('#' comments), the measured cost of
// a case (all its rows); a case not listed costs the median of those listed (1
// when none is). Throws InputError naming file and line on a malformed line.
std::vector<std::pair<std::string, double>> read_costs(const std::filesystem::path& corpus_dir);
// Shard k of n: cases assigned greedily, costliest first (ties by name), each to
// the shard with the least cost so far (ties: the lowest index) -- the same on
// every machine; returns shard k's cases in manifest order.
std::vector<Case> shard_of(std::vector<Case> cases, const std::vector<std::pair<std::string, double>>& costs,
                           int k, int n);
// GTEST_TOTAL_SHARDS / GTEST_SHARD_INDEX when both are set (UsageError when
// malformed), and GTEST_SHARD_STATUS_FILE touched to say sharding is understood.
void shard_from_environment(int& k, int& n);

}  // namespace lockstep::cli
