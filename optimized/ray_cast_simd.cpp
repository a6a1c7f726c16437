// Ray casting, optimized with Highway SIMD and TBB.
//
// Packets of 8 rays (structure of arrays, one ray per lane on AVX2) are tested
// against every sphere and triangle of the scene (brute force, primitives
// broadcast one at a time); screen tiles are spread over the cores with TBB.
// Highway compiles the kernels for each target (AVX2, AVX-512, SSE4, scalar
// fallback) and dispatches to the best the CPU has, as in hwy/examples/skeleton.
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
#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>

#include "core/camera.h"
#include "optimized/ray_cast.h"
#include "core/shading.h"
#include "optimized/refine.h"
#include "optimized/shade_simd.h"
#include "optimized/simd_scene.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "optimized/ray_cast_simd.cpp"
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

const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace lockstep::opt::simd
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace lockstep::opt::simd {

HWY_EXPORT(TracePacket);
HWY_EXPORT(PlaneT);
HWY_EXPORT(TargetName);

const char* target_name() { return HWY_DYNAMIC_DISPATCH(TargetName)(); }

// ---------------------------------------------------------------- scene preparation
void SimdScene::add_sphere(const Vec3& c, double r, uint32_t prim) {
  const Vec3 cf = frame.point(c);
  sx.push_back(float(cf.x));
  sy.push_back(float(cf.y));
  sz.push_back(float(cf.z));
  const float rf = float(std::abs(r));
  sr2.push_back(rf * rf);
  s_inside.push_back(r < 0);
  s_prim.push_back(prim);
  // Spheres come before triangles in the bounds arrays.
  b_center.insert(b_center.begin() + long(spheres() - 1), cf);
  b_radius.insert(b_radius.begin() + long(spheres() - 1), std::abs(r));
}

void SimdScene::add_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n, bool two_sided,
                             uint32_t prim, uint32_t tri) {
  const Vec3 v[3] = {frame.point(a), frame.point(b), frame.point(c)};
  for (int k = 0; k < 3; ++k)
    for (int ax = 0; ax < 3; ++ax) tv[k][ax].push_back(float(v[k][ax]));
  const Vec3 nf = frame.dir(n);
  for (int ax = 0; ax < 3; ++ax) tn[ax].push_back(float(nf[ax]));
  t_two_sided.push_back(two_sided);
  t_prim.push_back(prim);
  t_tri.push_back(tri);
  const Vec3 centroid = (v[0] + v[1] + v[2]) / 3.0;
  b_center.push_back(centroid);
  b_radius.push_back(std::max({length(v[0] - centroid), length(v[1] - centroid), length(v[2] - centroid)}));
}

Candidates all_candidates(const SimdScene& s) {
  Candidates c;
  c.spheres.resize(s.spheres());
  c.triangles.resize(s.triangles());
  for (size_t i = 0; i < c.spheres.size(); ++i) c.spheres[i] = uint32_t(i);
  for (size_t i = 0; i < c.triangles.size(); ++i) c.triangles[i] = uint32_t(i);
  return c;
}

SimdScene prepare_scene(const Scene& scene, const Frame& frame, bool cull) {
  SimdScene s;
  s.frame = frame;
  s.cull = cull;
  for (uint32_t i = 0; i < scene.sphere_count(); ++i)
    s.add_sphere(scene.sphere_center[i], scene.sphere_radius[i], i);
  for (uint32_t k = 0; k < scene.triangle_count(); ++k) {
    const uint32_t poly = scene.tri_poly[k];
    const auto& t = scene.tri_vertex[k];
    s.add_triangle(scene.vertex[t[0]], scene.vertex[t[1]], scene.vertex[t[2]], scene.poly_plane[poly].n,
                   scene.materials[scene.poly_material[poly]].two_sided(), scene.sphere_count() + poly, k);
  }
  return s;
}

namespace {

// Puts ray k of a packet into the frame: unit direction, t range rescaled.
void load_ray(const Frame& f, const Ray& r, Packet& p, int k, double& scale) {
  const Vec3 o = f.point(r.o);
  const Vec3 d = f.dir(r.d);
  const double len = length(d);
  p.ox[k] = float(o.x), p.oy[k] = float(o.y), p.oz[k] = float(o.z);
  p.dx[k] = float(d.x / len), p.dy[k] = float(d.y / len), p.dz[k] = float(d.z / len);
  p.tmin[k] = float(r.tmin * len);
  p.tmax[k] = r.tmax * len < 3e38 ? float(r.tmax * len) : HUGE_VALF;
  scale = len;
}

void clear_tail(Packet& p) {
  for (int k = p.count; k < kPacket; ++k) {
    p.ox[k] = p.oy[k] = p.oz[k] = 0;
    p.dx[k] = p.dy[k] = 0;
    p.dz[k] = 1;
    p.tmin[k] = 0;
    p.tmax[k] = 0;
  }
}

Hit to_hit(const SimdScene& s, float t, int32_t id, double scale) {
  Hit h;
  if (id < 0) return h;
  h.t = double(t) / scale;
  if (size_t(id) < s.spheres()) {
    h.prim = s.s_prim[size_t(id)];
  } else {
    h.prim = s.t_prim[size_t(id) - s.spheres()];
    h.tri = s.t_tri[size_t(id) - s.spheres()];
  }
  return h;
}

// Traces rays through a prepared scene, packets of 8, serially.
void trace_prepared(const SimdScene& s, const Candidates& cand, std::span<const Ray> rays, std::span<Hit> hits) {
  Packet p;
  PacketHits out;
  double scale[kPacket];
  for (size_t i = 0; i < rays.size(); i += kPacket) {
    p.count = int(std::min<size_t>(kPacket, rays.size() - i));
    for (int k = 0; k < p.count; ++k) load_ray(s.frame, rays[i + size_t(k)], p, k, scale[k]);
    clear_tail(p);
    HWY_DYNAMIC_DISPATCH(TracePacket)(s, cand, p, out);
    for (int k = 0; k < p.count; ++k) hits[i + size_t(k)] = to_hit(s, out.t[k], out.id[k], scale[k]);
  }
}

// Kernel calls: one primitive against packets of rays with different origins.
// The frame's origin is the primitive's anchor (sphere centre, scene vertex), so
// every ray keeps the precision of "primitive-relative" coordinates (as good as
// camera-relative: the offset between ray origin and primitive is rounded to
// float once) and its result does not depend on the other rays in its packet.
// The scene is built once; only the rays change per packet.
template <class AddPrims>
void kernel(std::span<const Ray> rays, std::span<double> t, const Vec3& anchor, AddPrims add) {
  SimdScene s;
  s.cull = false;
  s.frame.origin = anchor;
  add(s);
  const Candidates cand = all_candidates(s);
  Packet p;
  PacketHits out;
  double scale[kPacket];
  for (size_t i = 0; i < rays.size(); i += kPacket) {
    const size_t n = std::min<size_t>(kPacket, rays.size() - i);
    p.count = int(n);
    for (size_t k = 0; k < n; ++k) load_ray(s.frame, rays[i + k], p, int(k), scale[k]);
    clear_tail(p);
    HWY_DYNAMIC_DISPATCH(TracePacket)(s, cand, p, out);
    for (size_t k = 0; k < n; ++k) t[i + k] = out.id[k] < 0 ? kInfinity : double(out.t[k]) / scale[k];
  }
}

// ---------------------------------------------------------------- per-tile culling
// All primary rays start at the eye (the frame's origin), so a tile's rays lie
// inside a cone around the tile's central direction. A primitive whose bounding
// sphere (seen from the eye under half-angle beta) is further than alpha + beta
// from the cone's axis cannot be hit by any of them: the packets of that tile
// skip it. Conservative by a margin well above float's direction error.
struct ConeBounds {
  std::vector<Vec3> dir;              // unit direction from the eye to the bounding centre
  std::vector<double> beta;           // angular radius of the bounding sphere
  std::vector<uint8_t> contains_eye;  // the eye is inside: always a candidate
};

ConeBounds cone_bounds(const SimdScene& s) {
  ConeBounds cb;
  const size_t n = s.b_center.size();
  cb.dir.resize(n);
  cb.beta.resize(n);
  cb.contains_eye.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const double dist = length(s.b_center[i]);
    const double r = s.b_radius[i] * (1 + 1e-6) + 1e-30;
    cb.contains_eye[i] = dist <= r;
    if (cb.contains_eye[i]) continue;
    cb.dir[i] = s.b_center[i] / dist;
    cb.beta[i] = std::asin(r / dist);
  }
  return cb;
}

void cull_tile(const SimdScene& s, const ConeBounds& cb, const Camera& cam, int i0, int i1, int j0, int j1,
               Candidates& out) {
  out.spheres.clear();
  out.triangles.clear();
  // Cone through the tile's four corner pixel centres (the directions of all
  // pixels in between lie in their convex hull on the image plane).
  const Vec3 corner[4] = {normalize(cam.camera_dir(i0, j0)), normalize(cam.camera_dir(i1 - 1, j0)),
                          normalize(cam.camera_dir(i0, j1 - 1)), normalize(cam.camera_dir(i1 - 1, j1 - 1))};
  const Vec3 axis = normalize(corner[0] + corner[1] + corner[2] + corner[3]);
  double cos_alpha = 1;
  for (const Vec3& c : corner) cos_alpha = std::min(cos_alpha, dot(axis, c));
  const double alpha = std::acos(std::clamp(cos_alpha, -1.0, 1.0)) + 1e-5;
  const size_t ns = s.spheres();
  for (size_t i = 0; i < cb.dir.size(); ++i) {
    bool keep = cb.contains_eye[i] != 0;
    if (!keep) {
      const double reach = alpha + cb.beta[i];
      keep = reach >= M_PI || dot(axis, cb.dir[i]) >= std::cos(reach);
    }
    if (!keep) continue;
    if (i < ns) out.spheres.push_back(uint32_t(i));
    else out.triangles.push_back(uint32_t(i - ns));
  }
}

}  // namespace

// ---------------------------------------------------------------- the contract
void ray_sphere(std::span<const Ray> rays, const Sphere& sphere, std::span<double> t) {
  kernel(rays, t, sphere.center, [&](SimdScene& s) { s.add_sphere(sphere.center, sphere.radius, 0); });
}

void ray_polygon(std::span<const Ray> rays, const Scene& scene, uint32_t poly, std::span<double> t) {
  // The anchor is the scene's first vertex, the same for every polygon of the
  // scene: two polygons sharing an edge then round it to the same floats, which
  // watertightness needs.
  const uint32_t first = scene.poly_tri_first[poly];
  kernel(rays, t, scene.vertex.empty() ? Vec3{0, 0, 0} : scene.vertex[0], [&](SimdScene& s) {
    for (uint32_t k = first; k < scene.poly_tri_first[poly + 1]; ++k) {
      const auto& v = scene.tri_vertex[k];
      s.add_triangle(scene.vertex[v[0]], scene.vertex[v[1]], scene.vertex[v[2]], scene.poly_plane[poly].n,
                     true, 0, k);
    }
  });
}

void ray_plane(std::span<const Ray> rays, const Plane& plane, std::span<double> t) {
  // Each ray in its own frame (origin at the ray's origin): the plane's offset
  // becomes the origin's signed distance n.o + D, computed in double per ray, so
  // a plane far from the world origin costs no precision.
  const float nf[3] = {float(plane.n.x), float(plane.n.y), float(plane.n.z)};
  for (size_t i = 0; i < rays.size(); i += kPacket) {
    const size_t n = std::min<size_t>(kPacket, rays.size() - i);
    Packet p;
    alignas(32) float dist[kPacket] = {};
    double scale[kPacket];
    p.count = int(n);
    for (size_t k = 0; k < n; ++k) {
      Frame f;
      f.origin = rays[i + k].o;
      load_ray(f, rays[i + k], p, int(k), scale[k]);
      dist[k] = float(plane.d + dot(plane.n, rays[i + k].o));
    }
    clear_tail(p);
    alignas(32) float out[kPacket];
    HWY_DYNAMIC_DISPATCH(PlaneT)(p.dx, p.dy, p.dz, p.tmin, p.tmax, nf, dist, out, kPacket);
    for (size_t k = 0; k < n; ++k) t[i + k] = std::isinf(out[k]) ? kInfinity : double(out[k]) / scale[k];
  }
}

void trace(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, FrameStats* stats) {
  Frame f;
  if (!rays.empty()) f.origin = rays[0].o;
  const SimdScene s = prepare_scene(scene, f, true);
  const Candidates all = all_candidates(s);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, (rays.size() + kPacket - 1) / kPacket, 64),
                    [&](const tbb::blocked_range<size_t>& r) {
                      const size_t lo = r.begin() * kPacket, hi = std::min(rays.size(), r.end() * kPacket);
                      trace_prepared(s, all, rays.subspan(lo, hi - lo), hits.subspan(lo, hi - lo));
                    });
  for (size_t i = 0; i < rays.size(); ++i) refine_hit(scene, rays[i], hits[i]);
  if (stats) {
    stats->items = rays.size();
  }
}

Image render(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  const Camera cam = Camera::from_view(scene.view, opts.width, opts.height);
  // The camera's own frame: eye at the origin, x right, y up, z forward.
  const Frame frame{cam.eye, cam.right, cam.up, cam.forward};
  const SimdScene s = prepare_scene(scene, frame, true);
  const ConeBounds cb = cone_bounds(s);
  const ShadeScene shading = prepare_shading(scene, frame);
  Image image(opts.width, opts.height);
  constexpr int kTileW = 32, kTileH = 8;
  const int tiles_x = (opts.width + kTileW - 1) / kTileW, tiles_y = (opts.height + kTileH - 1) / kTileH;
  std::atomic<int> done{0};
  std::mutex progress_mutex;
  auto render_tile = [&](int tx, int ty) {
    Packet p;
    PacketHits out;
    ShadePacket sp{};
    Candidates cand;
    cull_tile(s, cb, cam, tx * kTileW, std::min(opts.width, (tx + 1) * kTileW), ty * kTileH,
              std::min(opts.height, (ty + 1) * kTileH), cand);
    for (int j = ty * kTileH; j < std::min(opts.height, (ty + 1) * kTileH); ++j) {
      for (int i0 = tx * kTileW; i0 < std::min(opts.width, (tx + 1) * kTileW); i0 += kPacket) {
        p.count = std::min(kPacket, opts.width - i0);
        Vec3 unit[kPacket];
        for (int k = 0; k < p.count; ++k) {
          // Camera-space direction (sx, sy, 1), normalised in double then rounded.
          const Vec3 d = cam.camera_dir(i0 + k, j);
          const double len = length(d);
          unit[k] = d / len;
          p.ox[k] = p.oy[k] = p.oz[k] = 0;
          p.dx[k] = float(unit[k].x), p.dy[k] = float(unit[k].y), p.dz[k] = float(unit[k].z);
          p.tmin[k] = float(cam.hither * len);
          p.tmax[k] = HUGE_VALF;
        }
        clear_tail(p);
        HWY_DYNAMIC_DISPATCH(TracePacket)(s, cand, p, out);
        for (int k = 0; k < p.count; ++k) {
          // The same unit ray in world space (t carries over: both are unit length).
          const Vec3& u = unit[k];
          const Ray ray{cam.eye, u.x * cam.right + u.y * cam.up + u.z * cam.forward, 0.0, kInfinity};
          Hit h = to_hit(s, out.t[k], out.id[k], 1.0);
          refine_far_sphere_hit(scene, ray, h);
          fill_lane(scene, frame, ray, h, sp, k);
        }
        for (int k = p.count; k < kPacket; ++k) sp.hit[k] = 0;
        shade_packet(shading, sp);
        for (int k = 0; k < p.count; ++k) image.set(i0 + k, j, Vec3{sp.r[k], sp.g[k], sp.b[k]});
      }
    }
    const int n = ++done;
    if (opts.progress && (n % 16 == 0 || n == tiles_x * tiles_y)) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      opts.progress(double(n) / (tiles_x * tiles_y));
    }
  };
  const int threads = opts.threads > 0 ? opts.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range2d<int>(0, tiles_y, 1, 0, tiles_x, 1),
                      [&](const tbb::blocked_range2d<int>& r) {
                        for (int ty = r.rows().begin(); ty < r.rows().end(); ++ty)
                          for (int tx = r.cols().begin(); tx < r.cols().end(); ++tx) render_tile(tx, ty);
                      });
  });
  if (stats) {
    stats->items = uint64_t(opts.width) * uint64_t(opts.height);
  }
  return image;
}

}  // namespace lockstep::opt::simd
#endif  // HWY_ONCE
