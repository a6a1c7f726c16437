// lockstep core: exact geometric predicates on doubles, for the painter's
// plan (core/painter_plan.h).
//
// Method: Shewchuk, "Adaptive precision floating-point arithmetic and fast
// robust geometric predicates" (1997). A number is kept as an *expansion*: a
// sum of doubles, nonoverlapping, in increasing magnitude, whose exact sum is
// the value. Sums and products of doubles are made exact by keeping their
// rounding errors (two_sum, two_product); the sign of an expansion is the sign
// of its largest component. Each predicate first evaluates in plain doubles and
// returns when the result is larger than Shewchuk's forward error bound (the
// "filter"); only near-degenerate inputs pay for the exact evaluation.
//
// The triangle-triangle test is built from orientations only (no constructed
// points), as in Guigue and Devillers, "Fast and robust triangle-triangle
// overlap test using orientation predicates" (2003), in a simpler form: two
// closed triangles in general position meet iff an edge of one meets the
// other; coplanar ones are tested in 2D.
#include <cmath>
#include <cstdlib>
#include <vector>

#include "core/painter_plan.h"

namespace lockstep::exact {
namespace {

using Expansion = std::vector<double>;

constexpr double kEps = 0x1p-53;  // unit roundoff of double

// a + b = x + y exactly (Knuth).
void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a;
  const double av = x - bv;
  y = (a - av) + (b - bv);
}

// a * b = x + y exactly (the fused multiply-add rounds once).
void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

// e + b (Shewchuk's Grow-Expansion, zero components dropped).
Expansion grow(const Expansion& e, double b) {
  Expansion h;
  h.reserve(e.size() + 1);
  double q = b;
  for (double ei : e) {
    double sum, err;
    two_sum(q, ei, sum, err);
    if (err != 0) h.push_back(err);
    q = sum;
  }
  if (q != 0 || h.empty()) h.push_back(q);
  return h;
}

// e + f: f's components added one at a time (Expansion-Sum).
Expansion add(const Expansion& e, const Expansion& f) {
  Expansion h = e;
  for (double fi : f) h = grow(h, fi);
  return h;
}

Expansion negate(Expansion e) {
  for (double& x : e) x = -x;
  return e;
}

// e * b (Scale-Expansion).
Expansion scale(const Expansion& e, double b) {
  Expansion h;
  h.reserve(2 * e.size());
  double q = 0;
  bool first = true;
  for (double ei : e) {
    double p, perr;
    two_product(ei, b, p, perr);
    if (first) {
      if (perr != 0) h.push_back(perr);
      q = p;
      first = false;
      continue;
    }
    double s, serr;
    two_sum(q, perr, s, serr);
    if (serr != 0) h.push_back(serr);
    double t, terr;
    two_sum(p, s, t, terr);
    if (terr != 0) h.push_back(terr);
    q = t;
  }
  if (q != 0 || h.empty()) h.push_back(q);
  return h;
}

// e * f: the sum of e scaled by each component of f.
Expansion mul(const Expansion& e, const Expansion& f) {
  Expansion h{0.0};
  for (double fi : f) h = add(h, scale(e, fi));
  return h;
}

// a - b exactly, as a two-component expansion.
Expansion diff(double a, double b) {
  double x, y;
  two_sum(a, -b, x, y);
  return y != 0 ? Expansion{y, x} : Expansion{x};
}

// The sign of the exact value: the largest nonzero component's.
int sign(const Expansion& e) {
  for (auto it = e.rbegin(); it != e.rend(); ++it)
    if (*it != 0) return *it > 0 ? 1 : -1;
  return 0;
}

int sign_of(double v) { return (v > 0) - (v < 0); }

}  // namespace

int orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  // Filter: Shewchuk's ccwerrboundA times the permanent.
  const double left = (bx - ax) * (cy - ay);
  const double right = (by - ay) * (cx - ax);
  const double det = left - right;
  const double bound = (3.0 + 16.0 * kEps) * kEps * (std::fabs(left) + std::fabs(right));
  if (std::fabs(det) > bound) return sign_of(det);
  // Exact: (b - a) and (c - a) as expansions, their cross product.
  const Expansion l = mul(diff(bx, ax), diff(cy, ay));
  const Expansion r = mul(diff(by, ay), diff(cx, ax));
  return sign(add(l, negate(r)));
}

int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // Filter in doubles (o3derrboundA).
  const double adx = a.x - d.x, ady = a.y - d.y, adz = a.z - d.z;
  const double bdx = b.x - d.x, bdy = b.y - d.y, bdz = b.z - d.z;
  const double cdx = c.x - d.x, cdy = c.y - d.y, cdz = c.z - d.z;
  const double det =
      adx * (bdy * cdz - bdz * cdy) + bdx * (cdy * adz - cdz * ady) + cdx * (ady * bdz - adz * bdy);
  const double permanent = std::fabs(adx) * (std::fabs(bdy * cdz) + std::fabs(bdz * cdy)) +
                           std::fabs(bdx) * (std::fabs(cdy * adz) + std::fabs(cdz * ady)) +
                           std::fabs(cdx) * (std::fabs(ady * bdz) + std::fabs(adz * bdy));
  const double bound = (7.0 + 56.0 * kEps) * kEps * permanent;
  if (std::fabs(det) > bound) return sign_of(det);
  // Exact: the same cofactor expansion over exact differences.
  const Expansion ex[3] = {diff(a.x, d.x), diff(b.x, d.x), diff(c.x, d.x)};
  const Expansion ey[3] = {diff(a.y, d.y), diff(b.y, d.y), diff(c.y, d.y)};
  const Expansion ez[3] = {diff(a.z, d.z), diff(b.z, d.z), diff(c.z, d.z)};
  Expansion total{0.0};
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const Expansion minor = add(mul(ey[j], ez[k]), negate(mul(ez[j], ey[k])));
    total = add(total, mul(ex[i], minor));
  }
  return sign(total);
}

int sign_of_triple_products(const double (*rows)[3], int n) {
  Expansion total{0.0};
  for (int i = 0; i < n; ++i)
    total = add(total, scale(scale(Expansion{rows[i][0]}, rows[i][1]), rows[i][2]));
  return sign(total);
}

// ---------------------------------------------------------------- triangle-triangle

namespace {

// 2D points of a plane, projected along the dominant axis of its normal (an
// affine bijection of the plane, so incidences are kept).
struct P2 {
  double x, y;
};

int orient(const P2& a, const P2& b, const P2& c) { return orient2d(a.x, a.y, b.x, b.y, c.x, c.y); }

// c on the closed segment ab, given that a, b, c are collinear.
bool between(const P2& a, const P2& b, const P2& c) {
  return std::min(a.x, b.x) <= c.x && c.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= c.y &&
         c.y <= std::max(a.y, b.y);
}

// Closed segments ab and cd meet.
bool segments_meet(const P2& a, const P2& b, const P2& c, const P2& d) {
  const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;  // proper crossing
  // Touching: an endpoint on the other segment.
  if (o1 == 0 && between(a, b, c)) return true;
  if (o2 == 0 && between(a, b, d)) return true;
  if (o3 == 0 && between(c, d, a)) return true;
  if (o4 == 0 && between(c, d, b)) return true;
  return false;
}

// Point p in the closed triangle abc (any orientation, possibly degenerate).
bool point_in_triangle(const P2& p, const P2& a, const P2& b, const P2& c) {
  const int o = orient(a, b, c);
  if (o == 0)
    return segments_meet(a, b, p, p) || segments_meet(b, c, p, p) || segments_meet(c, a, p, p);
  const int o1 = orient(a, b, p) * o, o2 = orient(b, c, p) * o, o3 = orient(c, a, p) * o;
  return o1 >= 0 && o2 >= 0 && o3 >= 0;
}

// Closed triangles (or segments, with repeated points) in one plane.
bool triangles_meet_2d(const std::array<P2, 3>& t, const std::array<P2, 3>& u) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (segments_meet(t[i], t[(i + 1) % 3], u[j], u[(j + 1) % 3])) return true;
  // No boundaries meet: one is inside the other, or they are apart.
  return point_in_triangle(t[0], u[0], u[1], u[2]) || point_in_triangle(u[0], t[0], t[1], t[2]);
}

// Projection dropping the coordinate `axis`.
P2 drop(const Vec3& v, int axis) {
  return axis == 0 ? P2{v.y, v.z} : (axis == 1 ? P2{v.z, v.x} : P2{v.x, v.y});
}

// An axis along which the plane of t (not degenerate) does not project to a line:
// the one whose 2D orientation of t is nonzero (exactly).
int projection_axis(const std::array<Vec3, 3>& t) {
  for (int axis = 2; axis >= 0; --axis) {
    const P2 a = drop(t[0], axis), b = drop(t[1], axis), c = drop(t[2], axis);
    if (orient(a, b, c) != 0) return axis;
  }
  return -1;  // collinear in 3D
}

// Closed segment pq against closed triangle abc, in 3D; abc not collinear.
bool segment_meets_triangle(const Vec3& p, const Vec3& q, const std::array<Vec3, 3>& t) {
  const int sp = orient3d(t[0], t[1], t[2], p), sq = orient3d(t[0], t[1], t[2], q);
  if (sp * sq > 0) return false;  // both strictly on one side of the plane
  if (sp == 0 && sq == 0) {
    // The segment lies in the triangle's plane: 2D.
    const int axis = projection_axis(t);
    const P2 a = drop(p, axis), b = drop(q, axis);
    return triangles_meet_2d({a, b, b}, {drop(t[0], axis), drop(t[1], axis), drop(t[2], axis)});
  }
  // The segment meets the plane in one point; it is in the closed triangle iff
  // the line pq passes on the same side of (or through) all three edges.
  const int o1 = orient3d(p, q, t[0], t[1]), o2 = orient3d(p, q, t[1], t[2]),
            o3 = orient3d(p, q, t[2], t[0]);
  return (o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0);
}

}  // namespace

bool triangles_intersect(const std::array<Vec3, 3>& t, const std::array<Vec3, 3>& u) {
  const int at = projection_axis(t), au = projection_axis(u);
  if (at < 0 && au < 0) {
    // Both collinear: segments; find the plane of all four extreme points or test in 2D per axis.
    for (int axis = 0; axis < 3; ++axis) {
      const std::array<P2, 3> a{drop(t[0], axis), drop(t[1], axis), drop(t[2], axis)};
      const std::array<P2, 3> b{drop(u[0], axis), drop(u[1], axis), drop(u[2], axis)};
      if (!triangles_meet_2d(a, b)) return false;  // a separating projection
    }
    // Two segments whose projections meet along every axis: they meet iff coplanar.
    return orient3d(t[0], t[1], u[0], u[1]) == 0 || orient3d(t[0], t[2], u[0], u[2]) == 0;
  }
  if (at < 0) return triangles_intersect(u, t);  // t is a segment: let u be the real triangle
  // t is a proper triangle. Coplanar with u?
  const int s0 = orient3d(t[0], t[1], t[2], u[0]), s1 = orient3d(t[0], t[1], t[2], u[1]),
            s2 = orient3d(t[0], t[1], t[2], u[2]);
  if (s0 == 0 && s1 == 0 && s2 == 0) {
    const std::array<P2, 3> a{drop(t[0], at), drop(t[1], at), drop(t[2], at)};
    const std::array<P2, 3> b{drop(u[0], at), drop(u[1], at), drop(u[2], at)};
    return triangles_meet_2d(a, b);
  }
  if ((s0 > 0 && s1 > 0 && s2 > 0) || (s0 < 0 && s1 < 0 && s2 < 0)) return false;  // u on one side
  // Not coplanar: the intersection (if any) is a segment or point whose ends lie
  // on edges, so some edge of one triangle meets the other triangle.
  for (int i = 0; i < 3; ++i)
    if (segment_meets_triangle(u[i], u[(i + 1) % 3], t)) return true;
  if (au < 0) return false;  // u is a segment: its edges were all there is
  for (int i = 0; i < 3; ++i)
    if (segment_meets_triangle(t[i], t[(i + 1) % 3], u)) return true;
  return false;
}

}  // namespace lockstep::exact
