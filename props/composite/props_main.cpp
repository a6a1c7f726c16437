// lockstep props/composite: the compositing family's properties as GoogleTest tests
// (temporary: the generic property driver will take the checks over).
//
// One test per (check, subject): <Check>.<subject>, e.g. Accuracy.simd, each a
// RapidCheck property over the check's generators (composite::one_of), plus
// RoundTrip8Exhaustive.<subject> (every (c, a) pair once).
//
// Environment:
//   RC_PARAMS="max_success=100 seed=..."   RapidCheck's own (case count, seed, reproduce=...)
//   LOCKSTEP_DEEP=1 (or a count)            deep mode: at least 1000 cases per property
//   LOCKSTEP_COMPOSITE_CASES=dir           saved cases replayed by Replay.counterexamples
//                                           (default props/composite/counterexamples)
//   LOCKSTEP_MEASURE=1                      run every case even after a failure (no shrinking), so
//                                           that the statistics cover the whole run; fails at the
//                                           end
// main() puts both into RC_PARAMS before RapidCheck reads it (no rc::detail), and
// picks a seed when none is given, so that every summary line and failure names it.
#include <gtest/gtest.h>
#include <rapidcheck.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <string>

#include "props/composite/checks.h"
#include "props/composite/gen.h"
#include "props/composite/mutants.h"
#include "props/composite/oracle.h"
#include "reference/composite.h"

namespace lockstep::props::composite {
namespace {

const char* env(const char* name) {
  const char* v = std::getenv(name);
  return v && *v ? v : nullptr;
}

// Writes LOCKSTEP_DEEP and a seed into RC_PARAMS; returns the seed (text).
std::string configure_rapidcheck() {
  std::string p = env("RC_PARAMS") ? env("RC_PARAMS") : "";
  if (const char* deep = env("LOCKSTEP_DEEP")) {
    const long n = std::atol(deep);
    if (n != 0 && p.find("max_success") == std::string::npos)
      p += " max_success=" + std::to_string(n > 1 ? std::max(n, 1000L) : 1000L);
  }
  std::string seed;
  const size_t at = p.find("seed=");
  if (at != std::string::npos) {
    seed = p.substr(at + 5, p.find(' ', at) == std::string::npos ? std::string::npos
                                                                 : p.find(' ', at) - at - 5);
  } else if (p.find("reproduce=") == std::string::npos) {
    std::random_device rd;
    seed = std::to_string((uint64_t(rd()) << 32) ^ rd());
    p += " seed=" + seed;
  } else {
    seed = "(reproduce)";
  }
  setenv("RC_PARAMS", p.c_str(), 1);
  return seed;
}

struct Tally {
  long cases = 0, pixels = 0, ok = 0, explained = 0, unexplained = 0, skipped = 0;
  std::map<std::string, long> labels;
  std::map<std::string, double> max_err;  // per "generator float|unorm8"
  double max_f = 0, max_8 = 0;
  void add(const StackCase& c, const Verdict& v) {
    ++cases;
    for (const Outcome& o : v.rays) {
      ++pixels;
      switch (o.kind) {
        case Outcome::ok:
          ++ok;
          break;
        case Outcome::explained:
          ++explained;
          break;
        case Outcome::unexplained:
          ++unexplained;
          break;
        case Outcome::skipped:
          ++skipped;
          break;
      }
      ++labels[(o.kind == Outcome::unexplained ? "UNEXPLAINED " : "") + o.label];
      if (o.kind == Outcome::skipped || !std::isfinite(o.err)) continue;
      double& m = max_err[c.generator];
      m = std::max(m, o.err);
      if (!c.is8()) {  // float error by layer count (the bounds grow with it)
        double& ml = max_err["float_layers=" + std::to_string(c.layers.size())];
        ml = std::max(ml, o.err);
      }
      if (!c.is8()) {  // float error by layer count (the bounds grow with it)
        double& ml = max_err["float_layers=" + std::to_string(c.layers.size())];
        ml = std::max(ml, o.err);
      }
      (c.is8() ? max_8 : max_f) = std::max(c.is8() ? max_8 : max_f, o.err);
    }
  }
  std::string text() const {
    std::ostringstream s;
    s << cases << " cases, " << pixels << " outcomes: ok " << ok << ", explained " << explained
      << ", unexplained " << unexplained << ", skipped " << skipped << "; max err float " << max_f
      << " ulps, unorm8 " << max_8 << " levels; per generator {";
    for (const auto& [k, m] : max_err) s << " " << k << ":" << m;
    s << " }; labels {";
    for (const auto& [k, n] : labels) s << " " << k << ":" << n;
    s << " }";
    // Classified-loss rates of the 8-bit representation, per alpha bucket.
    std::string rates;
    for (const auto& [k, n] : labels) {
      if (k.rfind("premul8_loss_", 0) != 0) continue;
      const std::string b = k.substr(13);
      const long kept = labels.count(b) ? labels.at(b) : 0;
      char buf[96];
      std::snprintf(buf, sizeof buf, " %s %ld/%ld (%.1f%%)", b.c_str(), n, n + kept,
                    100.0 * double(n) / double(n + kept));
      rates += buf;
    }
    if (!rates.empty()) s << "; loss rate by alpha:" << rates;
    return s.str();
  }
};

class Property : public testing::Test {
 public:
  Property(NamedCheck check, CompositeSubject subject, std::string seed)
      : check_(std::move(check)), subject_(std::move(subject)), seed_(std::move(seed)) {}
  void TestBody() override {
    const rc::Gen<StackCase> gen = one_of(check_.generators);
    Tally tally;
    bool failed = false;
    std::string first;
    const auto t0 = std::chrono::steady_clock::now();
    const std::string name = std::string(check_.name) + "." + subject_.name;
    const bool measure = env("LOCKSTEP_MEASURE") != nullptr;
    long measured_failures = 0;
    const bool ok = rc::check(name, [&] {
      const StackCase c = *gen;
      const Verdict v = check_.fn(subject_, c);
      if (!failed) tally.add(c, v);
      if (!v.passed()) {
        if (!failed) first = v.first_failure();
        if (measure) {  // keep going: the statistics cover every case; the test fails at the end
          ++measured_failures;
          return;
        }
        failed = true;
        RC_FAIL(v.first_failure());
      }
    });
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "[ lockstep ] " << name << " (seed " << seed_ << ", " << secs
              << " s): " << tally.text() << "\n";
    if (ok && measured_failures > 0)
      FAIL() << name << ": " << measured_failures
             << " cases with unexplained outcomes (LOCKSTEP_MEASURE); seed " << seed_
             << "; first:\n  " << first;
    if (!ok)
      FAIL() << name << " failed; seed " << seed_ << " (RC_PARAMS=\"seed=" << seed_
             << "\" reruns it; RapidCheck printed the shrunk case above)\nfirst failure before "
                "shrinking:\n  "
             << first;
  }

 private:
  NamedCheck check_;
  CompositeSubject subject_;
  std::string seed_;
};

// Every (c, a) pair once, through the subject's own premultiply (a 256 x 256
// straight unorm8 layer), then ref::unpremultiply8: the loss is within
// round_trip8_bound(a) and the bound is attained (it is the least bound).
class RoundTripExhaustive : public testing::Test {
 public:
  explicit RoundTripExhaustive(CompositeSubject s) : s_(std::move(s)) {}
  void TestBody() override {
    LayerStack st;
    Layer l;
    l.alpha = Alpha::straight;
    l.image = Image(256, 256);
    l.rgba8.resize(256 * 256 * 4);
    for (int a = 0; a < 256; ++a)
      for (int c = 0; c < 256; ++c) {
        uint8_t* q = &l.rgba8[size_t(a * 256 + c) * 4];
        q[0] = q[1] = q[2] = uint8_t(c);
        q[3] = uint8_t(a);
      }
    st.layers.push_back(l);
    st.storage = Storage::unorm8;
    FrameOptions o;
    o.width = o.height = 256;
    o.threads = 1;
    const Image out = s_.fn(st, o, nullptr);
    int attained = 0, wrong = 0;
    long losses = 0;
    std::map<std::string, std::pair<long, long>> by;  // bucket -> (lost, all)
    for (int a = 1; a < 256; ++a) {
      int worst = 0;
      for (int c = 0; c < 256; ++c) {
        const float* p = &out.rgba[size_t(a * 256 + c) * 4];
        const long pq = std::lround(double(p[0]) * 255);
        if (float(pq) / 255.0f != p[0] || pq != nearest_mul255(c, a)) ++wrong;
        const Rgba8 back = ref::unpremultiply8({uint8_t(pq), uint8_t(pq), uint8_t(pq), uint8_t(a)});
        const int loss = std::abs(int(back.r) - c);
        worst = std::max(worst, loss);
        losses += loss > 0;
        auto& b = by[a < 16    ? "a1-15"
                     : a < 64  ? "a16-63"
                     : a < 128 ? "a64-127"
                     : a < 255 ? "a128-254"
                               : "a255"];
        b.first += loss > 0;
        ++b.second;
        EXPECT_LE(loss, round_trip8_bound(a))
            << s_.name << ": c " << c << " a " << a << " premultiplied " << pq;
      }
      attained += worst == round_trip8_bound(a);
    }
    EXPECT_EQ(wrong, 0) << s_.name << ": premultiplied levels not correctly rounded";
    std::cout << "[ lockstep ] RoundTrip8Exhaustive." << s_.name << ": " << wrong
              << " wrongly rounded of 65280; " << losses
              << " of 65280 (c, a > 0) pairs lose; bound floor(1/2 + 127.5/a) attained for "
              << attained << " of 255 alphas; loss rate by alpha:";
    for (const auto& [k, v] : by)
      std::cout << " " << k << " " << 100.0 * double(v.first) / double(v.second) << "%";
    std::cout << "\n";
  }

 private:
  CompositeSubject s_;
};

// A deliberately broken compositor must fail its designated check (and the
// summary says which other checks catch it too). Runs every check quietly-ish:
// RapidCheck still prints the shrunk counterexample of each catch.
class MutantTest : public testing::Test {
 public:
  explicit MutantTest(Mutant m) : m_(std::move(m)) {}
  void TestBody() override {
    std::string caught, missed;
    bool designated = m_.caught_by.empty();
    for (const NamedCheck& c : composite_checks()) {
      const rc::Gen<StackCase> gen = one_of(c.generators);
      long cases = 0, first_fail = 0;
      if (m_.caught_by.empty() && c.needs_reference_peer)
        continue;  // agreement: the reference's own bugs
      const bool ok =
          rc::check("mutant " + std::string(m_.bug) + " vs " + std::string(c.name), [&] {
            const StackCase sc = *gen;
            ++cases;
            const Verdict v = c.fn(m_.subject, sc);
            if (!v.passed() && first_fail == 0) first_fail = cases;
            RC_ASSERT(v.passed());
          });
      (ok ? missed : caught) +=
          " " + std::string(c.name) + (ok ? "" : "(case " + std::to_string(first_fail) + ")");
      if (!ok && c.name == m_.caught_by) designated = true;
      if (m_.caught_by.empty()) EXPECT_TRUE(ok) << "the unbroken copy fails " << c.name;
    }
    std::cout << "[ lockstep ] Mutant " << m_.bug << " (" << m_.what << "): caught by{" << caught
              << " }, missed by{" << missed << " }\n";
    EXPECT_TRUE(designated) << m_.bug << " was not caught by " << m_.caught_by;
  }

 private:
  Mutant m_;
};

// Every saved case (counterexamples/*.stack) through every check and subject;
// fails on any unexplained outcome (the reference's NaN/inf cases fail until fixed).
class Replay : public testing::Test {
 public:
  void TestBody() override {
    namespace fs = std::filesystem;
    const fs::path dir = env("LOCKSTEP_COMPOSITE_CASES") ? env("LOCKSTEP_COMPOSITE_CASES")
                                                         : LOCKSTEP_COMPOSITE_CASES;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".stack") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files) {
      std::ifstream in(f);
      const StackCase c = read_case(in, f.string());
      for (const NamedCheck& chk : composite_checks())
        for (const CompositeSubject& s : composite_subjects()) {
          if (chk.needs_reference_peer && s.is_reference) continue;
          const Verdict v = chk.fn(s, c);
          std::map<std::string, int> labels;
          for (const Outcome& o : v.rays)
            if (o.kind != Outcome::ok)
              ++labels[(o.kind == Outcome::unexplained ? "UNEXPLAINED " : "") + o.label];
          std::string text;
          for (const auto& [k, n] : labels) text += " " + k + ":" + std::to_string(n);
          std::cout << "[ lockstep ] replay " << f.filename().string() << " " << chk.name << "."
                    << s.name << ":" << (text.empty() ? " ok" : text) << "\n";
          EXPECT_TRUE(v.passed()) << f.string() << " " << chk.name << "." << s.name << "\n  "
                                  << v.first_failure();
        }
    }
  }
};

void register_tests(const std::string& seed) {
  testing::RegisterTest("Replay", "counterexamples", nullptr, nullptr, __FILE__, __LINE__,
                        []() -> testing::Test* { return new Replay(); });
  for (const Mutant& m : mutants())
    testing::RegisterTest("Mutants", std::string(m.bug).c_str(), nullptr, nullptr, __FILE__,
                          __LINE__, [m]() -> testing::Test* { return new MutantTest(m); });
  for (const NamedCheck& c : composite_checks())
    for (const CompositeSubject& s : composite_subjects()) {
      if (c.needs_reference_peer && s.is_reference) continue;
      testing::RegisterTest(std::string(c.name).c_str(), s.name.c_str(), nullptr, nullptr, __FILE__,
                            __LINE__,
                            [c, s, seed]() -> testing::Test* { return new Property(c, s, seed); });
    }
  for (const CompositeSubject& s : composite_subjects())
    testing::RegisterTest("RoundTrip8Exhaustive", s.name.c_str(), nullptr, nullptr, __FILE__,
                          __LINE__, [s]() -> testing::Test* { return new RoundTripExhaustive(s); });
}

}  // namespace
}  // namespace lockstep::props::composite

int main(int argc, char** argv) {
  const std::string seed = lockstep::props::composite::configure_rapidcheck();
  testing::InitGoogleTest(&argc, argv);
  lockstep::props::composite::register_tests(seed);
  return RUN_ALL_TESTS();
}
