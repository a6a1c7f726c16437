// Ray casting kernels, Highway SIMD: 8 rays against one primitive at a time.
//
// Packets of 8 rays (structure of arrays, one ray per lane on AVX2) are tested
// against every candidate sphere and triangle (brute force, primitives
// broadcast one at a time). Highway compiles the kernels for each target
// (AVX2, AVX-512, SSE4, scalar fallback) and dispatches to the best the CPU
// has, as in hwy/examples/skeleton. Only the kernels live here, so that this is
// the one ray-casting file compiled once per target; the scene, the culling and
// the contract functions around them are plain C++ (ray_cast_simd.cpp).
//
// Two differences from the textbook, both on purpose:
//  * Spheres use the numerically stable form of Ray Tracing Gems ch. 7
//    (Haines, Guenther, Akenine-Moeller): the discriminant comes from the
//    squared distance between centre and line, |f - (f.d)d|^2, instead of
//    b^2 - 4ac, and the near root from c/q, so neither far/small spheres nor
//    grazing rays cancel catastrophically.
//  * Triangles use the watertight test of Woop, Benthin and Wald (JCGT 2013):
//    shear the triangle into the ray's space and evaluate the three 2D edge
//    functions exactly the same way for the two triangles sharing an edge, with
//    a double-precision retry when one is exactly zero. A ray through a shared
//    edge or vertex hits exactly one side. (-ffp-contract=off keeps the compiler
//    from fusing these products, which would break the symmetry.)
#include "optimized/ray_cast_simd_kernels.h"

#include <cmath>
#include <utility>

#include "optimized/ray_cast_simd.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "optimized/ray_cast_simd_kernels.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace lockstep::opt::simd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// 8 lanes on AVX2 and AVX-512 (capped), 4 on SSE4, 1 on the scalar fallback.
using DF = hn::CappedTag<float, kPacket>;
using DI = hn::RebindToSigned<DF>;
using VF = hn::Vec<DF>;
using VI = hn::Vec<DI>;
using MF = hn::Mask<DF>;

// Spheres, stable form. f = o - c, b = f.d (|d| = 1), l = f - b d,
// disc = r^2 - l.l, c = f.f - r^2, q = -b - sign(b) sqrt(disc), roots c/q and q.
HWY_INLINE void IntersectSpheres(DF df, const SimdScene& s, const std::vector<uint32_t>& ids, VF ox, VF oy, VF oz, VF dx, VF dy, VF dz,
                                 VF tmin, VF& tbest, VI& best, MF active) {
  const DI di;
  const VF zero = hn::Zero(df);
  const VF inf = hn::Set(df, HUGE_VALF);
  for (const uint32_t i : ids) {
    const VF fx = hn::Sub(ox, hn::Set(df, s.sx[i]));
    const VF fy = hn::Sub(oy, hn::Set(df, s.sy[i]));
    const VF fz = hn::Sub(oz, hn::Set(df, s.sz[i]));
    const VF r2 = hn::Set(df, s.sr2[i]);
    const VF b = hn::MulAdd(fx, dx, hn::MulAdd(fy, dy, hn::Mul(fz, dz)));
    const VF lx = hn::NegMulAdd(b, dx, fx);
    const VF ly = hn::NegMulAdd(b, dy, fy);
    const VF lz = hn::NegMulAdd(b, dz, fz);
    const VF disc = hn::Sub(r2, hn::MulAdd(lx, lx, hn::MulAdd(ly, ly, hn::Mul(lz, lz))));
    const MF hit = hn::And(active, hn::Ge(disc, zero));
    if (hn::AllFalse(df, hit)) continue;  // the whole packet misses: the common case
    const VF c = hn::Sub(hn::MulAdd(fx, fx, hn::MulAdd(fy, fy, hn::Mul(fz, fz))), r2);
    const VF root = hn::Sqrt(hn::Max(disc, zero));
    const VF q = hn::Neg(hn::Add(b, hn::CopySign(root, b)));
    const VF a0 = hn::Div(c, q), a1 = q;
    const VF tnear = hn::Min(a0, a1), tfar = hn::Max(a0, a1);
    VF t;
    if (!s.cull) {
      t = hn::IfThenElse(hn::Gt(tnear, tmin), tnear, tfar);  // nearest root in range
    } else if (!s.s_inside[i]) {
      t = hn::IfThenElse(hn::Gt(c, zero), tnear, inf);  // outside: the entering root; inside: unseen
    } else {
      t = tfar;  // only the inside is visible: the far wall
    }
    const MF take = hn::And(hit, hn::And(hn::Gt(t, tmin), hn::Lt(t, tbest)));
    tbest = hn::IfThenElse(take, t, tbest);
    best = hn::IfThenElse(hn::RebindMask(di, take), hn::Set(di, int32_t(i)), best);
  }
}

// Double-precision retry of one lane's edge functions, when float gave exactly 0.
HWY_NOINLINE void EdgeFunctionsInDouble(DF df, VF Ax, VF Ay, VF Bx, VF By, VF Cx, VF Cy, VF& U, VF& V,
                                        VF& W) {
  HWY_ALIGN float ax[kPacket], ay[kPacket], bx[kPacket], by[kPacket], cx[kPacket], cy[kPacket];
  HWY_ALIGN float u[kPacket], v[kPacket], w[kPacket];
  hn::Store(Ax, df, ax), hn::Store(Ay, df, ay), hn::Store(Bx, df, bx), hn::Store(By, df, by);
  hn::Store(Cx, df, cx), hn::Store(Cy, df, cy);
  hn::Store(U, df, u), hn::Store(V, df, v), hn::Store(W, df, w);
  for (size_t k = 0; k < hn::Lanes(df); ++k) {
    if (u[k] != 0 && v[k] != 0 && w[k] != 0) continue;
    // Products of two floats are exact in double, so these signs are exact.
    u[k] = float(double(cx[k]) * double(by[k]) - double(cy[k]) * double(bx[k]));
    v[k] = float(double(ax[k]) * double(cy[k]) - double(ay[k]) * double(cx[k]));
    w[k] = float(double(bx[k]) * double(ay[k]) - double(by[k]) * double(ax[k]));
  }
  U = hn::Load(df, u), V = hn::Load(df, v), W = hn::Load(df, w);
}

// Triangles, watertight, for the lanes in `active`, all of which share the
// permutation (kx, ky, kz) of the ray's dominant axis.
HWY_INLINE void IntersectTriangles(DF df, const SimdScene& s, const std::vector<uint32_t>& ids, int kx, int ky, int kz, const VF o[3],
                                   const VF d[3], VF tmin, VF& tbest, VI& best, MF active) {
  const DI di;
  const VF zero = hn::Zero(df);
  // Shear constants of the ray: after the shear, the ray runs along +z from the origin.
  const VF Sz = hn::Div(hn::Set(df, 1.0f), d[kz]);
  const VF Sx = hn::Mul(d[kx], Sz);
  const VF Sy = hn::Mul(d[ky], Sz);
  const float* X[3] = {s.tv[0][kx].data(), s.tv[1][kx].data(), s.tv[2][kx].data()};
  const float* Y[3] = {s.tv[0][ky].data(), s.tv[1][ky].data(), s.tv[2][ky].data()};
  const float* Z[3] = {s.tv[0][kz].data(), s.tv[1][kz].data(), s.tv[2][kz].data()};
  const int32_t base = int32_t(s.spheres());
  for (const uint32_t i : ids) {
    MF live = active;
    if (s.cull && !s.t_two_sided[i]) {
      // One-sided: only rays against the plane normal see it (back faces culled).
      const VF dn = hn::MulAdd(d[0], hn::Set(df, s.tn[0][i]),
                               hn::MulAdd(d[1], hn::Set(df, s.tn[1][i]), hn::Mul(d[2], hn::Set(df, s.tn[2][i]))));
      live = hn::And(live, hn::Lt(dn, zero));
      if (hn::AllFalse(df, live)) continue;
    }
    // Vertices relative to the ray origin, then sheared (no FMA: see the header).
    const VF Az = hn::Sub(hn::Set(df, Z[0][i]), o[kz]);
    const VF Bz = hn::Sub(hn::Set(df, Z[1][i]), o[kz]);
    const VF Cz = hn::Sub(hn::Set(df, Z[2][i]), o[kz]);
    const VF Ax = hn::Sub(hn::Sub(hn::Set(df, X[0][i]), o[kx]), hn::Mul(Sx, Az));
    const VF Ay = hn::Sub(hn::Sub(hn::Set(df, Y[0][i]), o[ky]), hn::Mul(Sy, Az));
    const VF Bx = hn::Sub(hn::Sub(hn::Set(df, X[1][i]), o[kx]), hn::Mul(Sx, Bz));
    const VF By = hn::Sub(hn::Sub(hn::Set(df, Y[1][i]), o[ky]), hn::Mul(Sy, Bz));
    const VF Cx = hn::Sub(hn::Sub(hn::Set(df, X[2][i]), o[kx]), hn::Mul(Sx, Cz));
    const VF Cy = hn::Sub(hn::Sub(hn::Set(df, Y[2][i]), o[ky]), hn::Mul(Sy, Cz));
    // Scaled barycentric coordinates: the 2D edge functions.
    VF U = hn::Sub(hn::Mul(Cx, By), hn::Mul(Cy, Bx));
    VF V = hn::Sub(hn::Mul(Ax, Cy), hn::Mul(Ay, Cx));
    VF W = hn::Sub(hn::Mul(Bx, Ay), hn::Mul(By, Ax));
    const MF some_zero = hn::Or(hn::Eq(U, zero), hn::Or(hn::Eq(V, zero), hn::Eq(W, zero)));
    if (!hn::AllFalse(df, hn::And(live, some_zero))) EdgeFunctionsInDouble(df, Ax, Ay, Bx, By, Cx, Cy, U, V, W);
    // Inside when the three have one sign (either winding: culling was done above).
    const MF any_neg = hn::Or(hn::Lt(U, zero), hn::Or(hn::Lt(V, zero), hn::Lt(W, zero)));
    const MF any_pos = hn::Or(hn::Gt(U, zero), hn::Or(hn::Gt(V, zero), hn::Gt(W, zero)));
    live = hn::AndNot(hn::And(any_neg, any_pos), live);
    if (hn::AllFalse(df, live)) continue;
    const VF det = hn::Add(hn::Add(U, V), W);
    const VF T = hn::Add(hn::Add(hn::Mul(U, hn::Mul(Sz, Az)), hn::Mul(V, hn::Mul(Sz, Bz))),
                         hn::Mul(W, hn::Mul(Sz, Cz)));
    const VF t = hn::Div(T, det);
    const MF take = hn::And(hn::And(live, hn::Ne(det, zero)), hn::And(hn::Gt(t, tmin), hn::Lt(t, tbest)));
    tbest = hn::IfThenElse(take, t, tbest);
    best = hn::IfThenElse(hn::RebindMask(di, take), hn::Set(di, base + int32_t(i)), best);
  }
}

void TracePacket(const SimdScene& s, const Candidates& cand, const Packet& p, PacketHits& out) {
  const DF df;
  const DI di;
  const size_t N = hn::Lanes(df);
  for (size_t lane0 = 0; lane0 < size_t(kPacket); lane0 += N) {
    const VF o[3] = {hn::Load(df, p.ox + lane0), hn::Load(df, p.oy + lane0), hn::Load(df, p.oz + lane0)};
    const VF d[3] = {hn::Load(df, p.dx + lane0), hn::Load(df, p.dy + lane0), hn::Load(df, p.dz + lane0)};
    const VF tmin = hn::Load(df, p.tmin + lane0);
    VF tbest = hn::Load(df, p.tmax + lane0);
    VI best = hn::Set(di, -1);
    const VI lane = hn::Add(hn::Iota(di, 0), hn::Set(di, int32_t(lane0)));
    const MF active = hn::RebindMask(df, hn::Lt(lane, hn::Set(di, p.count)));
    if (hn::AllFalse(df, active)) break;
    IntersectSpheres(df, s, cand.spheres, o[0], o[1], o[2], d[0], d[1], d[2], tmin, tbest, best, active);
    if (!cand.triangles.empty()) {
      // The shear needs the axis where |d| is largest, per ray. A packet usually
      // agrees; otherwise each distinct permutation runs with its lanes only.
      const VF ax = hn::Abs(d[0]), ay = hn::Abs(d[1]), az = hn::Abs(d[2]);
      const MF z_dom = hn::And(hn::Ge(az, ax), hn::Ge(az, ay));
      const MF y_dom = hn::AndNot(z_dom, hn::Ge(ay, ax));
      const MF x_dom = hn::AndNot(hn::Or(z_dom, y_dom), active);
      const MF dom[3] = {x_dom, y_dom, z_dom};
      for (int kz = 0; kz < 3; ++kz) {
        for (int neg = 0; neg < 2; ++neg) {
          const MF sign = neg ? hn::Lt(d[kz], hn::Zero(df)) : hn::Ge(d[kz], hn::Zero(df));
          const MF group = hn::And(active, hn::And(dom[kz], sign));
          if (hn::AllFalse(df, group)) continue;
          int kx = (kz + 1) % 3, ky = (kx + 1) % 3;
          if (neg) std::swap(kx, ky);  // keep the winding of the sheared triangle
          IntersectTriangles(df, s, cand.triangles, kx, ky, kz, o, d, tmin, tbest, best, group);
        }
      }
    }
    hn::Store(tbest, df, out.t + lane0);
    hn::Store(best, di, out.id + lane0);
  }
}

// Plane kernel: t = -dist / (n.d) per lane, in float, where dist = n.o + D is
// each ray origin's signed distance to the plane (computed in double by the caller).
void PlaneT(const float* dx, const float* dy, const float* dz, const float* tmin, const float* tmax,
            const float n[3], const float* dist, float* t, size_t count) {
  const DF df;
  const VF nx = hn::Set(df, n[0]), ny = hn::Set(df, n[1]), nz = hn::Set(df, n[2]);
  const VF inf = hn::Set(df, HUGE_VALF);
  for (size_t i = 0; i < count; i += hn::Lanes(df)) {
    const VF den = hn::MulAdd(nx, hn::LoadU(df, dx + i), hn::MulAdd(ny, hn::LoadU(df, dy + i), hn::Mul(nz, hn::LoadU(df, dz + i))));
    const VF tv = hn::Neg(hn::Div(hn::LoadU(df, dist + i), den));
    const MF ok = hn::And(hn::Ne(den, hn::Zero(df)),
                          hn::And(hn::Gt(tv, hn::LoadU(df, tmin + i)), hn::Lt(tv, hn::LoadU(df, tmax + i))));
    hn::StoreU(hn::IfThenElse(ok, tv, inf), df, t + i);
  }
}

// ---------------------------------------------------------------- cones, in double
//
// optimized/ray_cone.h cone_nearest, lane by lane: the same operations in the
// same order (no fused multiply-add but the one std::fma of the discriminant:
// the build has -ffp-contract=off), so every lane's answer is the scalar one
// bit for bit. Only the branches become masks: a lane that the scalar code
// would leave early computes on and is masked out at the end.
using DD = hn::CappedTag<double, kPacket>;
using VD = hn::Vec<DD>;
using MD = hn::Mask<DD>;

struct V3 {
  VD x, y, z;
};
HWY_INLINE VD Dot(const V3& a, const V3& b) {  // (x x + y y) + z z, as core/math.h dot
  return hn::Add(hn::Add(hn::Mul(a.x, b.x), hn::Mul(a.y, b.y)), hn::Mul(a.z, b.z));
}
HWY_INLINE V3 Sub3(const V3& a, const V3& b) {
  return {hn::Sub(a.x, b.x), hn::Sub(a.y, b.y), hn::Sub(a.z, b.z)};
}
HWY_INLINE V3 Add3(const V3& a, const V3& b) {
  return {hn::Add(a.x, b.x), hn::Add(a.y, b.y), hn::Add(a.z, b.z)};
}
HWY_INLINE V3 Scale(VD s, const V3& a) {
  return {hn::Mul(s, a.x), hn::Mul(s, a.y), hn::Mul(s, a.z)};
}

// b b + c with one rounding, as std::fma: MulAdd where the target fuses it;
// SSE4 and SSSE3 have no FMA (Highway's MulAdd there rounds twice), so each
// lane calls std::fma (x86-64-v3's own instruction, or glibc's exact fallback).
HWY_INLINE VD FusedMulAdd(DD dd, VD a, VD b, VD c) {
#if HWY_NATIVE_FMA
  (void)dd;
  return hn::MulAdd(a, b, c);
#else
  HWY_ALIGN double x[kPacket], y[kPacket], z[kPacket];
  hn::Store(a, dd, x), hn::Store(b, dd, y), hn::Store(c, dd, z);
  for (size_t i = 0; i < hn::Lanes(dd); ++i) x[i] = std::fma(x[i], y[i], z[i]);
  return hn::Load(dd, x);
#endif
}

// cone_residual: f(t) and slope f'(t) about the moved origin.
HWY_INLINE VD Residual(const V3& qp, const V3& dp, VD rho, VD kappa, VD t, VD& slope) {
  const DD dd;
  const V3 w = Add3(qp, Scale(t, dp));
  const VD r = hn::Add(rho, hn::Mul(t, kappa));
  slope = hn::Mul(hn::Set(dd, 2.0), hn::Sub(Dot(w, dp), hn::Mul(r, kappa)));
  return hn::Sub(Dot(w, w), hn::Mul(r, r));
}

// One Newton step of cone_roots_stable, kept where it does not make the residual worse.
HWY_INLINE VD Newton(const V3& qp, const V3& dp, VD rho, VD kappa, VD t) {
  const DD dd;
  VD slope, slope2;
  const VD f = Residual(qp, dp, rho, kappa, t, slope);
  const VD step = hn::Div(f, slope);
  const VD better = hn::Sub(t, step);
  const VD f2 = Residual(qp, dp, rho, kappa, better, slope2);
  const MD take = hn::And(hn::And(hn::Ne(slope, hn::Zero(dd)), hn::IsFinite(step)),
                          hn::Le(hn::Abs(f2), hn::Abs(f)));
  return hn::IfThenElse(take, better, t);
}

void ConeT(const ConeShape& c, const ConeRays& r, double* out, size_t count, bool solid) {
  const DD dd;
  const VD zero = hn::Zero(dd);
  const VD inf = hn::Set(dd, HUGE_VAL);
  const V3 centre{hn::Set(dd, c.centre.x), hn::Set(dd, c.centre.y), hn::Set(dd, c.centre.z)};
  const V3 base{hn::Set(dd, c.base.x), hn::Set(dd, c.base.y), hn::Set(dd, c.base.z)};
  const V3 u{hn::Set(dd, c.u.x), hn::Set(dd, c.u.y), hn::Set(dd, c.u.z)};
  const VD bound2 = hn::Set(dd, c.bound * c.bound);
  const VD r0 = hn::Set(dd, c.r0), k = hn::Set(dd, c.k), h = hn::Set(dd, c.h);
  for (size_t i = 0; i < count; i += hn::Lanes(dd)) {
    const V3 o{hn::LoadU(dd, r.ox + i), hn::LoadU(dd, r.oy + i), hn::LoadU(dd, r.oz + i)};
    const V3 d{hn::LoadU(dd, r.dx + i), hn::LoadU(dd, r.dy + i), hn::LoadU(dd, r.dz + i)};
    const VD tmin = hn::LoadU(dd, r.tmin + i), tmax = hn::LoadU(dd, r.tmax + i);
    // Bounding sphere: skip the packet when every ray passes clear of it.
    const VD dd2 = Dot(d, d);
    const V3 f = Sub3(o, centre);
    const VD b0 = hn::Div(Dot(f, d), dd2);
    const V3 perp = Sub3(f, Scale(b0, d));
    MD live = hn::And(hn::Not(hn::Gt(Dot(perp, perp), bound2)), hn::Lt(tmin, tmax));
    if (hn::AllFalse(dd, live)) {
      hn::StoreU(inf, dd, out + i);
      continue;
    }
    // cone_roots_careful: the origin moved along the ray near the centre.
    const VD shift = hn::Div(Dot(Sub3(centre, o), d), dd2);
    const V3 q = Sub3(Add3(o, Scale(shift, d)), base);
    const VD qu = Dot(q, u), du = Dot(d, u);
    const V3 qp = Sub3(q, Scale(qu, u)), dp = Sub3(d, Scale(du, u));
    const VD rho = hn::Add(r0, hn::Mul(k, qu)), kappa = hn::Mul(k, du);
    const VD A = hn::Sub(Dot(dp, dp), hn::Mul(kappa, kappa));
    const VD b = hn::Sub(Dot(qp, dp), hn::Mul(rho, kappa));
    const VD C = hn::Sub(Dot(qp, qp), hn::Mul(rho, rho));
    // cone_roots_stable: A = 0 (parallel to a side line) is linear.
    const MD linear = hn::Eq(A, zero);
    const VD disc = FusedMulAdd(dd, b, b, hn::Neg(hn::Mul(A, C)));
    const MD has_root =
        hn::Or(hn::And(linear, hn::Ne(b, zero)), hn::AndNot(linear, hn::Not(hn::Lt(disc, zero))));
    live = hn::And(live, has_root);
    if (hn::AllFalse(dd, live)) {
      hn::StoreU(inf, dd, out + i);
      continue;
    }
    const VD qq = hn::Neg(hn::Add(b, hn::CopySign(hn::Sqrt(hn::Max(disc, zero)), b)));
    const MD qzero = hn::Eq(qq, zero);
    const VD lin = hn::Div(hn::Neg(C), hn::Mul(hn::Set(dd, 2.0), b));
    VD t0 = hn::IfThenElse(linear, lin, hn::IfThenElseZero(hn::Not(qzero), hn::Div(qq, A)));
    VD t1 = hn::IfThenElse(linear, lin, hn::IfThenElseZero(hn::Not(qzero), hn::Div(C, qq)));
    t0 = Newton(qp, dp, rho, kappa, t0);
    t1 = Newton(qp, dp, rho, kappa, t1);
    const MD swap = hn::Gt(t0, t1);
    const VD lo = hn::IfThenElse(swap, t1, t0), hi = hn::IfThenElse(swap, t0, t1);
    // cone_nearest: the first root in range, on the finite part, on the visible side.
    auto visible = [&](VD t) {
      const VD tl = hn::Sub(t, shift);  // about the moved origin, as the scalar code
      const VD s = hn::Add(qu, hn::Mul(tl, du));
      MD ok = hn::And(hn::And(hn::Gt(t, tmin), hn::Lt(t, tmax)),
                      hn::And(hn::Ge(s, zero), hn::Le(s, h)));
      if (!solid) {
        VD slope;
        Residual(qp, dp, rho, kappa, tl, slope);
        ok = hn::And(ok, c.inside ? hn::Gt(slope, zero) : hn::Lt(slope, zero));
      }
      return ok;
    };
    const VD t_lo = hn::Add(lo, shift), t_hi = hn::Add(hi, shift);
    const MD v0 = hn::And(live, visible(t_lo)), v1 = hn::And(live, visible(t_hi));
    hn::StoreU(hn::IfThenElse(v0, t_lo, hn::IfThenElse(v1, t_hi, inf)), dd, out + i);
  }
}

const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace lockstep::opt::simd
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace lockstep::opt::simd {

HWY_EXPORT(TracePacket);
HWY_EXPORT(PlaneT);
HWY_EXPORT(ConeT);
HWY_EXPORT(TargetName);

void trace_packet(const SimdScene& s, const Candidates& cand, const Packet& p, PacketHits& out) {
  HWY_DYNAMIC_DISPATCH(TracePacket)(s, cand, p, out);
}

void plane_t(const float* dx, const float* dy, const float* dz, const float* tmin, const float* tmax,
             const float n[3], const float* dist, float* t, size_t count) {
  HWY_DYNAMIC_DISPATCH(PlaneT)(dx, dy, dz, tmin, tmax, n, dist, t, count);
}

void cone_t(const ConeShape& c, const ConeRays& r, double* t, size_t count, bool solid) {
  HWY_DYNAMIC_DISPATCH(ConeT)(c, r, t, count, solid);
}

const char* target_name() { return HWY_DYNAMIC_DISPATCH(TargetName)(); }

}  // namespace lockstep::opt::simd
#endif  // HWY_ONCE
