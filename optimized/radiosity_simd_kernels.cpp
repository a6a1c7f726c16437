// lockstep optimized: Lambert's form factor over many patches (radiosity_simd_kernels.h).
//
// Per lane (one patch j), the reference's steps (core/radiosity.cpp
// point_polygon_form_factor): for each edge (p_k, p_k+1) with r0 = p_k - c,
// r1 = p_k+1 - c, the angle gamma = atan2(|r0 x r1|, r0 . r1) it subtends at
// c and the unit normal of the plane through c and the edge; F = |sum gamma
// n . (r0 x r1) / |r0 x r1|| / (2 pi). Highway 1.0 has no Atan2: for
// len >= 0, atan2(len, d) is atan(min/max) or pi/2 minus it, mirrored to
// pi - that for d < 0 (Highway's Atan: 3 ULP).
#include "optimized/radiosity_simd_kernels.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "optimized/mask_bytes.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "optimized/radiosity_simd_kernels.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "hwy/contrib/math/math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace lockstep::opt::simd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void LambertRow(const PatchSoA& p, const Vec3& c, const Vec3& n, double* f, unsigned char* clip) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const size_t L = hn::Lanes(d);
  const V cx = hn::Set(d, c.x), cy = hn::Set(d, c.y), cz = hn::Set(d, c.z);
  const V nx = hn::Set(d, n.x), ny = hn::Set(d, n.y), nz = hn::Set(d, n.z);
  const V zero = hn::Zero(d), half_pi = hn::Set(d, M_PI / 2), pi = hn::Set(d, M_PI);
  for (size_t j = 0; j < p.padded; j += L) {
    V rx[4], ry[4], rz[4];
    for (int k = 0; k < 4; ++k) {
      rx[k] = hn::Sub(hn::LoadU(d, p.x[k].data() + j), cx);
      ry[k] = hn::Sub(hn::LoadU(d, p.y[k].data() + j), cy);
      rz[k] = hn::Sub(hn::LoadU(d, p.z[k].data() + j), cz);
    }
    // j sends nothing to a point behind or (within 1e-9 rad) in its plane:
    // its normal . (c - p_0) > 1e-9 |c - p_0|.
    const V qx = hn::LoadU(d, p.nx.data() + j), qy = hn::LoadU(d, p.ny.data() + j), qz = hn::LoadU(d, p.nz.data() + j);
    const V facing = hn::Neg(hn::Add(hn::Add(hn::Mul(qx, rx[0]), hn::Mul(qy, ry[0])), hn::Mul(qz, rz[0])));
    const V dist = hn::Sqrt(hn::Add(hn::Add(hn::Mul(rx[0], rx[0]), hn::Mul(ry[0], ry[0])), hn::Mul(rz[0], rz[0])));
    const auto sends = hn::Gt(facing, hn::Mul(hn::Set(d, 1e-9), dist));
    // Corners behind c's tangent plane: the reference clips; the caller does.
    auto behind = hn::FirstN(d, 0);
    for (int k = 0; k < 4; ++k) {
      const V h = hn::Add(hn::Add(hn::Mul(nx, rx[k]), hn::Mul(ny, ry[k])), hn::Mul(nz, rz[k]));
      behind = hn::Or(behind, hn::Lt(h, zero));
    }
    V sum = zero;
    for (int k = 0; k < 4; ++k) {
      const int k1 = (k + 1) & 3;
      const V ex = hn::Sub(hn::Mul(ry[k], rz[k1]), hn::Mul(rz[k], ry[k1]));
      const V ey = hn::Sub(hn::Mul(rz[k], rx[k1]), hn::Mul(rx[k], rz[k1]));
      const V ez = hn::Sub(hn::Mul(rx[k], ry[k1]), hn::Mul(ry[k], rx[k1]));
      const V len = hn::Sqrt(hn::Add(hn::Add(hn::Mul(ex, ex), hn::Mul(ey, ey)), hn::Mul(ez, ez)));
      const V dt = hn::Add(hn::Add(hn::Mul(rx[k], rx[k1]), hn::Mul(ry[k], ry[k1])), hn::Mul(rz[k], rz[k1]));
      // gamma = atan2(len, dt) in [0, pi].
      const V a = hn::Abs(dt);
      const V lo = hn::Min(len, a), hi = hn::Max(len, a);
      const auto some = hn::Gt(hi, zero);
      const V t = hn::Atan(d, hn::IfThenElse(some, hn::Div(lo, hn::IfThenElse(some, hi, hn::Set(d, 1))), zero));
      const V first = hn::IfThenElse(hn::Le(len, a), t, hn::Sub(half_pi, t));
      const V gamma = hn::IfThenElse(hn::Lt(dt, zero), hn::Sub(pi, first), first);
      const V nd = hn::Add(hn::Add(hn::Mul(nx, ex), hn::Mul(ny, ey)), hn::Mul(nz, ez));
      const auto edge = hn::Gt(len, zero);  // an edge through c's line of sight: no area
      sum = hn::Add(sum, hn::IfThenElseZero(edge, hn::Div(hn::Mul(gamma, nd), hn::IfThenElse(edge, len, hn::Set(d, 1)))));
    }
    const V F = hn::IfThenElseZero(sends, hn::Mul(hn::Abs(sum), hn::Set(d, 1 / (2 * M_PI))));
    hn::StoreU(F, d, f + j);
    const auto needs_clip = hn::And(sends, behind);
    for (size_t l = 0; l < L; ++l) clip[j + l] = 0;
    if (!hn::AllFalse(d, needs_clip)) {
      alignas(64) double m[HWY_MAX_BYTES / sizeof(double)];
      hn::Store(hn::IfThenElseZero(needs_clip, hn::Set(d, 1)), d, m);
      for (size_t l = 0; l < L; ++l) clip[j + l] = m[l] != 0;
    }
  }
}

// Row i's gathers in one pass over its form factors (radiosity_simd_kernels.h),
// the factors in double or in float (promoted as they are loaded).
template <class T>
HWY_INLINE void GatherRowOf(const T* f, size_t n, const double* const* old, size_t m, const double* const* fresh,
                            double* out) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const size_t L = hn::Lanes(d);
  auto load = [&](size_t j) {
    if constexpr (std::is_same_v<T, float>) return hn::PromoteTo(d, hn::LoadU(hn::Rebind<float, decltype(d)>(), f + j));
    else return hn::LoadU(d, f + j);
  };
  V pre_old[3] = {hn::Zero(d), hn::Zero(d), hn::Zero(d)}, pre_new[3] = {hn::Zero(d), hn::Zero(d), hn::Zero(d)};
  V post[3] = {hn::Zero(d), hn::Zero(d), hn::Zero(d)};
  double rest[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  size_t j = 0;
  for (; j + L <= m; j += L) {
    const V w = load(j);
    for (int c = 0; c < 3; ++c) {
      pre_old[c] = hn::MulAdd(w, hn::LoadU(d, old[c] + j), pre_old[c]);
      pre_new[c] = hn::MulAdd(w, hn::LoadU(d, fresh[c] + j), pre_new[c]);
    }
  }
  for (; j < m; ++j)
    for (int c = 0; c < 3; ++c) rest[c] += double(f[j]) * old[c][j], rest[3 + c] += double(f[j]) * fresh[c][j];
  for (; j + L <= n; j += L) {
    const V w = load(j);
    for (int c = 0; c < 3; ++c) post[c] = hn::MulAdd(w, hn::LoadU(d, old[c] + j), post[c]);
  }
  for (; j < n; ++j)
    for (int c = 0; c < 3; ++c) rest[6 + c] += double(f[j]) * old[c][j];
  for (int c = 0; c < 3; ++c) {
    out[c] = hn::GetLane(hn::SumOfLanes(d, pre_old[c])) + rest[c];
    out[3 + c] = hn::GetLane(hn::SumOfLanes(d, pre_new[c])) + rest[3 + c];
    out[6 + c] = hn::GetLane(hn::SumOfLanes(d, post[c])) + rest[6 + c];
  }
}

void GatherRow(const double* f, size_t n, const double* const* old, size_t m, const double* const* fresh,
               double* out) {
  GatherRowOf(f, n, old, m, fresh, out);
}

void GatherRowSingle(const float* f, size_t n, const double* const* old, size_t m, const double* const* fresh,
                     double* out) {
  GatherRowOf(f, n, old, m, fresh, out);
}

// Points against a shade (radiosity_simd_kernels.h): the least inside
// distance over outer's edges and over core's, a vector of points at a time.
void ClassifyPoints(const double* x, const double* y, size_t count, const HalfPlanes& outer, const HalfPlanes& core,
                    double deep, signed char* verdict) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const size_t L = hn::Lanes(d);
  const V zero = hn::Zero(d), dv = hn::Set(d, deep);
  size_t t = 0;
  for (; t + L <= count; t += L) {
    const V px = hn::LoadU(d, x + t), py = hn::LoadU(d, y + t);
    auto in = hn::FirstN(d, L);
    for (int e = 0; e < outer.edges; ++e)
      in = hn::And(in, hn::Ge(hn::MulAdd(hn::Set(d, outer.a[e]), px, hn::MulAdd(hn::Set(d, outer.b[e]), py,
                                                                                 hn::Set(d, outer.c[e]))),
                              zero));
    auto deep_in = hn::FirstN(d, core.edges > 0 ? L : 0);
    for (int e = 0; e < core.edges; ++e)
      deep_in = hn::And(deep_in, hn::Gt(hn::MulAdd(hn::Set(d, core.a[e]), px, hn::MulAdd(hn::Set(d, core.b[e]), py,
                                                                                          hn::Set(d, core.c[e]))),
                                        dv));
    // -1 (0xff) outside, 1 deep in the core, else 0: from the masks' bits,
    // a byte a lane.
    uint8_t in_bits[8] = {}, deep_bits[8] = {};
    hn::StoreMaskBits(d, in, in_bits);
    hn::StoreMaskBits(d, hn::And(in, deep_in), deep_bits);
    const uint64_t bytes = ((bits_to_bytes(in_bits[0]) ^ 0x0101010101010101ull) * 0xff) | bits_to_bytes(deep_bits[0]);
    std::memcpy(verdict + t, &bytes, L);
  }
  for (; t < count; ++t) {
    const std::array<double, 2> p{x[t], y[t]};
    verdict[t] = !outer.inside(p, 0) ? -1 : core.edges > 0 && core.inside(p, deep) ? 1 : 0;
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace lockstep::opt::simd
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace lockstep::opt::simd {

HWY_EXPORT(LambertRow);
HWY_EXPORT(GatherRow);
HWY_EXPORT(GatherRowSingle);
HWY_EXPORT(ClassifyPoints);

void lambert_row(const PatchSoA& p, const Vec3& c, const Vec3& n, double* f, unsigned char* clip) {
  HWY_DYNAMIC_DISPATCH(LambertRow)(p, c, n, f, clip);
}

void classify_points(const double* x, const double* y, size_t count, const HalfPlanes& outer,
                     const HalfPlanes& core, double deep, signed char* verdict) {
  HWY_DYNAMIC_DISPATCH(ClassifyPoints)(x, y, count, outer, core, deep, verdict);
}

void gather_row(const double* f, size_t n, const double* const* old, size_t m, const double* const* fresh,
                double* out) {
  HWY_DYNAMIC_DISPATCH(GatherRow)(f, n, old, m, fresh, out);
}

void gather_row(const float* f, size_t n, const double* const* old, size_t m, const double* const* fresh,
                double* out) {
  HWY_DYNAMIC_DISPATCH(GatherRowSingle)(f, n, old, m, fresh, out);
}

}  // namespace lockstep::opt::simd
#endif  // HWY_ONCE
