// lockstep props/driver: the generic property driver (RapidCheck runs through
// rc_run.h, the seed and case-count rule every property binary shares).
//
// For every family of the registry (registry/registry.h), its provider
// (props/families.cpp) lists the family's properties (props/property.h); each
// becomes one GoogleTest test <Suite>.<name>, e.g.
//   Accuracy.ray_cast__simd, Stability.grazing_rays__ray_sphere__reference,
//   Accuracy.composite__simd, FtbEqualsBtf.composite__oiio,
// plus the family's fixed tests, Mutants.<family>__<bug> (a deliberately broken
// implementation must fail its designated property), Replay.counterexamples
// (every file in corpus/counterexamples, any family), and a failing
// Registry.<family>_has_properties for a registered family without a provider.
//
// Environment:
//   RC_PARAMS="max_success=100 seed=..."   RapidCheck's own (case count, seed, reproduce=...)
//   LOCKSTEP_DEEP=1 (or a count)            deep mode: at least 1000 cases per property
//   LOCKSTEP_RANDOM_SEED=1                  RapidCheck's random seed instead of the per-property one
//   LOCKSTEP_ACCURACY_CSV=file              max/p99 error per (pair, impl, generator) (properties that ask)
//   LOCKSTEP_STABILITY_CSV=file             outcome counts per (check, generator, pair, impl, label)
//   LOCKSTEP_COUNTEREXAMPLE_DIR=dir         where failing cases are written and replayed (default corpus/counterexamples)
//   LOCKSTEP_NO_SAVE=1                      do not write counterexample files
//   LOCKSTEP_SAVE_CLASSIFIED=n              also save up to n textbook failures per (property, label)
//                                           as "expect classified <label>" replay cases
//   LOCKSTEP_MAX_SHRINK_RUNS=n              cap on property runs while shrinking (default 2000)
//   LOCKSTEP_MEASURE=1                      run every case even after a failure (no shrinking), so that
//                                           the statistics cover the whole run; implied by the CSV variables
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <rapidcheck.h>

#include "registry/registry.h"
#include "props/driver/rc_run.h"
#include "props/driver/records.h"
#include "props/driver/tally.h"
#include "props/property.h"

namespace lockstep::props::driver {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- configuration

const char* env(const char* name) {
  const char* v = std::getenv(name);
  return v && *v ? v : nullptr;
}

// Shrinking a case of 20 rays can take minutes; past this many runs after the
// first failure every candidate "passes", so RapidCheck stops at the smallest so far.
long max_shrink_runs() {
  return env("LOCKSTEP_MAX_SHRINK_RUNS") ? std::atol(env("LOCKSTEP_MAX_SHRINK_RUNS")) : 2000;
}

fs::path counterexample_dir() {
  if (const char* d = env("LOCKSTEP_COUNTEREXAMPLE_DIR")) return d;
  return LOCKSTEP_COUNTEREXAMPLE_DIR;
}

// ---------------------------------------------------------------- one property

struct RunOptions {
  bool report = true;  // summary lines, table, CSV, counterexample files
  long max_shrink_runs = 2000;
};

struct RunResult {
  bool passed = true;
  long first_failing_case = 0;  // 1-based, 0 = none
  std::string message;          // RapidCheck's result and the last failure
};

RunResult run_property(const Property& prop, const RunOptions& opt) {
  const std::string id = prop.id();
  // The seed fixed per property (a hash of its id) unless RC_PARAMS gives one,
  // LOCKSTEP_RANDOM_SEED=1 asks for RapidCheck's random seed, or deep mode is
  // on: `ctest` (and CI) run the same cases every time, and deep mode explores
  // new ones (rc_run.h).
  const rc_run::Params p = rc_run::params(id);
  const bool save_failures = opt.report && !env("LOCKSTEP_NO_SAVE");
  const long save_classified =
      opt.report && prop.save_classified && env("LOCKSTEP_SAVE_CLASSIFIED") ? std::atol(env("LOCKSTEP_SAVE_CLASSIFIED"))
                                                                            : 0;
  std::map<std::string, long> classified_saved;
  fs::path failure_file;  // chosen at the first failure; the last write is the shrunk case
  Tally tally;
  std::string last_failure;
  long runs = 0, first_fail = 0;
  long runs_since_failure = 0;  // while shrinking: see max_shrink_runs()
  // Measurement mode: run every case (no early stop, no shrinking) so that the
  // error statistics cover the whole run; the test still fails at the end.
  const bool measure =
      opt.report && (env("LOCKSTEP_MEASURE") || env("LOCKSTEP_ACCURACY_CSV") || env("LOCKSTEP_STABILITY_CSV"));
  long measured_unexplained = 0;
  std::string measured_first;
  auto record = [&](const std::string& expect, std::vector<std::string> notes, std::string text) {
    return Record{prop.family, id, prop.check, prop.pair, prop.impl, expect, std::to_string(p.seed),
                  std::move(notes), std::move(text)};
  };

  auto body = [&] {
    if (!last_failure.empty() && ++runs_since_failure > opt.max_shrink_runs) return;
    const Ran ran = prop.run();
    const Verdict& v = ran.verdict;
    ++runs;
    if (last_failure.empty()) tally.add(v);  // not while shrinking
    if (measure && !v.passed()) {
      if (measured_unexplained++ == 0) measured_first = v.first_failure();
      return;
    }
    std::set<std::string> tags;
    for (size_t i = 0; i < v.rays.size(); ++i) {
      const Outcome& o = v.rays[i];
      if (o.kind == Outcome::explained || o.kind == Outcome::unexplained)
        tags.insert((o.kind == Outcome::unexplained ? "UNEXPLAINED " : "") + o.label);
      if (o.kind == Outcome::explained && save_classified > 0 && classified_saved[o.label] < save_classified) {
        ++classified_saved[o.label];
        write_record(next_free(counterexample_dir(), id), record("classified " + o.label, {o.detail}, ran.text(long(i))));
      }
    }
    if (opt.report)
      for (const std::string& t : tags) RC_TAG(t);
    if (!v.passed()) {
      if (first_fail == 0) first_fail = runs;
      last_failure = v.first_failure();
      if (save_failures) {
        if (failure_file.empty()) failure_file = next_free(counterexample_dir(), id);
        std::vector<std::string> notes;
        for (const Outcome& o : v.rays)
          if (o.kind == Outcome::unexplained) notes.push_back(o.detail);
        write_record(failure_file, record("pass", std::move(notes), ran.text(-1)));
      }
      RC_FAIL(id + ": " + std::to_string(v.count(Outcome::unexplained)) + " unexplained of " +
              std::to_string(v.rays.size()) + "; first: " + last_failure);
    }
  };

  // The seed first, flushed, in every mode (a mutant's runs too): a run that
  // finds something, crashes or times out can be replayed with it, and ctest
  // keeps the line whether the test passes or not (ctest -V,
  // Testing/Temporary/LastTest.log). Deep mode draws a random seed on purpose.
  rc_run::print_seed("lockstep", id, p,
                     opt.report ? "ctest -R '" + prop.test_name() + "$'" : std::string("(a mutant's run)"));
  const auto start = std::chrono::steady_clock::now();
  const rc_run::Result result = rc_run::check(id, p, body);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  RunResult out;
  out.first_failing_case = first_fail;
  out.passed = result.passed && !(measure && measured_unexplained > 0);
  const std::string more =
      "; last failure: " + last_failure +
      (failure_file.empty() ? "" : "\ncounterexample written to " + failure_file.string());
  if (!result.passed)
    out.message = result.message + "\nseed " + std::to_string(p.seed) + ", max_success " +
                  std::to_string(p.max_success) + more;
  if (!opt.report) return out;

  // Report.
  std::cout << "[ lockstep ] " << id << ": " << tally.cases << " cases, " << tally.rays << " " << prop.units << " ("
            << "seed " << p.seed << ", max_success " << p.max_success << ", " << g3(seconds) << " s): ok " << tally.ok
            << ", explained " << tally.explained << ", unexplained " << tally.unexplained << ", skipped "
            << tally.skipped << "\n";
  if (!tally.labels.empty())
    std::cout << "[ lockstep ]   labels: " << labels_text(tally.labels, tally.rays, prop.units, &tally) << "\n";
  if (!tally.class_rays.empty()) {
    std::cout << "[ lockstep ]   " << prop.units << " per class:";
    for (const auto& [c, n] : tally.class_rays) std::cout << " " << c << " " << n;
    std::cout << "\n";
  }
  if (!tally.skipped_labels.empty())
    std::cout << "[ lockstep ]   skipped (not well-conditioned): " << labels_text(tally.skipped_labels, tally.rays, prop.units)
              << "\n";
  for (const auto& [unit, e] : tally.errors)
    std::cout << "[ lockstep ]   " << (unit.empty() ? prop.unit : unit) << " (judged): max " << g3(Tally::max_of(e))
              << " p99 " << g3(Tally::p99_of(e)) << " over " << e.size() << " " << prop.units
              << (unit.empty() && prop.bound > 0 ? "; bound " + g3(prop.bound) : "") << "\n";
  table().push_back({prop.family, prop.check, prop.generator, prop.pair, prop.impl, prop.units, tally});
  if (const char* csv = env("LOCKSTEP_ACCURACY_CSV"); csv && prop.accuracy_csv && tally.default_errors()) {
    const auto& e = *tally.default_errors();
    upsert_csv(csv, "kernel,impl,generator,max,p99,cases,bound", 3,
               {prop.pair + "," + prop.impl + "," + prop.generator + "," + g3(Tally::max_of(e)) + "," +
                g3(Tally::p99_of(e)) + "," + std::to_string(e.size()) + "," + g3(prop.bound)});
  }
  if (const char* csv = env("LOCKSTEP_STABILITY_CSV")) {
    // rays: the label's denominator, the units of its class `per` (empty: all units).
    std::vector<std::string> rows;
    const std::string k = prop.check + "," + prop.generator + "," + prop.pair + "," + prop.impl + ",";
    rows.push_back(k + "ok," + std::to_string(tally.ok) + "," + std::to_string(tally.rays) + ",");
    for (const auto& [l, n] : tally.labels) {
      const auto [den, cls] = tally.per(l);
      rows.push_back(k + l + "," + std::to_string(n) + "," + std::to_string(den) + "," + cls);
    }
    for (const auto& [c, n] : tally.class_rays)
      rows.push_back(k + "class:" + c + "," + std::to_string(n) + "," + std::to_string(tally.rays) + ",");
    upsert_csv(csv, "check,generator,pair,impl,label,count,rays,per", 5, rows);
  }

  // A known failure's rate: over the cap (at 1e-6 significance) fails the run.
  const KnownFailure& kf = prop.known;
  if (!kf.label.empty()) {
    const std::string label = known_label(prop.impl, kf);
    const std::string per(kf.per);
    if (tally.class_rays.count(per) || tally.labels.count(label)) {
      const long n = tally.class_rays.count(per) ? tally.class_rays.at(per) : 0;
      const long k = tally.labels.count(label) ? tally.labels.at(label) : 0;
      const long cap = known_failure_cap(n, kf.max_rate);
      const long floor = known_failure_floor(n, kf.max_rate);
      std::cout << "[ lockstep ]   known failure " << label << ": " << k << " of " << n << " " << per << " " << prop.units << " ("
                << g3(n ? 100.0 * double(k) / double(n) : 0.0) << "%); stated max rate " << g3(100 * kf.max_rate)
                << "%, at most " << cap << " of " << n << " in a run, at least " << floor
                << " (the rate within a factor " << g3(kCapSlack) << " of the cap)\n";
      // The other side: a cap far above the rate hides regressions.
      EXPECT_GE(k, floor) << id << ": known failure " << label << " on only " << k << " of " << n << " " << per
                          << " " << prop.units << " (" << g3(n ? 100.0 * double(k) / double(n) : 0.0)
                          << "%): its stated max rate " << g3(100 * kf.max_rate) << "% is more than " << g3(kCapSlack)
                          << " times the rate (at least " << floor
                          << " expected at 1e-6 significance): measure it and lower the cap";
      EXPECT_LE(k, cap) << id << ": known failure " << label << " on " << k << " of " << n << " " << per
                        << " " << prop.units << " (" << g3(n ? 100.0 * double(k) / double(n) : 0.0)
                        << "%), over its stated max rate " << g3(100 * kf.max_rate) << "% (the " << prop.family
                        << " row in registry/; at most " << cap << " expected at 1e-6 significance)";
    }
  }

  if (measure && measured_unexplained > 0) {
    ADD_FAILURE() << id << ": " << measured_unexplained << " of " << tally.cases
                  << " cases had unexplained outcomes (measurement mode: no shrinking); first: " << measured_first;
  }
  rc_run::report(result, p, more);
  return out;
}

// ---------------------------------------------------------------- registered properties

std::deque<Property>& all_properties() {
  static std::deque<Property> p;
  return p;
}

// ---------------------------------------------------------------- replay

void replay_file(const fs::path& f) {
  SCOPED_TRACE(f.filename().string());
  Record r;
  try {
    r = read_record(f);
  } catch (const std::exception& e) {
    ADD_FAILURE() << "unreadable counterexample: " << e.what();
    return;
  }
  // The properties this file names: one, or with check/impl "all" every property
  // of the family that fits (one per (check, pair, impl): the generator does not
  // change a check).
  std::set<std::string> seen;
  std::vector<const Property*> props;
  for (const Property& p : all_properties()) {
    if (p.family != r.family || p.pair != r.pair) continue;
    if (r.check != "all" && p.check != r.check) continue;
    if (r.impl != "all" && p.impl != r.impl) continue;
    if (seen.insert(p.check + "." + p.pair + "." + p.impl).second) props.push_back(&p);
  }
  if (props.empty()) {
    ADD_FAILURE() << "no property " << r.family << "/" << r.check << "/" << r.pair << "/" << r.impl
                  << " is registered (families: " << registry().names() << ")";
    return;
  }
  for (const Property* p : props) {
    Verdict v;
    try {
      v = p->replay(r.text, f.string());
    } catch (const std::exception& e) {
      ADD_FAILURE() << "unreadable case: " << e.what();
      return;
    }
    const std::string what = f.filename().string() + (props.size() > 1 ? " " + p->test_name() : "");
    if (r.expect == "pass") {
      EXPECT_TRUE(v.passed()) << (r.property.empty() ? p->id() : r.property) << " still fails: " << v.first_failure();
      std::cout << "[ lockstep ]   " << what << ": " << (v.passed() ? "passes" : "FAILS") << "\n";
    } else if (r.expect.rfind("classified ", 0) == 0) {
      const std::string label = r.expect.substr(11);
      const int i = v.first_with_label(label);
      const bool held = i >= 0 && v.rays[size_t(i)].kind == Outcome::explained && v.passed();
      EXPECT_TRUE(held) << r.property << ": expected a failure classified '" << label << "', got: "
                        << (v.rays.empty() ? std::string("no outcome") : v.rays[0].detail);
      std::cout << "[ lockstep ]   " << what << ": " << (held ? "classification holds (" : "CHANGED (") << label
                << ")\n";
    } else {
      ADD_FAILURE() << "unknown expectation '" << r.expect << "'";
    }
  }
}

void replay_all() {
  const fs::path dir = counterexample_dir();
  std::vector<fs::path> files;
  if (fs::exists(dir))
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".txt") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::cout << "[ lockstep ] replaying " << files.size() << " counterexamples from " << dir << "\n";
  for (const fs::path& f : files) replay_file(f);
}

// ---------------------------------------------------------------- mutants

void run_mutant(const std::string& family, const Mutant& m) {
  std::string caught, missed;
  bool designated = m.caught_by.empty();
  for (const Property& p : m.properties) {
    const RunResult r = run_property(p, {.report = false, .max_shrink_runs = 0});
    (r.passed ? missed : caught) += " " + p.suite + (r.passed ? "" : "(case " + std::to_string(r.first_failing_case) + ")");
    if (!r.passed && p.check == m.caught_by) designated = true;
    if (m.caught_by.empty()) {
      EXPECT_TRUE(r.passed) << "the unbroken copy fails " << p.test_name() << "\n" << r.message;
    }
  }
  std::cout << "[ lockstep ] Mutant " << family << "/" << m.name << " (" << m.what << "): caught by{" << caught
            << " }, missed by{" << missed << " }\n";
  EXPECT_TRUE(designated) << m.name << " was not caught by " << m.caught_by;
}

// ---------------------------------------------------------------- registration

class Body : public ::testing::Test {
 public:
  explicit Body(std::function<void()> f) : f_(std::move(f)) {}
  void TestBody() override { f_(); }

 private:
  std::function<void()> f_;
};

void add(const std::string& suite, const std::string& name, std::function<void()> f) {
  ::testing::RegisterTest(suite.c_str(), name.c_str(), nullptr, nullptr, __FILE__, __LINE__,
                          [f]() -> ::testing::Test* { return new Body(f); });
}

void register_all(RunResources& run) {
  std::set<std::string> names;  // every test name once
  auto unique = [&](const std::string& n) {
    if (!names.insert(n).second) std::cerr << "lockstep props: test " << n << " registered twice\n";
    return n;
  };
  for (const Family& f : registry().families) {
    const ProviderRow* row = nullptr;
    for (const ProviderRow& r : property_providers())
      if (r.family == f.name) row = &r;
    if (!row) {
      const std::string fam(f.name);
      add("Registry", unique(fam + "_has_properties"), [fam] {
        FAIL() << "family '" << fam << "' is in the registry (registry/registry.cpp) but props/families.cpp has no "
               << "property provider for it: it is not tested";
      });
      continue;
    }
    FamilyProperties fp = row->provide(f, run);
    if (fp.properties.empty()) {
      const std::string fam(f.name);
      add("Registry", unique(fam + "_has_properties"),
          [fam] { FAIL() << "the property provider of family '" << fam << "' lists no properties"; });
    }
    for (Property& p : fp.properties) {
      all_properties().push_back(std::move(p));
      const Property* q = &all_properties().back();
      unique(q->test_name());
      add(q->suite, q->name, [q] { run_property(*q, {.report = true, .max_shrink_runs = max_shrink_runs()}); });
    }
    for (FixedTest& t : fp.fixed) {
      unique(t.suite + "." + t.name);
      add(t.suite, t.name, std::move(t.body));
    }
    for (Mutant& m : fp.mutants) {
      const std::string fam(f.name);
      unique("Mutants." + fam + "__" + m.name);
      add("Mutants", fam + "__" + m.name, [fam, m] { run_mutant(fam, m); });
    }
  }
  // A provider for a family that is not in the registry tests nothing real.
  for (const ProviderRow& r : property_providers())
    if (!registry().find(r.family)) {
      const std::string fam(r.family);
      add("Registry", unique(fam + "_is_registered"), [fam] {
        FAIL() << "props/families.cpp has properties for '" << fam << "', which registry/registry.cpp does not list";
      });
    }
  add("Replay", "counterexamples", [] { replay_all(); });
}

}  // namespace
}  // namespace lockstep::props::driver

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  // The binary's run: what the properties share across families (the embree
  // rows' one Embree device), owned here and passed down, released after them.
  lockstep::RunResources run;
  lockstep::props::driver::register_all(run);
  const int rc = RUN_ALL_TESTS();
  lockstep::props::driver::print_table();
  // The properties own what their runs keep (the embree rows' devices): released
  // here, while the libraries they belong to are still up, not at static destruction.
  lockstep::props::driver::all_properties().clear();
  return rc;
}
