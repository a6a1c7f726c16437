// lockstep verify: every corpus case, every implementation, one table.
//
// The cases come from CORPUS_DIR/manifest.txt (app/manifest.cpp), each of one
// family of the registry; every case is verified the same way whatever its
// family (app/verify_image.cpp) and reported (app/report.cpp).
#include <cstdio>

#include "app/verify.h"

namespace lockstep::cli {

namespace fs = std::filesystem;

namespace {

void print_help() {
  std::printf(
      "usage: lockstep verify [CORPUS_DIR] [--report DIR | --no-report] [--impl NAME]...\n"
      "                       [--filter SUBSTR] [--shard K/N] [--threads N] [--regolden] [--junit FILE]\n"
      "                       [--json FILE]\n"
      "\n"
      "Runs every case of CORPUS_DIR/manifest.txt (default: %s), whatever its family:\n"
      "  * runs it with the family's reference and checks that against golden/<case>\n"
      "    (an .exr for images; every sample within %g);\n"
      "  * runs it with every other implementation the case lists and compares each\n"
      "    with the reference (default: the family's tolerance, below), and never a sample\n"
      "    off by more than the family's hard limit or NaN;\n"
      "  * for cases with an analytic judge (ray_cast: 'disk', 'convex'), checks every\n"
      "    implementation, the reference included, against the closed-form answer: the\n"
      "    optimized ones must match it; the reference must do what the manifest expects.\n"
      "Prints one row per case and implementation; writes each output as people look at it\n"
      "(PNGs for images), its difference from the reference (heat maps), report.md and\n"
      "index.html (one page that opens from the file system: the table sortable and\n"
      "filterable, each case's pictures side by side with zoom, A/B flip, wipe and the pixel\n"
      "under the cursor, and charts; its data in report.json, see app/report_page.cpp).\n"
      "\n"
      "families (registry/registry.h):\n",
      LOCKSTEP_CORPUS_DIR, kGoldenTolerance);
  for (const Family& f : registry().families) {
    std::printf("  %-10s %s; impls: %s\n", std::string(f.name).c_str(), f.kind->describe_tolerance(f.tol).c_str(),
                impl_names(f).c_str());
    // Rows held to their own agreement (FamilyImpl::agree).
    for (const FamilyImpl& i : f.impls)
      if (i.agree)
        std::printf("  %-10s   %s: its own, %s\n", "", std::string(i.name).c_str(),
                    f.kind->describe_tolerance(*i.agree).c_str());
  }
  std::printf(
      "\n"
      "  --report DIR     report folder (default ./lockstep-report)\n"
      "  --no-report      write no report\n"
      "  --impl NAME      only these implementations besides the reference (repeat, or a\n"
      "                   comma list; a name of any family)\n"
      "  --filter SUBSTR  only cases whose name (or family) contains SUBSTR\n"
      "  --shard K/N      only shard K of N (K = 0 .. N-1): the cases split into N parts of about\n"
      "                   equal measured cost (CORPUS_DIR/costs.txt), the same split on every\n"
      "                   machine; without it, GoogleTest's GTEST_TOTAL_SHARDS and GTEST_SHARD_INDEX\n"
      "                   (and GTEST_SHARD_STATUS_FILE is touched), as CI runners set them\n"
      "  --threads N      worker threads for the optimized implementations (default: all cores)\n"
      "  --junit FILE     also write the rows as JUnit XML (a suite per family, a testcase per\n"
      "                   case and implementation; CI dashboards read it)\n"
      "  --json FILE      also write the rows as JSON (schema lockstep-verify/1, app/verify_export.cpp)\n"
      "  --regolden       render the golden images (reference only) instead of verifying;\n"
      "                   goldens never come from optimized code (scripts/regolden.sh)\n"
      "\n"
      "Exit codes: 0 every case passes, 1 some fail, 2 bad usage or bad manifest/input.\n");
}

// A name of an implementation of any family.
void check_impl_name(const std::string& n) {
  for (const Family& f : registry().families)
    if (f.find(n)) return;
  throw UsageError("unknown implementation '" + n + "' (known: " + all_impl_names() + ")");
}

}  // namespace

int verify_main(Args args) {
  std::string corpus = LOCKSTEP_CORPUS_DIR, report = "lockstep-report", filter, value, junit, json;
  int shard = 0, shards = 1;
  bool shard_given = false;
  bool corpus_given = false;
  VerifyOptions o;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string_view a = args[i];
    if (a == "--help" || a == "-h") {
      print_help();
      return kExitOk;
    } else if (take_option(args, i, "--report", value)) {
      if (value.empty()) throw UsageError("--report needs a folder");
      report = value;
    } else if (a == "--no-report") {
      o.no_report = true;
    } else if (take_option(args, i, "--impl", value)) {
      for (size_t s = 0, e; s <= value.size(); s = e + 1) {
        e = value.find(',', s);
        if (e == std::string::npos) e = value.size();
        if (e == s) continue;
        o.only.push_back(value.substr(s, e - s));
        check_impl_name(o.only.back());
      }
    } else if (take_option(args, i, "--filter", value)) {
      filter = registry().canonical(value);  // an old family spelling: its family
    } else if (take_option(args, i, "--threads", value)) {
      o.threads = int(parse_long("--threads", value, 1, 4096));
    } else if (take_option(args, i, "--shard", value)) {
      const size_t slash = value.find('/');
      if (slash == std::string::npos) throw UsageError("--shard is K/N (K = 0 .. N-1), got '" + value + "'");
      shards = int(parse_long("--shard's N", value.substr(slash + 1), 1, 100000));
      shard = int(parse_long("--shard's K", value.substr(0, slash), 0, shards - 1));
      shard_given = true;
    } else if (take_option(args, i, "--junit", value)) {
      if (value.empty()) throw UsageError("--junit needs a file");
      junit = value;
    } else if (take_option(args, i, "--json", value)) {
      if (value.empty()) throw UsageError("--json needs a file");
      json = value;
    } else if (a == "--regolden") {
      o.regolden = true;
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
  std::erase_if(cases, [&](const Case& c) {
    return c.name.find(filter) == std::string::npos && std::string(c.family->name).find(filter) == std::string::npos;
  });
  if (cases.empty()) throw UsageError("no case name contains '" + filter + "'");
  if (!shard_given) shard_from_environment(shard, shards);
  if (shards > 1) {
    cases = shard_of(std::move(cases), read_costs(corpus_dir), shard, shards);
    std::fprintf(stderr, "lockstep verify: shard %d of %d (0-based): %zu cases\n", shard, shards, cases.size());
  }
  load_inputs(cases);
  o.golden_dir = corpus_dir / "golden";
  o.report_dir = report;
  if (o.regolden) o.no_report = true;
  std::error_code ec;
  if (!o.no_report) {
    fs::create_directories(o.report_dir, ec);
    if (ec || !fs::is_directory(o.report_dir))
      throw InputError(report, 0, "cannot create the report folder" + (ec ? ": " + ec.message() : ""));
  }
  if (o.regolden) {
    fs::create_directories(o.golden_dir, ec);
    if (ec) throw InputError(o.golden_dir.string(), 0, "cannot create the golden folder: " + ec.message());
  }

  std::vector<Row> rows;
  std::vector<std::string> verdicts;
  RowSessions sessions;  // the embree rows' sessions and their one device, for the whole run
  if (!o.regolden) print_header();
  for (size_t ci = 0; ci < cases.size(); ++ci) {
    const Case& c = cases[ci];
    const std::string size =
        c.family->sized ? " (" + std::to_string(c.frame_width()) + "x" + std::to_string(c.frame_height()) + ")" : "";
    std::fprintf(stderr, "lockstep verify: [%zu/%zu] %s %s%s\n", ci + 1, cases.size(),
                 std::string(c.family->name).c_str(), c.name.c_str(), size.c_str());
    for (Row& r : verify_case(c, o, verdicts, sessions)) rows.push_back(std::move(r));
  }

  if (o.regolden) {
    std::fprintf(stderr, "lockstep verify: %zu golden images written by the reference to %s\n", cases.size(),
                 o.golden_dir.string().c_str());
    return kExitOk;
  }
  long failed = 0;
  for (const Row& r : rows) failed += r.pass ? 0 : 1;
  const bool all_pass = failed == 0;
  std::printf("%zu cases, %zu rows: %s\n", cases.size(), rows.size(),
              all_pass ? "all PASS" : (std::to_string(failed) + " FAIL").c_str());
  if (!json.empty()) write_json(json, cases.size(), rows);
  if (!junit.empty()) write_junit(junit, rows);
  if (!o.no_report) {
    write_report(o.report_dir, cases, rows, verdicts, all_pass, o.threads);
    write_page(o.report_dir, report_data(cases, rows, verdicts, o.threads), cases);
    std::fprintf(stderr, "lockstep verify: report in %s and %s\n", (o.report_dir / "index.html").string().c_str(),
                 (o.report_dir / "report.md").string().c_str());
  }
  return all_pass ? kExitOk : kExitFail;
}

}  // namespace lockstep::cli
