// lockstep props: the property tests, registered from the pair table.
//
// For every pair and implementation of core/pairs.h (never a hard-coded list):
//   Agreement.<pair>__<impl>           non-reference impls vs the reference, well-conditioned input
//   Render.<pair>__<impl>              16x16 renders vs the reference (generators that render)
//   Accuracy.<pair>__<impl>            every impl vs the oracle, within Impl::oracle_t_rel
//   Stability.<gen>__<pair>__<impl>    every stability generator that fits the pair
//   Watertight.<gen>__<pair>__<impl>   closed meshes, rays through shared edges and vertices
//   Degenerate.<gen>__<pair>__<impl>   zero-area and otherwise degenerate polygons
//   Replay.counterexamples             every file in corpus/counterexamples
//
// Environment:
//   RC_PARAMS="max_success=100 seed=..."   RapidCheck's own (case count, seed, reproduce=...)
//   LOCKSTEP_DEEP=1 (or a count)            deep mode: at least 1000 cases per property
//   LOCKSTEP_ACCURACY_CSV=file              max/p99 relative t error per (pair, impl, generator)
//   LOCKSTEP_STABILITY_CSV=file             outcome counts per (generator, pair, impl, label)
//   LOCKSTEP_COUNTEREXAMPLE_DIR=dir         where failing cases are written (default corpus/counterexamples)
//   LOCKSTEP_NO_SAVE=1                      do not write counterexample files
//   LOCKSTEP_SAVE_CLASSIFIED=n              also save up to n textbook failures per (property, label)
//                                           as "expect classified <label>" replay cases
//   LOCKSTEP_MAX_SHRINK_RUNS=n              cap on property runs while shrinking (default 2000)
//   LOCKSTEP_MEASURE=1                      run every case even after a failure (no shrinking), so that
//                                           the statistics cover the whole run; implied by the CSV variables
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <rapidcheck.h>

#include "pairs/ray_cast.h"
#include "props/ray_cast/case.h"
#include "props/ray_cast/generators.h"
#include "props/ray_cast/checks.h"
#include "props/ray_cast/oracle.h"

namespace rc::detail {
TestListener& globalTestListener();
}

namespace lockstep::props {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- configuration

const char* env(const char* name) {
  const char* v = std::getenv(name);
  return v && *v ? v : nullptr;
}

// The seed is fixed per property (a hash of its name) unless RC_PARAMS gives one
// or LOCKSTEP_RANDOM_SEED=1 asks for RapidCheck's random seed: `ctest` (and CI)
// run the same cases every time, and deep mode explores new ones.
rc::detail::TestParams params(const std::string& property) {
  rc::detail::TestParams p = rc::detail::configuration().testParams;
  const char* given = env("RC_PARAMS");
  if (!env("LOCKSTEP_RANDOM_SEED") && !(given && std::string(given).find("seed") != std::string::npos) &&
      !env("LOCKSTEP_DEEP"))
    p.seed = std::hash<std::string>{}(property) & 0xffffffffffffull;
  if (const char* deep = env("LOCKSTEP_DEEP")) {
    const long n = std::atol(deep);
    if (n != 0) p.maxSuccess = std::max(p.maxSuccess, n > 1 ? int(n) : 1000);
  }
  return p;
}

fs::path counterexample_dir() {
  if (const char* d = env("LOCKSTEP_COUNTEREXAMPLE_DIR")) return d;
  return LOCKSTEP_COUNTEREXAMPLE_DIR;
}

std::string generator_of(const std::string& pair) {
  const RayCastRows& t = ray_cast_rows();
  if (pair == t.ray_sphere.name) return std::string(t.ray_sphere.generator);
  if (pair == t.ray_plane.name) return std::string(t.ray_plane.generator);
  if (pair == t.ray_polygon.name) return std::string(t.ray_polygon.generator);
  if (pair == t.ray_cast.name) return std::string(t.ray_cast.generator);
  return "";
}

unsigned kind_bit(Kernel k) {
  switch (k) {
    case Kernel::sphere: return gen::kSphereKernel;
    case Kernel::plane: return gen::kPlaneKernel;
    case Kernel::polygon: return gen::kPolygonKernel;
    default: return gen::kTrace;
  }
}

// ---------------------------------------------------------------- tallies and CSV

struct Tally {
  long cases = 0, rays = 0, ok = 0, explained = 0, unexplained = 0, skipped = 0;
  std::map<std::string, long> labels;  // explained/unexplained labels
  std::map<std::string, long> skipped_labels;
  // Rays per class (watertight: vertex, edge, face), and which class each label
  // was seen in: rates divide by the rays of their class.
  std::map<std::string, long> class_rays;
  std::map<std::string, std::string> label_class;  // label -> its class ("*" if several)
  std::vector<double> errors;  // relative t errors where both hit (judged rays)
  void add(const Verdict& v) {
    ++cases;
    for (const Outcome& o : v.rays) {
      ++rays;
      if (!o.cls.empty()) ++class_rays[o.cls];
      if (o.kind == Outcome::explained || o.kind == Outcome::unexplained) {
        const std::string l = (o.kind == Outcome::unexplained ? "UNEXPLAINED " : "") + o.label;
        auto [it, fresh] = label_class.emplace(l, o.cls);
        if (!fresh && it->second != o.cls) it->second = "*";
      }
      switch (o.kind) {
        case Outcome::ok: ++ok; break;
        case Outcome::explained: ++explained; ++labels[o.label]; break;
        case Outcome::unexplained: ++unexplained; ++labels["UNEXPLAINED " + o.label]; break;
        case Outcome::skipped: ++skipped; ++skipped_labels[o.label]; break;
      }
      if (o.kind != Outcome::skipped && o.both_hit && std::isfinite(o.err)) errors.push_back(o.err);
    }
  }
  // The denominator of a label's rate: the rays of its class, or all rays.
  std::pair<long, std::string> per(const std::string& label) const {
    auto it = label_class.find(label);
    if (it == label_class.end() || it->second.empty() || it->second == "*") return {rays, ""};
    auto c = class_rays.find(it->second);
    return {c == class_rays.end() ? rays : c->second, it->second};
  }
  double max_error() const { return errors.empty() ? 0 : *std::max_element(errors.begin(), errors.end()); }
  double p99() const {
    if (errors.empty()) return 0;
    std::vector<double> e = errors;
    const size_t k = std::min(e.size() - 1, size_t(std::ceil(0.99 * double(e.size()))) - 1);
    std::nth_element(e.begin(), e.begin() + long(k), e.end());
    return e[k];
  }
};

// Rewrites rows of a CSV keyed by their first key_cols fields, under an exclusive lock
// (ctest runs several test processes at once).
void upsert_csv(const std::string& path, const std::string& header, size_t key_cols,
                const std::vector<std::string>& rows) {
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT, 0644);
  if (fd < 0) {
    std::cerr << "cannot open " << path << "\n";
    return;
  }
  ::flock(fd, LOCK_EX);
  std::string text;
  char buf[4096];
  for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) > 0;) text.append(buf, size_t(n));
  auto key = [&](const std::string& line) {
    size_t pos = 0;
    for (size_t k = 0; k < key_cols && pos != std::string::npos; ++k) pos = line.find(',', pos + (k ? 1 : 0));
    return line.substr(0, pos);
  };
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);)
    if (!l.empty() && l != header) lines.push_back(l);
  for (const std::string& r : rows) {
    auto it = std::find_if(lines.begin(), lines.end(), [&](const std::string& l) { return key(l) == key(r); });
    if (it != lines.end()) *it = r;
    else lines.push_back(r);
  }
  std::string out = header + "\n";
  for (const auto& l : lines) out += l + "\n";
  ::lseek(fd, 0, SEEK_SET);
  if (::ftruncate(fd, 0) != 0 || ::write(fd, out.data(), out.size()) != ssize_t(out.size()))
    std::cerr << "cannot write " << path << "\n";
  ::flock(fd, LOCK_UN);
  ::close(fd);
}

std::string g3(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

// The stability table of this process, printed at exit.
struct TableRow {
  std::string check, generator, pair, impl;
  Tally tally;
};
std::vector<TableRow>& table() {
  static std::vector<TableRow> t;
  return t;
}

std::string labels_text(const std::map<std::string, long>& labels, long rays, const Tally* t = nullptr) {
  std::string s;
  for (const auto& [l, n] : labels) {
    if (!s.empty()) s += ", ";
    const auto [den, cls] = t ? t->per(l) : std::pair<long, std::string>{rays, ""};
    s += l + " " + std::to_string(n) + " (" + g3(100.0 * double(n) / double(std::max(1L, den))) + "%" +
         (cls.empty() ? "" : " of " + std::to_string(den) + " " + cls + " rays") + ")";
  }
  return s.empty() ? "-" : s;
}

void print_table() {
  if (table().empty()) return;
  std::cout << "\n==== lockstep props: outcome table (rays judged against the oracle) ====\n";
  std::cout << "check | generator | pair | impl | cases | rays | ok | explained (classified) | unexplained | skipped | "
               "labels\n";
  for (const TableRow& r : table()) {
    const Tally& t = r.tally;
    std::cout << r.check << " | " << r.generator << " | " << r.pair << " | " << r.impl << " | " << t.cases << " | "
              << t.rays << " | " << t.ok << " | " << t.explained << " | " << t.unexplained << " | " << t.skipped
              << " | " << labels_text(t.labels, t.rays, &t) << "\n";
  }
}

// ---------------------------------------------------------------- counterexamples

fs::path next_free(const std::string& property) {
  const fs::path dir = counterexample_dir();
  for (int n = 1;; ++n) {
    fs::path p = dir / (property + "-" + std::to_string(n) + ".txt");
    if (!fs::exists(p)) return p;
  }
}

void save(const fs::path& path, const Record& r) {
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  std::ofstream out(path);
  write_record(out, r);
}

// ---------------------------------------------------------------- one property

struct Spec {
  std::string check;      // accuracy | agreement | stability | watertight | degenerate | render
  std::string generator;  // registry name
  const Subject* subject;
  std::string property() const {
    return check + "." + generator + "." + subject->info.pair + "." + subject->info.name;
  }
};

void run_property(const Spec& spec) {
  const Subject& s = *spec.subject;
  try {
    probe(s);
  } catch (const Placeholder& e) {
    GTEST_SKIP() << s.info.pair << "/" << s.info.name << ": " << e.what() << " -- not tested yet";
  }
  const gen::Named* g = gen::find(spec.generator);
  ASSERT_NE(g, nullptr) << "no generator named '" << spec.generator << "' (pair table or registry out of date)";
  const std::string property = spec.property();
  const rc::detail::TestParams p = params(property);
  const bool save_failures = !env("LOCKSTEP_NO_SAVE");
  const long save_classified = env("LOCKSTEP_SAVE_CLASSIFIED") ? std::atol(env("LOCKSTEP_SAVE_CLASSIFIED")) : 0;
  std::map<std::string, long> classified_saved;
  fs::path failure_file;  // chosen at the first failure; the last write is the shrunk case
  Tally tally;
  std::string last_failure;
  // Shrinking a case of 20 rays can take minutes; past this many runs after the
  // first failure every candidate "passes", so RapidCheck stops at the smallest so far.
  const long max_shrink_runs = env("LOCKSTEP_MAX_SHRINK_RUNS") ? std::atol(env("LOCKSTEP_MAX_SHRINK_RUNS")) : 2000;
  long runs_since_failure = 0;
  // Measurement mode: run every case (no early stop, no shrinking) so that the
  // error statistics cover the whole run; the test still fails at the end.
  const bool measure = env("LOCKSTEP_MEASURE") || env("LOCKSTEP_ACCURACY_CSV") || env("LOCKSTEP_STABILITY_CSV");
  long measured_unexplained = 0;
  std::string measured_first;

  auto body = [&] {
    if (!last_failure.empty() && ++runs_since_failure > max_shrink_runs) return;
    const Case c = *g->gen;
    Verdict v;
    try {
      v = run_check(spec.check, s, c);
    } catch (const Placeholder& e) {
      RC_DISCARD(e.what());
    }
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
      if (o.kind == Outcome::explained && s.info.mode == Mode::textbook && save_classified > 0 &&
          spec.check != "render" && classified_saved[o.label] < save_classified) {
        ++classified_saved[o.label];
        Record r{property, spec.check, s.info.pair, s.info.name, "classified " + o.label,
                 std::to_string(p.seed), {o.detail}, with_ray(c, i)};
        save(next_free(property), r);
      }
    }
    for (const std::string& t : tags) RC_TAG(t);
    if (!v.passed()) {
      last_failure = v.first_failure();
      if (save_failures) {
        if (failure_file.empty()) failure_file = next_free(property);
        Record r{property, spec.check, s.info.pair, s.info.name, "pass", std::to_string(p.seed), {}, c};
        for (const Outcome& o : v.rays)
          if (o.kind == Outcome::unexplained) r.notes.push_back(o.detail);
        save(failure_file, r);
      }
      RC_FAIL(property + ": " + std::to_string(v.count(Outcome::unexplained)) + " unexplained of " +
              std::to_string(v.rays.size()) + "; first: " + last_failure);
    }
  };

  rc::detail::TestMetadata meta;
  meta.id = property;
  meta.description = property;
  const auto start = std::chrono::steady_clock::now();
  const auto result = rc::detail::checkProperty(rc::detail::toProperty(body), meta, p,
                                                rc::detail::globalTestListener(),
                                                rc::detail::configuration().reproduce);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // Report.
  std::cout << "[ lockstep ] " << property << ": " << tally.cases << " cases, " << tally.rays << " rays ("
            << "seed " << p.seed << ", max_success " << p.maxSuccess << ", " << g3(seconds) << " s): ok " << tally.ok
            << ", explained " << tally.explained << ", unexplained " << tally.unexplained << ", skipped "
            << tally.skipped << "\n";
  if (!tally.labels.empty())
    std::cout << "[ lockstep ]   labels: " << labels_text(tally.labels, tally.rays, &tally) << "\n";
  if (!tally.class_rays.empty()) {
    std::cout << "[ lockstep ]   rays per class:";
    for (const auto& [c, n] : tally.class_rays) std::cout << " " << c << " " << n;
    std::cout << "\n";
  }
  if (!tally.skipped_labels.empty())
    std::cout << "[ lockstep ]   skipped (not well-conditioned): " << labels_text(tally.skipped_labels, tally.rays)
              << "\n";
  if (!tally.errors.empty())
    std::cout << "[ lockstep ]   relative t error (both hit, judged): max " << g3(tally.max_error()) << " p99 "
              << g3(tally.p99()) << " over " << tally.errors.size() << " rays; bound " << g3(s.info.bound) << "\n";
  table().push_back({spec.check, spec.generator, s.info.pair, s.info.name, tally});
  if (spec.check == "accuracy" || spec.check == "stability" || spec.check == "watertight") {
    if (const char* csv = env("LOCKSTEP_ACCURACY_CSV"); csv && !tally.errors.empty())
      upsert_csv(csv, "kernel,impl,generator,max,p99,cases,bound", 3,
                 {s.info.pair + "," + s.info.name + "," + spec.generator + "," + g3(tally.max_error()) + "," +
                  g3(tally.p99()) + "," + std::to_string(tally.errors.size()) + "," + g3(s.info.bound)});
  }
  if (const char* csv = env("LOCKSTEP_STABILITY_CSV")) {
    // rays: the label's denominator, the rays of its class `per` (empty: all rays).
    std::vector<std::string> rows;
    const std::string k = spec.check + "," + spec.generator + "," + s.info.pair + "," + s.info.name + ",";
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
  if (!s.info.known_failure.empty() && (tally.class_rays.count(s.info.known_per) || tally.labels.count(known_label(s.info)))) {
    const std::string label = known_label(s.info);
    const long n = tally.class_rays.count(s.info.known_per) ? tally.class_rays.at(s.info.known_per) : 0;
    const long k = tally.labels.count(label) ? tally.labels.at(label) : 0;
    const long cap = known_failure_cap(n, s.info.known_max_rate);
    std::cout << "[ lockstep ]   known failure " << label << ": " << k << " of " << n << " " << s.info.known_per
              << " rays (" << g3(n ? 100.0 * double(k) / double(n) : 0.0) << "%); stated max rate "
              << g3(100 * s.info.known_max_rate) << "%, at most " << cap << " of " << n << " in a run\n";
    EXPECT_LE(k, cap) << property << ": known failure " << label << " on " << k << " of " << n << " "
                      << s.info.known_per << " rays (" << g3(n ? 100.0 * double(k) / double(n) : 0.0)
                      << "%), over its stated max rate " << g3(100 * s.info.known_max_rate)
                      << "% (core/pairs.cpp; at most " << cap << " expected at 1e-6 significance)";
  }

  if (measure && measured_unexplained > 0) {
    ADD_FAILURE() << property << ": " << measured_unexplained << " of " << tally.cases
                  << " cases had unexplained outcomes (measurement mode: no shrinking); first: " << measured_first;
  }
  if (!result.template is<rc::detail::SuccessResult>()) {
    std::ostringstream ss;
    rc::detail::printResultMessage(result, ss);
    FAIL() << ss.str() << "\nseed " << p.seed << "; last failure: " << last_failure
           << (failure_file.empty() ? "" : "\ncounterexample written to " + failure_file.string());
  } else {
    const auto& success = result.template get<rc::detail::SuccessResult>();
    if (!success.distribution.empty()) {
      rc::detail::printResultMessage(result, std::cout);
      std::cout << "\n";
    }
  }
}

// ---------------------------------------------------------------- replay

void replay_all() {
  const fs::path dir = counterexample_dir();
  std::vector<fs::path> files;
  if (fs::exists(dir))
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".txt") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::cout << "[ lockstep ] replaying " << files.size() << " counterexamples from " << dir << "\n";
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.filename().string());
    Record r;
    try {
      std::ifstream in(f);
      r = read_record(in, f.string());
    } catch (const std::exception& e) {
      ADD_FAILURE() << "unreadable counterexample: " << e.what();
      continue;
    }
    const Subject* s = find_subject(r.pair, r.impl);
    if (!s) {
      ADD_FAILURE() << "no implementation " << r.pair << "/" << r.impl << " in the pair table";
      continue;
    }
    try {
      probe(*s);
    } catch (const Placeholder&) {
      std::cout << "[ lockstep ]   " << f.filename().string() << ": " << r.impl << " is a placeholder, skipped\n";
      continue;
    }
    const Verdict v = run_check(r.check, *s, r.c);
    if (r.expect == "pass") {
      EXPECT_TRUE(v.passed()) << r.property << " still fails: " << v.first_failure();
      std::cout << "[ lockstep ]   " << f.filename().string() << ": " << (v.passed() ? "passes" : "FAILS") << "\n";
    } else if (r.expect.rfind("classified ", 0) == 0) {
      const std::string label = r.expect.substr(11);
      const int i = v.first_with_label(label);
      const bool held = i >= 0 && v.rays[size_t(i)].kind == Outcome::explained && v.passed();
      EXPECT_TRUE(held) << r.property << ": expected a failure classified '" << label << "', got: "
                        << (v.rays.empty() ? std::string("no outcome") : v.rays[0].detail);
      std::cout << "[ lockstep ]   " << f.filename().string() << ": " << (held ? "classification holds (" : "CHANGED (")
                << label << ")\n";
    } else {
      ADD_FAILURE() << "unknown expectation '" << r.expect << "'";
    }
  }
}

// ---------------------------------------------------------------- registration

class PropertyTest : public ::testing::Test {
 public:
  explicit PropertyTest(Spec s) : spec_(std::move(s)) {}
  void TestBody() override { run_property(spec_); }

 private:
  Spec spec_;
};

class ReplayTest : public ::testing::Test {
 public:
  void TestBody() override { replay_all(); }
};

void add(const std::string& suite, const std::string& name, const Spec& spec) {
  ::testing::RegisterTest(suite.c_str(), name.c_str(), nullptr, nullptr, __FILE__, __LINE__,
                          [spec]() -> ::testing::Test* { return new PropertyTest(spec); });
}

void register_all() {
  static const std::vector<Subject> subjects = all_subjects();
  for (const Subject& s : subjects) {
    const std::string id = s.info.pair + "__" + s.info.name;
    const std::string well = generator_of(s.info.pair);
    const gen::Named* wg = gen::find(well);
    if (!wg) {
      std::cerr << "lockstep props: pair " << s.info.pair << " names generator '" << well
                << "', which props/gen does not have\n";
    }
    if (!s.info.is_reference) add("Agreement", id, {"agreement", well, &s});
    add("Accuracy", id, {"accuracy", well, &s});
    if (s.kernel == Kernel::frame && !s.info.is_reference && wg && (wg->kinds & gen::kRender))
      add("Render", id, {"render", well, &s});
    for (const gen::Named& g : gen::registry()) {
      if (!g.stability) continue;
      const std::string gid = std::string(g.name) + "__" + id;
      if (g.kinds & kind_bit(s.kernel)) add("Stability", gid, {"stability", std::string(g.name), &s});
      if ((g.kinds & gen::kWatertight) && (s.kernel == Kernel::polygon || s.kernel == Kernel::frame))
        add("Watertight", gid, {"watertight", std::string(g.name), &s});
      if ((g.kinds & gen::kDegenerate) && (s.kernel == Kernel::polygon || s.kernel == Kernel::frame))
        add("Degenerate", gid, {"degenerate", std::string(g.name), &s});
    }
  }
  ::testing::RegisterTest("Replay", "counterexamples", nullptr, nullptr, __FILE__, __LINE__,
                          []() -> ::testing::Test* { return new ReplayTest(); });
}

}  // namespace
}  // namespace lockstep::props

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  lockstep::props::register_all();
  const int rc = RUN_ALL_TESTS();
  lockstep::props::print_table();
  return rc;
}
