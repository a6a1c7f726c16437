// The oracle: exact rational decisions (CGAL::Gmpq), t through MPFR at 256 bits.
// This is the only translation unit that includes CGAL.
#include "props/ray_cast/oracle.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>  // glibc's bits/floatn.h: _Float128 is __float128 in C++ before GCC 13

#define MPFR_WANT_FLOAT128 1
#include <mpfr.h>
#include <quadmath.h>

#include <CGAL/Gmpq.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/Simple_cartesian.h>

namespace lockstep::props::ray_cast {

namespace {

using Q = CGAL::Gmpq;
using K = CGAL::Simple_cartesian<Q>;
using LD = long double;

// ---------------------------------------------------------------- exact vectors
struct Q3 {
  Q x, y, z;
  const Q& operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};
Q3 q3(const Vec3& v) { return {Q(v.x), Q(v.y), Q(v.z)}; }
Q3 operator-(const Q3& a, const Q3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Q3 operator+(const Q3& a, const Q3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Q3 operator*(const Q3& a, const Q& s) { return {a.x * s, a.y * s, a.z * s}; }
Q dotq(const Q3& a, const Q3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
bool is_zero(const Q3& a) { return CGAL::is_zero(a.x) && CGAL::is_zero(a.y) && CGAL::is_zero(a.z); }

// ---------------------------------------------------------------- MPFR at 256 bits
class Mp {
 public:
  Mp() { mpfr_init2(v_, 256); }
  explicit Mp(const Q& q) : Mp() { mpfr_set_q(v_, q.mpq(), MPFR_RNDN); }
  Mp(const Mp&) = delete;
  Mp& operator=(const Mp&) = delete;
  ~Mp() { mpfr_clear(v_); }
  mpfr_ptr get() { return v_; }
  mpfr_srcptr get() const { return v_; }
  f128 f() const { return mpfr_get_float128(v_, MPFR_RNDN); }

 private:
  mpfr_t v_;
};

f128 to_f128(const Q& q) { return Mp(q).f(); }
LD to_ld(const Q& q) { return LD(Mp(q).f()); }

// The roots of A t^2 + 2 Bh t + C = 0, given its exact discriminant Dq = Bh^2 -
// A C >= 0, in ascending order: the stable form (q = -(Bh + sign(Bh) sqrt(Dq)),
// roots q / A and C / q, so no root comes from a cancelling difference) at 256
// bits, rounded to f128. Both 0 when q = 0 (Bh = Dq = 0, then C = 0: the
// double root t = 0).
void stable_roots(const Q& A, const Q& Bh, const Q& Dq, const Q& C, f128& t0, f128& t1) {
  Mp mA(A), mB(Bh), mD(Dq), mC(C), s, q, ra, rb;
  mpfr_sqrt(s.get(), mD.get(), MPFR_RNDN);
  if (mpfr_sgn(mB.get()) >= 0) {
    mpfr_add(q.get(), mB.get(), s.get(), MPFR_RNDN);
    mpfr_neg(q.get(), q.get(), MPFR_RNDN);
  } else {
    mpfr_sub(q.get(), s.get(), mB.get(), MPFR_RNDN);
  }
  t0 = t1 = 0;
  if (mpfr_zero_p(q.get())) return;
  mpfr_div(ra.get(), q.get(), mA.get(), MPFR_RNDN);
  mpfr_div(rb.get(), mC.get(), q.get(), MPFR_RNDN);
  const f128 a = ra.f(), b = rb.f();
  t0 = a < b ? a : b;
  t1 = a < b ? b : a;
}

// ---------------------------------------------------------------- approximate vectors for conditioning
struct L3 {
  LD x, y, z;
};
L3 l3(const Vec3& v) { return {v.x, v.y, v.z}; }
L3 l3(const Q3& v) { return {to_ld(v.x), to_ld(v.y), to_ld(v.z)}; }
LD dotl(const L3& a, const L3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
LD norml(const L3& a) { return std::sqrt(dotl(a, a)); }
L3 crossl(const L3& a, const L3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
LD abssum(const L3& a, const L3& b) { return std::fabs(a.x * b.x) + std::fabs(a.y * b.y) + std::fabs(a.z * b.z); }

// Accumulates a condition number as a sum of labelled terms and a margin as a
// minimum of labelled margins.
struct CondBuilder {
  Conditioning c;
  LD biggest = 0;
  void kappa(LD v, const char* why) {
    if (!(v >= 0)) v = INFINITY;  // NaN: treat as unbounded
    c.kappa = double(LD(c.kappa) + v);
    if (v > biggest && why[0]) {
      biggest = v;
      c.kappa_why = why;
    }
  }
  void margin(LD m, const char* why) {
    if (!(m >= 0)) m = 0;
    if (double(m) < c.margin) {
      c.margin = double(m);
      c.margin_why = why;
    }
  }
};

// Root k (0: -sqrt, 1: +sqrt) of A t^2 + 2 Bh t + C = 0 with A > 0, Dq = Bh^2 - A C >= 0,
// compared exactly with x: returns -1, 0, 1 for root < x, ==, >.
int compare_root(int k, const Q& A, const Q& Bh, const Q& Dq, double x) {
  // root_k = (-Bh + s sqrt(Dq)) / A, s = -1 or +1; root_k ? x  <=>  s sqrt(Dq) ? w, w = A x + Bh.
  const Q w = A * Q(x) + Bh;
  const Q w2 = w * w;
  const int sw = CGAL::sign(w);
  if (k == 1) {  // sqrt(Dq) ? w
    if (sw < 0) return 1;
    const int c = CGAL::compare(Dq, w2);
    return c;  // Dq vs w^2 decides sqrt(Dq) vs w >= 0
  }
  // -sqrt(Dq) ? w   <=>   sqrt(Dq) ? -w, reversed
  if (sw > 0) return -1;  // -sqrt(Dq) <= 0 < w
  const int c = CGAL::compare(Dq, w2);  // sqrt(Dq) vs -w >= 0
  return -c;
}

bool root_in_range(int k, const Q& A, const Q& Bh, const Q& Dq, const Ray& ray) {
  if (compare_root(k, A, Bh, Dq, ray.tmin) <= 0) return false;
  if (std::isinf(ray.tmax) && ray.tmax > 0) return true;
  return compare_root(k, A, Bh, Dq, ray.tmax) < 0;
}

enum class SphereMode { kernel, visible_outside, visible_inside };

OracleHit sphere_query(const Ray& ray, const Vec3& center, double radius, SphereMode mode) {
  OracleHit h;
  const Q3 o = q3(ray.o), d = q3(ray.d), c = q3(center);
  const Q r(radius);
  const Q3 f = o - c;
  const Q A = dotq(d, d);
  const Q Bh = dotq(d, f);
  const Q C = dotq(f, f) - r * r;
  const Q Dq = Bh * Bh - A * C;
  CondBuilder L, W, T;
  if (CGAL::is_zero(A)) {
    for (CondBuilder* b : {&L, &W, &T}) b->margin(0, "zero_direction");
    h.local = L.c, h.world = W.c, h.textbook = T.c;
    return h;
  }
  const int sD = CGAL::sign(Dq);
  bool in0 = false, in1 = false;
  if (sD >= 0) {
    in0 = root_in_range(0, A, Bh, Dq, ray);
    in1 = root_in_range(1, A, Bh, Dq, ray);
  }
  switch (mode) {
    case SphereMode::kernel:
      if (in0) h.root = 0;
      else if (in1) h.root = 1;
      break;
    case SphereMode::visible_outside:
      if (sD > 0 && in0) h.root = 0;
      break;
    case SphereMode::visible_inside:
      if (sD > 0 && in1) h.root = 1;
      break;
  }
  h.hit = h.root >= 0;

  // t of both roots, stable form at 256 bits.
  f128 t0 = f128(kInfinity), t1 = f128(kInfinity);
  if (sD >= 0) stable_roots(A, Bh, Dq, C, t0, t1);
  if (h.hit) h.t = h.root == 0 ? t0 : t1;

  // ---- conditioning (long double is plenty)
  const L3 oL = l3(ray.o), dL = l3(ray.d), cL = l3(center);
  const L3 fL{oL.x - cL.x, oL.y - cL.y, oL.z - cL.z};
  const LD dn = norml(dL);
  const L3 u{dL.x / dn, dL.y / dn, dL.z / dn};
  const LD fn = norml(fL);
  const LD rr = std::fabs(LD(radius));
  const LD l = norml(crossl(fL, u));           // distance from the centre to the line
  const LD hq = to_ld(Dq) / to_ld(A);          // r^2 - l^2, from the exact discriminant
  const LD r_minus_l = hq / (rr + l);          // signed: > 0 the line cuts the sphere
  const LD world_scale = norml(oL) + norml(cL);
  const LD tc = -to_ld(Bh) / to_ld(A);         // closest approach
  const LD AL = to_ld(A), BL = to_ld(Bh), CL = to_ld(C), DL = to_ld(Dq);

  auto kappa_root = [&](f128 tk, CondBuilder& b, int view) {
    const LD tdist = std::fabs(LD(tk)) * dn;
    const LD s = std::sqrt(std::max<LD>(hq, 0));
    const LD g = s > 0 ? l / s : INFINITY;
    b.kappa(g, "grazing");
    b.kappa(s > 0 ? rr * rr / (s * tdist) : INFINITY, "grazing");
    b.kappa(fn / tdist, "near_tmin");
    b.kappa(fn * g / tdist, "grazing");
    if (view >= 1) b.kappa((world_scale) * (1 + g) / tdist, "translation");
    if (view >= 2) {
      const LD tt = std::fabs(LD(tk));
      b.kappa((BL * BL + std::fabs(AL * CL)) / (2 * std::sqrt(std::max<LD>(DL, 0)) * AL * tt), "cancellation");
      b.kappa((std::fabs(BL) + std::sqrt(std::max<LD>(DL, 0))) / (AL * tt), "cancellation");
    }
  };
  // kappa of the answer
  CondBuilder* views[3] = {&L, &W, &T};
  if (h.hit)
    for (int v = 0; v < 3; ++v) kappa_root(h.t, *views[v], v);
  // decisions
  const bool tmax_finite = std::isfinite(ray.tmax);
  auto in_range_approx = [&](LD t) { return t > ray.tmin && (!tmax_finite || t < ray.tmax); };
  const bool graze_relevant = h.hit || (sD < 0 && in_range_approx(tc));
  if (graze_relevant) {
    const LD ml = std::fabs(r_minus_l) / (fn + rr);
    const LD mw = std::fabs(r_minus_l) / (world_scale + rr);
    const LD mt = std::fabs(DL) / (BL * BL + std::fabs(AL * CL));
    L.margin(ml, "grazing");
    W.margin(std::min(ml, mw), "grazing");
    T.margin(std::min(ml, mw), "grazing");
    T.margin(mt, "cancellation");
  }
  auto root_margins = [&](int k) {
    const f128 tk = k == 0 ? t0 : t1;
    for (int v = 0; v < 3; ++v) {
      CondBuilder kb;
      kappa_root(tk, kb, v);
      const LD t = LD(tk);
      views[v]->margin(std::fabs(t - ray.tmin) / (LD(kb.c.kappa) * std::fabs(t) + std::fabs(LD(ray.tmin))), "near_tmin");
      if (tmax_finite)
        views[v]->margin(std::fabs(t - ray.tmax) / (LD(kb.c.kappa) * std::fabs(t) + std::fabs(LD(ray.tmax))), "near_tmax");
    }
  };
  if (sD >= 0) {
    if (mode == SphereMode::kernel) {
      root_margins(0);
      if (!in0) root_margins(1);
    } else {
      root_margins(mode == SphereMode::visible_outside ? 0 : 1);
    }
  }
  h.t_decide = h.hit ? double(h.t) : (sD < 0 ? double(tc) : double(t0));
  h.local = L.c, h.world = W.c, h.textbook = T.c;
  return h;
}

// ---------------------------------------------------------------- planes and polygons
struct ExactPlane {
  Q3 n;
  Q d;
  bool valid = false;
};

struct PlaneAnswer {
  bool in_range = false;  // the plane is hit in (tmin, tmax), n.d != 0
  Q t;
  Q3 p;                   // the exact hit point (when in_range)
};

// Conditioning of the plane part; returns the exact answer.
PlaneAnswer plane_query(const Ray& ray, const ExactPlane& pl, CondBuilder& L, CondBuilder& W, double& t_decide,
                        double& kappa_local, double& kappa_world) {
  PlaneAnswer a;
  const Q3 o = q3(ray.o), d = q3(ray.d);
  const Q den = dotq(pl.n, d);
  const Q num = -(dotq(pl.n, o) + pl.d);
  const L3 nL = l3(pl.n), dL = l3(ray.d), oL = l3(ray.o);
  const LD dpL = to_ld(pl.d);
  const LD nn = norml(nL), dd = norml(dL);
  const LD denL = to_ld(den), numL = to_ld(num);
  const LD kden = abssum(nL, dL) / std::fabs(denL);
  const LD snum = abssum(nL, oL) + std::fabs(dpL);
  L.margin(std::fabs(denL) / (nn * dd), "parallel");
  W.margin(std::fabs(denL) / (nn * dd), "parallel");
  if (CGAL::is_zero(den)) {
    t_decide = kInfinity;
    return a;
  }
  a.t = num / den;
  const LD t = to_ld(a.t);
  t_decide = double(t);
  // local: relative to the ray origin; the offset n.o + d is formed in double by
  // careful implementations, hence the 2^-29 (double/float roundoff) weight.
  L.kappa(1, "");
  L.kappa(kden, "parallel");
  L.kappa(snum / std::fabs(numL) * 0x1p-29L, "translation");
  W.kappa(kden, "parallel");
  W.kappa(snum / std::fabs(numL), "translation");
  kappa_local = L.c.kappa;
  kappa_world = W.c.kappa;
  for (CondBuilder* b : {&L, &W}) {
    b->margin(std::fabs(t - ray.tmin) / (LD(b->c.kappa) * std::fabs(t) + std::fabs(LD(ray.tmin))), "near_tmin");
    if (std::isfinite(ray.tmax))
      b->margin(std::fabs(t - ray.tmax) / (LD(b->c.kappa) * std::fabs(t) + std::fabs(LD(ray.tmax))), "near_tmax");
  }
  const bool above_min = a.t > Q(ray.tmin);
  const bool below_max = !std::isfinite(ray.tmax) ? ray.tmax > 0 : a.t < Q(ray.tmax);
  a.in_range = above_min && below_max;
  if (a.in_range) a.p = o + d * a.t;
  return a;
}

Q3 exact_newell(std::span<const Vec3> v) {
  Q3 n{Q(0), Q(0), Q(0)};
  for (size_t i = 0; i < v.size(); ++i) {
    const Q3 a = q3(v[i]), b = q3(v[(i + 1) % v.size()]);
    n.x += (a.y - b.y) * (a.z + b.z);
    n.y += (a.z - b.z) * (a.x + b.x);
    n.z += (a.x - b.x) * (a.y + b.y);
  }
  return n;
}

int dominant_axis_exact(const Q3& n) {
  const Q ax = CGAL::abs(n.x), ay = CGAL::abs(n.y), az = CGAL::abs(n.z);
  return ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
}

// The polygon's plane: exact through the vertices when they are exactly coplanar,
// else the stored (rounded Newell) plane. Sets zero_area when the exact area is 0.
ExactPlane polygon_plane(const Scene& scene, uint32_t poly, bool& zero_area) {
  ExactPlane pl;
  const auto v = scene.polygon_vertices(poly);
  const Q3 n = exact_newell(v);
  zero_area = is_zero(n);
  if (zero_area) return pl;
  const Q3 v0 = q3(v[0]);
  bool coplanar = true;
  for (size_t i = 1; i < v.size() && coplanar; ++i) coplanar = CGAL::is_zero(dotq(n, q3(v[i]) - v0));
  if (coplanar) {
    pl.n = n;
    pl.d = -dotq(n, v0);
    pl.valid = true;
    return pl;
  }
  const Plane& s = scene.poly_plane[poly];
  pl.n = q3(s.n);
  pl.d = Q(s.d);
  pl.valid = !is_zero(pl.n);
  return pl;
}

struct PolygonAnswer {
  OracleHit h;
  Q t;  // exact t when h.hit
};

// visible: apply NFF sidedness (stored normal, two-sided materials).
PolygonAnswer polygon_query(const Ray& ray, const Scene& scene, uint32_t poly, bool visible) {
  PolygonAnswer out;
  OracleHit& h = out.h;
  CondBuilder L, W;
  bool zero_area = false;
  const ExactPlane pl = polygon_plane(scene, poly, zero_area);
  h.zero_area = zero_area;
  if (!pl.valid) {
    // Zero area: the exact answer is "never hit", with no decision to get wrong.
    h.local = L.c, h.world = W.c, h.textbook = W.c;
    if (!zero_area) {  // stored normal rounded to 0: degenerate in double only
      L.margin(0, "zero_area");
      W.margin(0, "zero_area");
      h.local = L.c, h.world = W.c, h.textbook = W.c;
    }
    return out;
  }
  double t_decide = kInfinity, kl = 1, kw = 1;
  const PlaneAnswer a = plane_query(ray, pl, L, W, t_decide, kl, kw);
  h.t_decide = t_decide;
  if (a.in_range) {
    // Exact inside test on the projection dropping the dominant axis of the normal.
    const int drop = dominant_axis_exact(pl.n);
    const int ax = (drop + 1) % 3, ay = (drop + 2) % 3;
    const auto v = scene.polygon_vertices(poly);
    std::vector<K::Point_2> pts;
    pts.reserve(v.size());
    for (const Vec3& p : v) {
      K::Point_2 q(Q(p[ax]), Q(p[ay]));
      if (pts.empty() || pts.back() != q) pts.push_back(q);
    }
    while (pts.size() > 1 && pts.back() == pts.front()) pts.pop_back();
    const K::Point_2 P(a.p[ax], a.p[ay]);
    bool inside = false;
    if (pts.size() >= 3) inside = CGAL::bounded_side_2(pts.begin(), pts.end(), P, K()) != CGAL::ON_UNBOUNDED_SIDE;
    // Edge margin, approximately, in the projection.
    const LD px = to_ld(a.p[ax]), py = to_ld(a.p[ay]);
    LD dist = INFINITY, lo_x = INFINITY, lo_y = INFINITY, hi_x = -INFINITY, hi_y = -INFINITY;
    for (size_t i = 0; i < v.size(); ++i) {
      const LD x0 = v[i][ax], y0 = v[i][ay];
      const LD x1 = v[(i + 1) % v.size()][ax], y1 = v[(i + 1) % v.size()][ay];
      lo_x = std::min(lo_x, x0), hi_x = std::max(hi_x, x0), lo_y = std::min(lo_y, y0), hi_y = std::max(hi_y, y0);
      const LD ex = x1 - x0, ey = y1 - y0, len2 = ex * ex + ey * ey;
      LD s = len2 > 0 ? ((px - x0) * ex + (py - y0) * ey) / len2 : 0;
      s = std::clamp<LD>(s, 0, 1);
      const LD dx = px - (x0 + s * ex), dy = py - (y0 + s * ey);
      dist = std::min(dist, std::sqrt(dx * dx + dy * dy));
    }
    const LD diam = std::hypot(hi_x - lo_x, hi_y - lo_y);
    const LD t = to_ld(a.t), tdist = std::fabs(t) * norml(l3(ray.d));
    const L3 P3 = l3(a.p);
    // The plane itself, as implementations compute it from the vertices: moving a
    // vertex by e turns the normal by up to e diam / (2 area), which moves the plane
    // at the hit point (r from the farthest vertex) by r times that, i.e. t by that
    // over |u.n|. Large for slivers (area ~ 0 against diam^2). Perturbations are
    // relative to the polygon's size (local) or to its coordinates (world).
    {
      const L3 nn = l3(pl.n);
      const LD two_area = norml(nn);  // exact Newell vector: |n| = 2 area (for exactly coplanar vertices)
      LD r = 0, vmax = 0;
      for (const Vec3& q : v) {
        const L3 ql = l3(q);
        r = std::max(r, norml(L3{ql.x - P3.x, ql.y - P3.y, ql.z - P3.z}));
        vmax = std::max(vmax, norml(ql));
      }
      const LD cosu = std::fabs(dotl(nn, l3(ray.d))) / (two_area * norml(l3(ray.d)));
      if (two_area > 0 && cosu > 0 && tdist > 0) {
        const LD k = r * diam / (two_area * cosu * tdist);
        // Implementations that take the plane from the scene (Newell's normal in
        // double: refined traces) see this locally, in units of float, weighted 2^-29 as
        // the offset above; the float polygon kernels do not (below).
        L.kappa(k * diam * 0x1p-29L, "sliver");
        W.kappa(k * diam, "sliver");
        W.kappa(k * vmax, "translation");  // the vertices' own coordinates, far from the origin
      }
    }
    // The float polygon kernels (kernel queries: !visible) take no plane from the scene.
    // optimized/ray_cast_simd.cpp intersects the scene's triangles with Woop et al.'s
    // sheared test in float: the vertices and the ray origin rounded to float relative
    // to the anchor a (the scene's first vertex, shared so that shared edges round
    // alike), the vertices' offsets from the origin formed in float, then, with kz the
    // dominant axis of the unit direction u, s_i the lateral offset of vertex i from the
    // ray in the kz-plane and tau_i = (v_i - o)_kz / u_kz its depth, the edge functions
    // U_i = s_j x s_k (det = sum U_i: twice the triangle's area seen along the ray) and
    // t = sum U_i tau_i / det. So the 2^-29 terms above (a plane computed in double)
    // do not describe them; their t moves, per unit of float's roundoff, by
    //   positions  moving v_i by e moves the triangle's plane at P by lambda_i (n.e)
    //              (lambda_i: P's barycentrics in the triangle T holding it), the origin
    //              by n.e; e componentwise relative to |v_i - a|, |o - a| (rounding into
    //              the frame) and |v_i - o| (the offsets): over h = |n.u| t, the origin's
    //              distance to the plane;
    //   edges      each U_i relatively perturbed product by product moves t by
    //              dU_i (tau_i - t) / det: sum (|s_jx s_ky| + |s_jy s_kx| + |U_i|)
    //              |tau_i - t| / (|det| t), large where T seen along the ray is a sliver.
    // These are condition numbers (one relative perturbation per quantity), as every
    // kappa here: the few roundings per quantity are what the bound's ulps per unit of
    // kappa cover. The positions term is labelled by its larger factor: the ray's
    // obliquity t / h ("parallel") or the coordinates' size against t ("translation").
    // Traces (visible) decide in their own frames and refine a polygon's t in double
    // (judged in the world view): unchanged.
    if (!visible && tdist > 0) {
      const L3 dl = l3(ray.d), nn = l3(pl.n);
      const LD dm = norml(dl), nm = norml(nn);
      const LD u_[3] = {dl.x / dm, dl.y / dm, dl.z / dm};
      const LD n_[3] = {std::fabs(nn.x / nm), std::fabs(nn.y / nm), std::fabs(nn.z / nm)};
      const LD h = std::fabs(dotl(nn, dl)) / (nm * dm) * tdist;
      const int kz = std::fabs(u_[2]) >= std::fabs(u_[0]) && std::fabs(u_[2]) >= std::fabs(u_[1])
                         ? 2
                         : (std::fabs(u_[1]) >= std::fabs(u_[0]) ? 1 : 0);
      const int kx = (kz + 1) % 3, ky = (kz + 2) % 3;
      const Vec3 anchor = scene.vertex.empty() ? Vec3{0, 0, 0} : scene.vertex[0];
      auto nsum = [&](const Vec3& p, const Vec3& q) {  // sum_k |n_k| |p - q|_k
        return n_[0] * std::fabs(LD(p.x) - LD(q.x)) + n_[1] * std::fabs(LD(p.y) - LD(q.y)) +
               n_[2] * std::fabs(LD(p.z) - LD(q.z));
      };
      LD pos = -1, edges = 0, inside = -INFINITY;
      for (uint32_t k = scene.poly_tri_first[poly]; k < scene.poly_tri_first[poly + 1]; ++k) {
        const auto& tv = scene.tri_vertex[k];
        LD s[3][2], tau[3];  // lateral offsets; depths relative to P's, tau_i - t
        for (int i = 0; i < 3; ++i) {
          const Vec3& q = scene.vertex[tv[i]];
          const LD rel[3] = {LD(q.x) - P3.x, LD(q.y) - P3.y, LD(q.z) - P3.z};
          tau[i] = rel[kz] / u_[kz];
          s[i][0] = rel[kx] - u_[kx] * tau[i];
          s[i][1] = rel[ky] - u_[ky] * tau[i];
        }
        LD U[3], det = 0;
        for (int i = 0; i < 3; ++i) {
          U[i] = s[(i + 1) % 3][0] * s[(i + 2) % 3][1] - s[(i + 1) % 3][1] * s[(i + 2) % 3][0];
          det += U[i];
        }
        if (!(det != 0)) continue;  // no area seen along the ray: the kernel never hits it
        LD lam_min = INFINITY, p = 0, e = 0;
        for (int i = 0; i < 3; ++i) {
          const int j = (i + 1) % 3, l = (i + 2) % 3;
          lam_min = std::min(lam_min, U[i] / det);
          const Vec3& q = scene.vertex[tv[i]];
          p += std::fabs(U[i] / det) * (nsum(q, anchor) + nsum(q, ray.o));
          e += (std::fabs(s[j][0] * s[l][1]) + std::fabs(s[j][1] * s[l][0]) + std::fabs(U[i])) * std::fabs(tau[i]);
        }
        e /= std::fabs(det) * tdist;
        // T: the triangle holding P (largest smallest barycentric); on a shared edge the worse.
        if (lam_min > inside + 1e-9L) pos = p, edges = e;
        else if (lam_min >= inside - 1e-9L) pos = std::max(pos, p), edges = std::max(edges, e);
        inside = std::max(inside, lam_min);
      }
      if (pos >= 0 && h > 0) {
        const LD k_pos = (nsum(ray.o, anchor) + pos) / h, oblique = tdist / h;
        L.kappa(k_pos, oblique >= k_pos / oblique ? "parallel" : "translation");
        L.kappa(edges, "sliver");
      }
    }
    L.margin(dist / (LD(kl) * tdist + tdist + diam), "near_edge");
    W.margin(dist / (LD(kw) * tdist + norml(P3) + diam), "near_edge");
    bool facing = true;
    if (visible) {
      const uint32_t prim = scene.sphere_count() + poly;
      const Plane& sp = scene.poly_plane[poly];
      const Q dn = dotq(q3(sp.n), q3(ray.d));
      facing = scene.material_of_prim(prim).two_sided() || CGAL::sign(dn) < 0;
      if (!scene.material_of_prim(prim).two_sided()) {
        const LD m = std::fabs(to_ld(dn)) / (norml(l3(sp.n)) * norml(l3(ray.d)));
        L.margin(m, "parallel");
        W.margin(m, "parallel");
      }
    }
    if (inside && facing) {
      h.hit = true;
      h.t = to_f128(a.t);
      out.t = a.t;
    }
  }
  h.local = L.c, h.world = W.c, h.textbook = W.c;
  return out;
}

// ---------------------------------------------------------------- cones
//
// NFF's open cone (core/cone_quadric.h) with the axis a = apex - base left
// unnormalised, so that everything stays rational: with w = P - base and
// L = a.a, P is on the side when
//     L^2 |w|^2 - L (w.a)^2 = (r0 L + (r1 - r0) (w.a))^2   and   0 <= w.a <= L
// (the textbook's equation times L^2). Along o + t d this is A t^2 + 2 Bh t + C,
// exact; the roots are compared with tmin, tmax and the two height limits
// exactly (compare_root_q), and t comes from the stable form at 256 bits.

// compare_root with a rational x.
int compare_root_q(int k, const Q& A, const Q& Bh, const Q& Dq, const Q& x) {
  const Q w = A * x + Bh;
  const int sw = CGAL::sign(w);
  if (k == 1) {
    if (sw < 0) return 1;
    return CGAL::compare(Dq, w * w);
  }
  if (sw > 0) return -1;
  return -CGAL::compare(Dq, w * w);
}

// How many roundings of their own scale the careful forms' quadric pieces
// carry (q_perp, d_perp, rho, kappa from the moved origin and the rounded unit
// axis, then b, A, C and the discriminant): an operation count, not a fit. The
// deep runs found grazing roots off by up to 16 ulps of this scale per unit of
// the linear estimate (props/README.md, ray_cone).
constexpr long double kConePieceRoundings = 16;

struct ConeExact {
  Q A, Bh, C, Dq;
  Q qa, da, L;
};

// The quadric along the ray from origin o (exact).
ConeExact cone_exact(const Q3& o, const Q3& d, const Q3& base, const Q3& a, const Q& r0,
                     const Q& dr) {
  ConeExact e;
  e.L = dotq(a, a);
  const Q3 q = o - base;
  e.qa = dotq(q, a);
  e.da = dotq(d, a);
  const Q rq = r0 * e.L + dr * e.qa;  // L times the radius at the origin's height
  const Q rd = dr * e.da;
  const Q L2 = e.L * e.L;
  e.A = L2 * dotq(d, d) - e.L * e.da * e.da - rd * rd;
  e.Bh = L2 * dotq(q, d) - e.L * e.qa * e.da - rq * rd;
  e.C = L2 * dotq(q, q) - e.L * e.qa * e.qa - rq * rq;
  if (CGAL::sign(e.A) < 0) e.A = -e.A, e.Bh = -e.Bh, e.C = -e.C;  // same roots, A > 0
  e.Dq = e.Bh * e.Bh - e.A * e.C;
  return e;
}

}  // namespace

OracleHit oracle_cone(const Ray& ray, const Scene& scene, uint32_t cone) {
  OracleHit h;
  const Vec3 baseV = scene.cone_base[cone], apexV = scene.cone_apex[cone];
  const double r0v = scene.cone_r0[cone], r1v = scene.cone_r1[cone];
  const Q3 o = q3(ray.o), d = q3(ray.d), base = q3(baseV), a = q3(apexV) - base;
  const Q r0(r0v), dr = Q(r1v) - Q(r0v);
  const ConeExact e = cone_exact(o, d, base, a, r0, dr);
  CondBuilder L, W, T;
  if (is_zero(d)) {
    for (CondBuilder* b : {&L, &W, &T}) b->margin(0, "zero_direction");
    h.local = L.c, h.world = W.c, h.textbook = T.c;
    return h;
  }
  // Candidate roots in increasing order (exact): each one's t as a float128 and
  // whether it is in (tmin, tmax) and on the finite part.
  struct Root {
    f128 t = f128(kInfinity);
    bool in_range = false, in_height = false;
  };
  std::vector<Root> roots;
  const bool linear = CGAL::is_zero(e.A);
  // A root compared with a rational x: -1, 0, 1.
  auto cmp = [&](int k, const Q& x) {
    if (linear) {
      const Q t = -e.C / (Q(2) * e.Bh);
      return int(CGAL::compare(t, x));
    }
    return compare_root_q(k, e.A, e.Bh, e.Dq, x);
  };
  auto classify = [&](int k, Root& r) {
    r.in_range =
        cmp(k, Q(ray.tmin)) > 0 && (std::isinf(ray.tmax) ? ray.tmax > 0 : cmp(k, Q(ray.tmax)) < 0);
    // 0 <= qa + t da <= L
    const int sda = CGAL::sign(e.da);
    if (sda == 0) {
      r.in_height = CGAL::sign(e.qa) >= 0 && e.qa <= e.L;
    } else {
      const Q lo = -e.qa / e.da, hi = (e.L - e.qa) / e.da;  // t at height 0 and at height L
      const Q& tl = sda > 0 ? lo : hi;
      const Q& th = sda > 0 ? hi : lo;
      r.in_height = cmp(k, tl) >= 0 && cmp(k, th) <= 0;
    }
  };
  const int sD = linear ? 0 : CGAL::sign(e.Dq);
  if (linear) {
    if (!CGAL::is_zero(e.Bh)) {
      Root r;
      r.t = to_f128(-e.C / (Q(2) * e.Bh));
      classify(0, r);
      roots.push_back(r);
    }
  } else if (sD >= 0) {
    f128 t0, t1;
    stable_roots(e.A, e.Bh, e.Dq, e.C, t0, t1);
    Root r0r, r1r;
    r0r.t = t0, r1r.t = t1;
    classify(0, r0r);
    classify(1, r1r);
    roots = {r0r, r1r};
  }
  int taken = -1;
  for (size_t k = 0; k < roots.size() && taken < 0; ++k)
    if (roots[k].in_range && roots[k].in_height) taken = int(k);
  h.hit = taken >= 0;
  h.root = taken;
  if (h.hit) h.t = roots[size_t(taken)].t;

  // ---- conditioning (long double), in the cone's unit-axis terms
  const L3 oL = l3(ray.o), dL = l3(ray.d), bL = l3(baseV), aL = l3(apexV);
  const L3 axis{aL.x - bL.x, aL.y - bL.y, aL.z - bL.z};
  const LD hh = norml(axis);
  const L3 u{axis.x / hh, axis.y / hh, axis.z / hh};
  const LD k = (LD(r1v) - LD(r0v)) / hh;
  const L3 cL{(aL.x + bL.x) / 2, (aL.y + bL.y) / 2, (aL.z + bL.z) / 2};
  const LD R =
      std::sqrt(hh * hh / 4 + std::max<LD>(r0v, r1v) * std::max<LD>(r0v, r1v));  // bounding sphere
  const LD dn = norml(dL);
  const L3 fL{oL.x - cL.x, oL.y - cL.y, oL.z - cL.z};
  const LD fn = norml(fL);
  const LD world_scale = norml(oL) + norml(cL);
  // The careful forms move the origin to o + shift d near the centre: shift
  // (a dot product and a quotient) and the product carry about 8 roundings of
  // |o - c|, the sum one of |c|. That is where their line sits, to within eps.
  const LD shift_err = norml(cL) + 8 * fn;
  const LD du = dotl(dL, u);
  const L3 dp{dL.x - du * u.x, dL.y - du * u.y, dL.z - du * u.z};
  const LD kap = k * du;
  // The pieces about the point of the line nearest the centre (what the careful
  // forms compute from): scale of the discriminant's rounding.
  const LD sh = -dotl(fL, dL) / (dn * dn);
  const L3 q1{oL.x + sh * dL.x - bL.x, oL.y + sh * dL.y - bL.y, oL.z + sh * dL.z - bL.z};
  const LD qu1 = dotl(q1, u);
  const L3 qp1{q1.x - qu1 * u.x, q1.y - qu1 * u.y, q1.z - qu1 * u.z};
  const LD rho1 = LD(r0v) + k * qu1;
  const LD S = (dotl(qp1, qp1) + rho1 * rho1) * (dotl(dp, dp) + kap * kap);
  const LD L4 = to_ld(e.L) * to_ld(e.L);
  const LD DqN =
      linear ? 0 : to_ld(e.Dq) / (L4 * L4);  // the unit-axis discriminant (coefficients / L^2)
  const LD AL = to_ld(e.A), BL = to_ld(e.Bh), CL = to_ld(e.C), DL = to_ld(e.Dq);
  // The world-origin pieces (the textbook computes from o itself).
  const L3 q0{oL.x - bL.x, oL.y - bL.y, oL.z - bL.z};
  const LD qu0 = dotl(q0, u);
  const L3 qp0{q0.x - qu0 * u.x, q0.y - qu0 * u.y, q0.z - qu0 * u.z};
  const LD rho0 = LD(r0v) + k * qu0;
  const LD pieces0 = dotl(qp0, qp0) + rho0 * rho0;

  CondBuilder* views[3] = {&L, &W, &T};
  // kappa of root t, per view (0 local, 1 world, 2 textbook).
  auto kappa_root = [&](f128 tk, CondBuilder& b, int view) {
    const LD t = LD(tk), tdist = std::fabs(t) * dn;
    const L3 P{oL.x + t * dL.x, oL.y + t * dL.y, oL.z + t * dL.z};
    const L3 w{P.x - bL.x, P.y - bL.y, P.z - bL.z};
    const LD s = dotl(w, u);
    const L3 wp{w.x - s * u.x, w.y - s * u.y, w.z - s * u.z};
    const LD r = LD(r0v) + k * s;
    const LD Fp = 2 * (dotl(wp, dp) - r * kap);  // f'(t), unit axis
    const LD grad = 2 * std::max<LD>(std::fabs(r), 0) * std::sqrt(1 + k * k);
    const LD g = std::fabs(Fp) > 0 ? grad * dn / std::fabs(Fp) : INFINITY;  // 1 / cos(incidence)
    b.kappa(g, "grazing");
    b.kappa(R * g / tdist, "grazing");
    b.kappa(fn / tdist, "near_tmin");
    b.kappa(fn * g / tdist, "grazing");
    // The quadric's own pieces over its slope: the discriminant's rounding
    // (kConePieceRoundings x the pieces' scale, as for the grazing margin below)
    // moves the root by that over f'. Large at a graze (f' -> 0) and near the
    // apex (r -> 0).
    const LD pieces1 = kConePieceRoundings * (dotl(qp1, qp1) + rho1 * rho1 + R * R);
    const LD apex = std::fabs(Fp) > 0 ? pieces1 / (std::fabs(Fp) * std::fabs(t)) : INFINITY;
    b.kappa(apex, (r > 0 && R / r > g) ? "near_apex" : "grazing");
    // A = d_perp^2 - kappa^2 rounds by eps (d_perp^2 + kappa^2), which moves f by
    // that times t'^2, t' the root from where the quadric is set up: the careful
    // forms' moved origin near the centre (the textbook's own origin: below).
    // Large for the far root of rays parallel to a side line (A -> 0).
    const LD tp = t - sh, a_err = dotl(dp, dp) + kap * kap;
    b.kappa(std::fabs(Fp) > 0 ? tp * tp * a_err / (std::fabs(Fp) * std::fabs(t)) : INFINITY,
            "parallel");
    if (view >= 1) b.kappa(world_scale * (1 + g) / tdist, "translation");
    if (view >= 2) {
      const LD tt = std::fabs(t);
      if (!linear) {
        b.kappa((BL * BL + std::fabs(AL * CL)) / (2 * std::sqrt(std::max<LD>(DL, 0)) * AL * tt),
                "cancellation");
        b.kappa((std::fabs(BL) + std::sqrt(std::max<LD>(DL, 0))) / (AL * tt), "cancellation");
      }
      b.kappa(std::fabs(Fp) > 0 ? pieces0 / (std::fabs(Fp) * tt) : INFINITY, "cancellation");
      b.kappa(std::fabs(Fp) > 0 ? tt * a_err / std::fabs(Fp) : INFINITY, "parallel");
    }
  };
  if (h.hit)
    for (int v = 0; v < 3; ++v) kappa_root(h.t, *views[v], v);
  // Decisions. Hit or miss of the quadric: the discriminant against the rounding
  // of its pieces (about the centre; the shift to there rounds in world
  // coordinates, hence the world scale); the textbook's from the origin itself.
  const LD tc = sh;  // closest approach to the centre
  const bool tmax_finite = std::isfinite(ray.tmax);
  auto in_range_approx = [&](LD t) { return t > ray.tmin && (!tmax_finite || t < ray.tmax); };
  if (!linear && (h.hit || (sD < 0 && in_range_approx(tc)) || sD >= 0)) {
    // S bounds b^2 and |A C|; b, A and C come from pieces (q_perp, d_perp, rho,
    // kappa, themselves from the rounded unit axis and the moved origin) of a
    // dozen roundings between them: the margin is counted against
    // kConePieceRoundings S.
    const LD ml = std::fabs(DqN) / (kConePieceRoundings * S) / (1 + shift_err / R);
    L.margin(ml, "grazing");
    W.margin(ml, "grazing");
    T.margin(ml, "grazing");
    T.margin(std::fabs(DL) / (BL * BL + std::fabs(AL * CL)), "cancellation");
  }
  if (linear) {
    for (CondBuilder* b : {&L, &W, &T}) b->margin(0, "parallel");
  }
  auto root_margins = [&](const Root& rt) {
    for (int v = 0; v < 3; ++v) {
      CondBuilder kb;
      kappa_root(rt.t, kb, v);
      const LD t = LD(rt.t), kt = LD(kb.c.kappa) * std::fabs(t);
      views[v]->margin(std::fabs(t - ray.tmin) / (kt + std::fabs(LD(ray.tmin))), "near_tmin");
      if (tmax_finite)
        views[v]->margin(std::fabs(t - ray.tmax) / (kt + std::fabs(LD(ray.tmax))), "near_tmax");
      // The rim: the height at the root against 0 and h, over how far the height
      // moves with t's error and the rounding of the positions.
      const LD s = qu0 + t * du;
      const LD moved = kt * std::fabs(du) + shift_err + R + (v >= 1 ? world_scale : 0);
      views[v]->margin(std::min(std::fabs(s), std::fabs(hh - s)) / moved, "near_rim");
    }
  };
  if (!roots.empty()) {
    root_margins(roots[0]);
    if (!(roots[0].in_range && roots[0].in_height) && roots.size() > 1) root_margins(roots[1]);
  }
  h.t_decide = h.hit ? double(h.t) : (roots.empty() ? double(tc) : double(roots[0].t));
  h.local = L.c, h.world = W.c, h.textbook = T.c;
  return h;
}

// ---------------------------------------------------------------- public
bool well_conditioned(const OracleHit& h) { return h.world.kappa <= kWellKappa && h.world.margin >= kWellMargin; }

double to_double(f128 x) { return double(x); }

std::string hex128(f128 x) {
  char buf[128];
  quadmath_snprintf(buf, sizeof buf, "%Qa", x);
  return buf;
}

double rel_error(double a, f128 b) {
  if (std::isnan(a)) return kInfinity;
  const bool ainf = std::isinf(a), binf = isinfq(b);
  if (ainf || binf) return (ainf && binf && (a > 0) == (b > 0)) ? 0.0 : kInfinity;
  const f128 diff = fabsq(f128(a) - b);
  if (b == 0) return double(diff);
  return double(diff / fabsq(b));
}

std::string describe(const OracleHit& h) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%s t=%s (%.17g) kappa local %.3g%s%s world %.3g%s%s textbook %.3g%s%s; margin local %.3g%s%s world "
                "%.3g%s%s textbook %.3g%s%s%s",
                h.hit ? "hit" : "miss", hex128(h.t).c_str(), double(h.t), h.local.kappa,
                h.local.kappa_why[0] ? " " : "", h.local.kappa_why, h.world.kappa, h.world.kappa_why[0] ? " " : "",
                h.world.kappa_why, h.textbook.kappa, h.textbook.kappa_why[0] ? " " : "", h.textbook.kappa_why,
                h.local.margin, h.local.margin_why[0] ? " " : "", h.local.margin_why, h.world.margin,
                h.world.margin_why[0] ? " " : "", h.world.margin_why, h.textbook.margin,
                h.textbook.margin_why[0] ? " " : "", h.textbook.margin_why, h.zero_area ? " zero_area" : "");
  return buf;
}

OracleHit oracle_sphere(const Ray& ray, const Sphere& sphere) {
  return sphere_query(ray, sphere.center, sphere.radius, SphereMode::kernel);
}

OracleHit oracle_plane(const Ray& ray, const Plane& plane) {
  OracleHit h;
  CondBuilder L, W;
  ExactPlane pl{q3(plane.n), Q(plane.d), true};
  if (is_zero(pl.n)) {
    h.local = L.c, h.world = W.c, h.textbook = W.c;
    return h;
  }
  double t_decide = kInfinity, kl = 1, kw = 1;
  const PlaneAnswer a = plane_query(ray, pl, L, W, t_decide, kl, kw);
  h.t_decide = t_decide;
  if (a.in_range) {
    h.hit = true;
    h.t = to_f128(a.t);
  }
  h.local = L.c, h.world = W.c, h.textbook = W.c;
  return h;
}

OracleHit oracle_polygon(const Ray& ray, const Scene& scene, uint32_t poly) {
  return polygon_query(ray, scene, poly, false).h;
}

bool oracle_zero_area(const Scene& scene, uint32_t poly) {
  return is_zero(exact_newell(scene.polygon_vertices(poly)));
}

OracleTrace oracle_trace(const Scene& scene, const Ray& ray) {
  OracleTrace tr;
  tr.per_prim.resize(scene.prim_count());
  for (uint32_t s = 0; s < scene.sphere_count(); ++s) {
    const double r = scene.sphere_radius[s];
    tr.per_prim[s] = sphere_query(ray, scene.sphere_center[s], r,
                                  r > 0 ? SphereMode::visible_outside : SphereMode::visible_inside);
  }
  for (uint32_t p = 0; p < scene.polygon_count(); ++p)
    tr.per_prim[scene.sphere_count() + p] = polygon_query(ray, scene, p, true).h;
  // Nearest.
  for (uint32_t i = 0; i < tr.per_prim.size(); ++i) {
    const OracleHit& h = tr.per_prim[i];
    if (h.hit && (tr.prim == Hit::kNoHit || h.t < tr.per_prim[tr.prim].t)) tr.prim = i;
  }
  OracleHit best;
  if (tr.prim != Hit::kNoHit) best = tr.per_prim[tr.prim];
  const f128 tb = best.hit ? best.t : f128(kInfinity);
  // Tied prims, and the runner-up.
  uint32_t second = Hit::kNoHit;
  for (uint32_t i = 0; i < tr.per_prim.size(); ++i) {
    const OracleHit& h = tr.per_prim[i];
    if (!h.hit) continue;
    if (fabsq(h.t - tb) <= f128(1e-12) * fabsq(tb)) {
      tr.tied.push_back(i);
    } else if (second == Hit::kNoHit || h.t < tr.per_prim[second].t) {
      second = i;
    }
  }
  // Margin over every decision that could change the answer: prims whose
  // decision sits before the best hit, and the separation from the runner-up.
  Conditioning L = best.local, W = best.world, T = best.textbook;
  if (!best.hit) L = W = T = Conditioning{};
  auto take = [](Conditioning& into, const Conditioning& from) {
    if (from.margin < into.margin) {
      into.margin = from.margin;
      into.margin_why = from.margin_why;
    }
  };
  const double limit = best.hit ? double(tb) * (1 + 1e-6) : kInfinity;
  for (uint32_t i = 0; i < tr.per_prim.size(); ++i) {
    const OracleHit& h = tr.per_prim[i];
    if (!(h.t_decide <= limit) && !(std::isinf(limit))) continue;
    take(L, h.local), take(W, h.world), take(T, h.textbook);
  }
  if (best.hit && second != Hit::kNoHit) {
    const OracleHit& s = tr.per_prim[second];
    const double gap = double((s.t - tb) / fabsq(tb));
    auto sep = [&](Conditioning& c, double k1, double k2) {
      const double m = gap / (k1 + k2);
      if (m < c.margin) {
        c.margin = m;
        c.margin_why = "separation";
      }
    };
    sep(L, best.local.kappa, s.local.kappa);
    sep(W, best.world.kappa, s.world.kappa);
    sep(T, best.textbook.kappa, s.textbook.kappa);
  }
  best.local = L, best.world = W, best.textbook = T;
  tr.best = best;
  return tr;
}

OracleContact oracle_contact(const Scene& scene, const Ray& ray) {
  OracleContact c;
  std::vector<PolygonAnswer> answers;
  answers.reserve(scene.polygon_count());
  int best = -1;
  for (uint32_t p = 0; p < scene.polygon_count(); ++p) {
    answers.push_back(polygon_query(ray, scene, p, false));
    if (answers.back().h.hit && (best < 0 || answers.back().t < answers[size_t(best)].t)) best = int(p);
  }
  if (best < 0) return c;
  c.contact = true;
  const Q tb = answers[size_t(best)].t;
  c.t = to_f128(tb);
  c.transversal = true;
  for (uint32_t p = 0; p < scene.polygon_count(); ++p) {
    if (!answers[p].h.hit || answers[p].t != tb) continue;
    c.touching.push_back(scene.sphere_count() + p);
    const uint32_t prim = scene.sphere_count() + p;
    if (scene.material_of_prim(prim).two_sided()) continue;
    const Plane& sp = scene.poly_plane[p];
    const Q dn = dotq(q3(sp.n), q3(ray.d));
    const LD m = std::fabs(to_ld(dn)) / (norml(l3(sp.n)) * norml(l3(ray.d)));
    if (!(CGAL::sign(dn) < 0 && m >= 1e-6L)) c.transversal = false;
  }
  return c;
}

}  // namespace lockstep::props::ray_cast
