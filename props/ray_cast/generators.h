// lockstep props: generators.
//
// RapidCheck's own double generator is mostly small integers and shrinks to
// nothing interesting, so every number here is built from integers that shrink
// meaningfully: an exponent that shrinks towards 0 (the value towards 1), a
// mantissa that shrinks towards 0 (the value towards a power of two), a sign
// that shrinks towards +, a count of ulps that shrinks towards 0 (towards the
// degenerate configuration itself). Every integer range is generated at full
// width whatever RapidCheck's "size" is (gen::resize), so the first cases are
// as varied as the last.
//
// Case generators are registered by name; the pair table (core/pairs.cpp) names
// the well-conditioned one of each algorithm, and the stability generators are
// listed here with the kernels they exercise.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include <rapidcheck.h>

#include "core/math.h"
#include "props/ray_cast/case.h"

namespace lockstep::props::gen {

// ---------------------------------------------------------------- numbers
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

// ---------------------------------------------------------------- geometry helpers (deterministic)
// Closed triangle/quad meshes with vertices on a dyadic grid (shared vertices are
// the same doubles). faces index into verts, counter-clockwise seen from outside.
struct Mesh {
  std::vector<Vec3> verts;
  std::vector<std::vector<uint32_t>> faces;
};
Mesh octahedron();
Mesh icosahedron(int grid_bits);          // vertices rounded to 2^-grid_bits
Mesh icosphere(int level, int grid_bits);  // subdivided icosahedron, on the unit sphere
Mesh tessellated_cube(int n, bool quads);  // n x n cells per face, as quads or triangle pairs

// ---------------------------------------------------------------- named case generators
enum Kinds : unsigned {
  kSphereKernel = 1u << 0,
  kPlaneKernel = 1u << 1,
  kPolygonKernel = 1u << 2,
  kTrace = 1u << 3,
  kRender = 1u << 4,
  kWatertight = 1u << 5,
  kDegenerate = 1u << 6,
};

struct Named {
  std::string_view name;
  unsigned kinds;      // which checks the cases support
  bool stability;      // a stability generator (ill-conditioned on purpose)
  std::string_view what;
  rc::Gen<Case> gen;
};

const std::vector<Named>& registry();
const Named* find(std::string_view name);

}  // namespace lockstep::props::gen
