// lockstep props: number generators shared by every family's case generators.
//
// RapidCheck's own double generator is mostly small integers and shrinks to
// nothing interesting, so every number here is built from integers that shrink
// meaningfully: an exponent that shrinks towards 0 (the value towards 1), a
// mantissa that shrinks towards 0 (the value towards a power of two), a sign
// that shrinks towards +, a count of ulps that shrinks towards 0 (towards the
// degenerate configuration itself). Every integer range is generated at full
// width whatever RapidCheck's "size" is (gen::resize), so the first cases are
// as varied as the last.
#pragma once

#include <cstdint>

#include <rapidcheck.h>

#include "core/math.h"

namespace lockstep::props::gen {

// Integer in [lo, hi], uniformly, shrinking towards target (zig-zag: target,
// target+1, target-1, ...).
rc::Gen<int64_t> int_towards(int64_t lo, int64_t hi, int64_t target);
// Integer in [lo, hi], shrinking towards lo.
rc::Gen<int64_t> int_in(int64_t lo, int64_t hi);
// Coin with probability num/den of true; shrinks towards false.
rc::Gen<bool> chance(int num, int den);
// Positive double, log-uniform in [lo, hi]: exponent and 52-bit mantissa drawn
// separately (shrinks towards 1, or the bound nearest to it, with a short mantissa).
rc::Gen<double> log_uniform(double lo, double hi);
// As log_uniform, random sign (shrinks towards +).
rc::Gen<double> signed_log_uniform(double lo, double hi);
// Uniform-ish in [lo, hi] with a 52-bit fraction (shrinks towards lo).
rc::Gen<double> uniform(double lo, double hi);
// Any 64-bit pattern as a double: NaN, infinities, subnormals, -0 (shrinks to +0).
rc::Gen<double> bit_pattern();
// Any finite double from its bit pattern.
rc::Gen<double> finite_bit_pattern();
// x moved k ulps (std::nextafter), k in [-max_ulps, max_ulps] shrinking to 0.
double nudge(double x, int64_t k);
rc::Gen<double> nudged(double x, int max_ulps);
// Unit vector (double precision, normalised), roughly uniform on the sphere;
// shrinks towards the coordinate axes.
rc::Gen<Vec3> unit_dir();
// Multiple of 2^exp with |m| <= 2^bits (exact, for geometry that must be exact).
rc::Gen<double> dyadic(int bits, int exp);

}  // namespace lockstep::props::gen
