// lockstep props/driver: running one RapidCheck property (see rc_run.h).
#include "props/driver/rc_run.h"

#include <gtest/gtest.h>
#include <rapidcheck.h>

#include <cstdlib>
#include <iostream>
#include <sstream>

namespace rc::detail {
TestListener& globalTestListener();  // RapidCheck's own, not in its public headers
}

namespace lockstep::props::rc_run {
namespace {

const char* env(const char* name) {
  const char* v = std::getenv(name);
  return v && *v ? v : nullptr;
}

bool given(const char* key) {
  const char* p = env("RC_PARAMS");
  return p && std::string(p).find(key) != std::string::npos;
}

rc::detail::TestParams test_params(const Params& p) {
  rc::detail::TestParams t = rc::detail::configuration().testParams;
  t.seed = p.seed;
  t.maxSuccess = p.max_success;
  return t;
}

}  // namespace

Params params(const std::string& name, int scale) {
  const rc::detail::TestParams& config = rc::detail::configuration().testParams;
  Params p;
  p.scale = scale;
  p.deep = env("LOCKSTEP_DEEP") != nullptr;
  p.seed = config.seed;
  if (!given("seed") && !p.deep && !env("LOCKSTEP_RANDOM_SEED"))
    p.seed = std::hash<std::string>{}(name)&0xffffffffffffull;
  int cases = 100;
  if (given("max_success")) {
    cases = config.maxSuccess;
  } else if (p.deep) {
    const long n = std::atol(env("LOCKSTEP_DEEP"));
    if (n > 1) cases = int(n);
    if (n == 1) cases = 1000;
  }
  p.max_success = cases * scale;
  return p;
}

void print_seed(const std::string& tag, const std::string& name, const Params& p,
                const std::string& how) {
  std::cout << "[ " << tag << " ] " << name << ": seed " << p.seed << ", max_success "
            << p.max_success << (p.deep ? " (deep)" : "") << "; replay: RC_PARAMS=\"seed=" << p.seed
            << " max_success=" << p.max_success / p.scale << "\"" << (how.empty() ? "" : " " + how)
            << std::endl;
}

std::string ctest_line(const std::string& prefix) {
  const ::testing::TestInfo* t = ::testing::UnitTest::GetInstance()->current_test_info();
  if (!t) return "";
  return "ctest -R '" + prefix + t->test_suite_name() + "." + t->name() + "$'";
}

Result check(const std::string& name, const Params& p, const std::function<void()>& body) {
  rc::detail::TestMetadata meta;
  meta.id = name;
  meta.description = name;
  const auto result = rc::detail::checkProperty(rc::detail::toProperty(body), meta, test_params(p),
                                                rc::detail::globalTestListener(),
                                                rc::detail::configuration().reproduce);
  Result r;
  r.passed = result.template is<rc::detail::SuccessResult>();
  r.tagged = r.passed && !result.template get<rc::detail::SuccessResult>().distribution.empty();
  std::ostringstream ss;
  rc::detail::printResultMessage(result, ss);
  r.message = ss.str();
  return r;
}

bool report(const Result& r, const Params& p, const std::string& more) {
  if (!r.passed)
    ADD_FAILURE() << r.message << "\nseed " << p.seed << ", max_success " << p.max_success << more;
  else if (r.tagged)
    std::cout << r.message << "\n";
  return r.passed;
}

bool run(const std::string& name, const std::function<void()>& body, int scale, bool echo) {
  const Params p = params(name, scale);
  print_seed("lockstep", name, p, ctest_line());
  const Result r = check(name, p, body);
  if (echo)
    std::cout << "[ lockstep ] " << name << " (seed " << p.seed << ", max_success " << p.max_success
              << "): " << r.message << "\n";
  return report(r, p);
}

}  // namespace lockstep::props::rc_run
