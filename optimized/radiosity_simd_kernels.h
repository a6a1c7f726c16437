// lockstep optimized: the Highway radiosity kernel (radiosity_simd_kernels.cpp).
//
// Three kernels: Lambert's point-to-polygon form factor (core/radiosity.h
// point_polygon_form_factor) from one point to many patches at once, in
// double, over the patches as structure of arrays; dispatched at run time to
// the best target the CPU has (HWY_DYNAMIC_DISPATCH); and the solve's row
// gather, sum_j F_ij B_j over the radiosities as structure of arrays; and
// points against a shade (a receiver's targets, a run of its bins at once).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/math.h"

namespace lockstep::opt::simd {

// Patches as structure of arrays, padded to a whole number of vectors with
// patches that face away from everything (their lanes answer 0). A triangle
// repeats its last corner (a zero-length edge adds nothing).
struct PatchSoA {
  size_t count = 0;   // real patches
  size_t padded = 0;  // count rounded up to the widest vector
  std::vector<double> x[4], y[4], z[4];  // corners
  std::vector<double> nx, ny, nz;         // unit normals
};

// F from the point c (unit normal n) to every patch j of p (0 when the patch
// faces away from c, or c is within 1e-9 rad of its plane, as
// centre_form_factor): f[j] for j < p.padded. Lanes whose patch reaches
// behind c's tangent plane (needs clipping) are left to the caller:
// clip[j] = 1 there (f[j] then undefined), else 0.
void lambert_row(const PatchSoA& p, const Vec3& c, const Vec3& n, double* f, unsigned char* clip);

// Row i of the solve, one pass over its form factors f[0..n) and the
// radiosities as structure of arrays (old[c], fresh[c]: channel c, the last
// sweep's and this one's): out[c] = sum_{j<m} f[j] old[c][j], out[3 + c] =
// sum_{j<m} f[j] fresh[c][j], out[6 + c] = sum_{j>=m} f[j] old[c][j].
// Jacobi: m = 0 (fresh not read); Gauss-Seidel: m = i.
void gather_row(const double* f, size_t n, const double* const* old, size_t m, const double* const* fresh,
                double* out);
// The same with the factors in float (the solve's copy, optimized/radiosity_simd.cpp).
void gather_row(const float* f, size_t n, const double* const* old, size_t m, const double* const* fresh,
                double* out);

// A convex polygon in a plane's frame as the half-planes inside its edges:
// a x + b y + c, the distance inside (unit normals), >= 0 for every edge
// (radiosity_simd.cpp: a blocker's shade on a receiver's plane).
struct HalfPlanes {
  int edges = 0;
  double a[10], b[10], c[10];
  // Corners p[0..m) (m <= 10) in either turn; every inside distance raised by grow.
  void set(const std::array<double, 2>* p, int m, double grow) {
    double area = 0;
    for (int k = 0; k < m; ++k) area += p[k][0] * p[(k + 1) % m][1] - p[(k + 1) % m][0] * p[k][1];
    const double turn = area >= 0 ? 1 : -1;  // edge-on (area 0): a sliver, grown
    edges = 0;
    for (int k = 0; k < m; ++k) {
      const auto& u = p[k];
      const auto& v = p[(k + 1) % m];
      const double len = std::hypot(v[0] - u[0], v[1] - u[1]);
      if (!(len > 0)) continue;  // a repeated corner: no edge (the others bound it)
      a[edges] = -(v[1] - u[1]) * turn / len, b[edges] = (v[0] - u[0]) * turn / len;
      c[edges] = -(a[edges] * u[0] + b[edges] * u[1]) + grow;
      ++edges;
    }
  }
  // Whether every inside distance is at least least (a NaN is not).
  bool inside(const std::array<double, 2>& y, double least) const {
    for (int e = 0; e < edges; ++e)
      if (!(a[e] * y[0] + b[e] * y[1] + c[e] >= least)) return false;
    return true;
  }
};

// For points (x[t], y[t]), t < count: verdict[t] = -1 when outside outer
// (an inside distance below 0, or NaN), 1 when inside it and more than deep
// inside core (core.edges > 0), else 0.
void classify_points(const double* x, const double* y, size_t count, const HalfPlanes& outer,
                     const HalfPlanes& core, double deep, signed char* verdict);

}  // namespace lockstep::opt::simd
