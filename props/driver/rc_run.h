// lockstep props/driver: running one RapidCheck property, for every property
// binary (lockstep_props' driver and fixed tests, lockstep_dropped_props,
// lockstep_fuzz_nff, lockstep_fuzz_volume). The only code that uses
// RapidCheck's internals (rc::detail); a small library of its own
// (lockstep_rc_run: no CGAL, no registry), so that the fuzz binaries stay small
// for scripts/fuzz.sh's sanitizer build.
//
// One rule for every binary:
//   seed         a hash of the property's name, so that ctest runs the same cases
//                every time, unless RC_PARAMS gives one, or LOCKSTEP_DEEP or
//                LOCKSTEP_RANDOM_SEED is set (RapidCheck's random seed, on purpose).
//   case count   RC_PARAMS' max_success when given (a replay needs the same
//                count), else LOCKSTEP_DEEP=1: 1000, LOCKSTEP_DEEP=N > 1: N, else
//                100; times the binary's scale (the fuzzers: 50, parsing is cheap).
// Before the first case, one line, flushed (a run that fails, crashes or
// times out can be replayed from ctest's log):
//   [ <tag> ] <name>: seed S, max_success N[ (deep)]; replay: RC_PARAMS="seed=S max_success=M"
//   <how>
// (M = N / scale: what RC_PARAMS must say to draw the same cases).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace lockstep::props::rc_run {

struct Params {
  std::uint64_t seed = 0;
  int max_success = 100;  // cases, the scale applied
  int scale = 1;
  bool deep = false;  // LOCKSTEP_DEEP is set
};

// The seed and case count of the property `name` (the rule above).
Params params(const std::string& name, int scale = 1);

// The replay line above, printed and flushed; `how` follows the RC_PARAMS
// ("ctest -R 'Suite.name$'").
void print_seed(const std::string& tag, const std::string& name, const Params& p,
                const std::string& how);
// "ctest -R '<prefix><Suite>.<name>$'" for the running GoogleTest test (prefix:
// the binary's ctest TEST_PREFIX, "dropped.").
std::string ctest_line(const std::string& prefix = "");

struct Result {
  bool passed = false;
  // RapidCheck's result message: on failure the shrunk case and reproduce=...;
  // on success "OK, passed N tests" and the RC_TAG distribution, if any.
  std::string message;
  bool tagged = false;  // passed with a tag distribution
};

// Runs body (which draws with *gen and asserts with RC_ASSERT / RC_FAIL) as
// RapidCheck property `name` with p's seed and case count (RC_PARAMS'
// reproduce= and its other settings apply).
Result check(const std::string& name, const Params& p, const std::function<void()>& body);

// A failed result reported through GoogleTest (ADD_FAILURE: RapidCheck's
// message, then "seed S, max_success N" and `more`); a passing one with a tag
// distribution prints it. Returns r.passed.
bool report(const Result& r, const Params& p, const std::string& more = "");

// params (at `scale`), print_seed (tag "lockstep", ctest_line()), check,
// report: a property of a fixed test in one call. `echo`: also one line with
// RapidCheck's message, passed or not ("[ lockstep ] name (seed S,
// max_success N): OK, passed N tests"; the fuzzers, whose logs say how many
// inputs each run tried).
bool run(const std::string& name, const std::function<void()>& body, int scale = 1, bool echo = false);

// A fuzzer's property: run at 50 times the usual case count (parsing is
// cheap), echoed.
inline bool fuzz(const std::string& name, const std::function<void()>& body) { return run(name, body, 50, true); }

}  // namespace lockstep::props::rc_run
