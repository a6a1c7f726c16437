// lockstep props: number generators that shrink meaningfully (see numbers.h).
#include "props/gen/numbers.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace lockstep::props::gen {

using rc::Gen;

Gen<int64_t> int_towards(int64_t lo, int64_t hi, int64_t target) {
  target = std::clamp(target, lo, hi);
  const int64_t up = hi - target, down = target - lo, m = std::min(up, down);
  return rc::gen::map(rc::gen::resize(rc::kNominalSize, rc::gen::inRange<int64_t>(0, hi - lo + 1)),
                      [=](int64_t u) {
                        if (u <= 2 * m) {
                          const int64_t k = (u + 1) / 2;
                          return (u % 2) ? target + k : target - k;
                        }
                        const int64_t r = u - 2 * m;
                        return up > down ? target + m + r : target - m - r;
                      });
}

Gen<int64_t> int_in(int64_t lo, int64_t hi) { return int_towards(lo, hi, lo); }

Gen<bool> chance(int num, int den) {
  return rc::gen::map(int_in(0, den - 1), [=](int64_t k) { return k >= den - num; });
}

namespace {
constexpr int64_t kMant = int64_t(1) << 52;
}

Gen<double> log_uniform(double lo, double hi) {
  const int e_lo = std::ilogb(lo), e_hi = std::ilogb(hi);
  return rc::gen::map(rc::gen::pair(int_towards(e_lo, e_hi, std::clamp(0, e_lo, e_hi)), int_in(0, kMant - 1)),
                      [=](std::pair<int64_t, int64_t> em) {
                        const double x = std::ldexp(1.0 + double(em.second) / double(kMant), int(em.first));
                        return std::clamp(x, lo, hi);
                      });
}

Gen<double> signed_log_uniform(double lo, double hi) {
  return rc::gen::map(rc::gen::pair(log_uniform(lo, hi), chance(1, 2)),
                      [](std::pair<double, bool> v) { return v.second ? -v.first : v.first; });
}

Gen<double> uniform(double lo, double hi) {
  return rc::gen::map(int_in(0, kMant), [=](int64_t m) { return lo + (hi - lo) * (double(m) / double(kMant)); });
}

Gen<double> bit_pattern() {
  return rc::gen::map(rc::gen::resize(rc::kNominalSize, rc::gen::arbitrary<uint64_t>()),
                      [](uint64_t b) { return std::bit_cast<double>(b); });
}

Gen<double> finite_bit_pattern() {
  return rc::gen::map(bit_pattern(), [](double x) { return std::isfinite(x) ? x : std::ldexp(1.0, 1000); });
}

double nudge(double x, int64_t k) {
  for (; k > 0; --k) x = std::nextafter(x, kInfinity);
  for (; k < 0; ++k) x = std::nextafter(x, -kInfinity);
  return x;
}

Gen<double> nudged(double x, int max_ulps) {
  return rc::gen::map(int_towards(-max_ulps, max_ulps, 0), [x](int64_t k) { return nudge(x, k); });
}

Gen<Vec3> unit_dir() {
  const auto c = int_towards(-(1 << 20), 1 << 20, 0);
  return rc::gen::map(rc::gen::tuple(c, c, c), [](std::tuple<int64_t, int64_t, int64_t> v) {
    Vec3 d{double(std::get<0>(v)), double(std::get<1>(v)), double(std::get<2>(v))};
    if (d == Vec3{0, 0, 0}) d = {0, 0, 1};
    return normalize(d);
  });
}

Gen<double> dyadic(int bits, int exp) {
  return rc::gen::map(int_towards(-(int64_t(1) << bits), int64_t(1) << bits, 0),
                      [exp](int64_t m) { return std::ldexp(double(m), exp); });
}

}  // namespace lockstep::props::gen
