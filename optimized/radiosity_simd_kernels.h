// lockstep optimized: the Highway radiosity kernel (radiosity_simd_kernels.cpp).
//
// Two kernels: Lambert's point-to-polygon form factor (core/radiosity.h
// point_polygon_form_factor) from one point to many patches at once, in
// double, over the patches as structure of arrays; dispatched at run time to
// the best target the CPU has (HWY_DYNAMIC_DISPATCH); and the solve's row
// gather, sum_j F_ij B_j over the radiosities as structure of arrays.
#pragma once

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

}  // namespace lockstep::opt::simd
