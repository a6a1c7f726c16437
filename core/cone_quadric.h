// lockstep core: ray-cone intersection, NFF's open-ended truncated cone (a
// cylinder when the radii are equal), two ways: the quadric every ray-casting
// row shares (reference/ray_cone.cpp, optimized/ray_cone.h, optimized/refine.h).
//
// Source: the quadric method of Glassner (ed.), "An Introduction to Ray
// Tracing", ch. 2 (Haines), for a cone of arbitrary axis, as in lecture notes.
// The cone runs from base B (radius r0) to apex A (radius r1); h = |A - B|,
// u = (A - B) / h, slope k = (r1 - r0) / h. A point P lies on its side when,
// with w = P - B and s = w.u (the height above the base),
//     |w - s u|^2 = (r0 + k s)^2   and   0 <= s <= h.
// Substituting P(t) = o + t d with q = o - B:
//     q_perp = q - (q.u) u,  d_perp = d - (d.u) u,
//     rho = r0 + k (q.u),    kappa = k (d.u)        (the radius is rho + t kappa)
//     A t^2 + B t + C = 0 with A = d_perp.d_perp - kappa^2,
//                              B = 2 (q_perp.d_perp - rho kappa),
//                              C = q_perp.q_perp - rho^2.
// Roots outside 0 <= s <= h are dropped (the quadric is the whole double cone or
// the infinite cylinder); no caps (NFF's cones are open).
//
// cone_roots_textbook: the formula as written, any precision T.
// cone_roots_stable: double; the ray's origin first moved along the ray to
//   the point nearest the cone's centre (so that far origins do not swamp the
//   pieces above with rounding: q, C and rho would be ~|o|, |o|^2; the same
//   move as the Hearn-Baker sphere form), then the half-B form, the root that does not cancel
//   computed first and the other from the product of the roots (C / A), each
//   then refined by one Newton step on the quadric itself (which repairs what
//   the rounding of A, B, C cost); the spirit of the stable sphere form that
//   optimized/refine.h uses.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/math.h"

namespace lockstep {

// The pieces above for one ray and one cone, in precision T.
template <typename T>
struct ConeQuadric {
  Vec3T<T> qp, dp;  // q_perp, d_perp
  T rho, kappa;     // radius along the ray: rho + t kappa
  T qu, du, h;      // height along the ray: qu + t du, in [0, h]
  T A, half_B, C;   // A t^2 + 2 half_B t + C
};

template <typename T>
ConeQuadric<T> cone_quadric(const Vec3T<T>& o, const Vec3T<T>& d, const Vec3T<T>& base, T r0, const Vec3T<T>& apex,
                            T r1) {
  ConeQuadric<T> c;
  const Vec3T<T> axis = apex - base;
  c.h = std::sqrt(dot(axis, axis));
  const Vec3T<T> u = axis / c.h;
  const T k = (r1 - r0) / c.h;
  const Vec3T<T> q = o - base;
  c.qu = dot(q, u);
  c.du = dot(d, u);
  c.qp = q - c.qu * u;
  c.dp = d - c.du * u;
  c.rho = r0 + k * c.qu;
  c.kappa = k * c.du;
  c.A = dot(c.dp, c.dp) - c.kappa * c.kappa;
  c.half_B = dot(c.qp, c.dp) - c.rho * c.kappa;
  c.C = dot(c.qp, c.qp) - c.rho * c.rho;
  return c;
}

// Whether the root t lies on the finite part of the cone (0 <= s <= h).
template <typename T>
bool cone_in_height(const ConeQuadric<T>& c, T t) {
  const T s = c.qu + t * c.du;
  return s >= T(0) && s <= c.h;
}

// The textbook: both roots t0 <= t1 of the quadric (not yet clipped to the
// height); false when the line misses it. When the ray is parallel to a side
// line (A = 0) the one root is returned twice.
template <typename T>
bool cone_roots_textbook(const ConeQuadric<T>& c, T& t0, T& t1) {
  const T A = c.A;
  const T B = T(2) * c.half_B;
  const T C = c.C;
  if (A == T(0)) {  // parallel to a side line: the equation is linear
    if (B == T(0)) return false;
    t0 = t1 = -C / B;
    return true;
  }
  const T disc = B * B - T(4) * A * C;  // < 0: the line misses the quadric
  if (disc < T(0)) return false;
  const T root = std::sqrt(disc);
  t0 = (-B - root) / (T(2) * A);
  t1 = (-B + root) / (T(2) * A);
  if (t0 > t1) std::swap(t0, t1);  // A < 0 (the ray steeper than the side) flips them
  return true;
}

// f(t) and f'(t) of the quadric along the ray, from its geometric pieces (not
// from A, B, C), for the Newton step.
inline double cone_residual(const ConeQuadric<double>& c, double t, double& slope) {
  const Vec3 w = c.qp + t * c.dp;
  const double r = c.rho + t * c.kappa;
  slope = 2.0 * (dot(w, c.dp) - r * c.kappa);
  return dot(w, w) - r * r;
}

// The careful form (see the top of the file), from the pieces of a quadric set
// up with an origin near the cone (cone_roots_careful does that).
inline bool cone_roots_stable(const ConeQuadric<double>& c, double& t0, double& t1) {
  const double A = c.A, b = c.half_B, C = c.C;
  if (A == 0) {
    if (b == 0) return false;
    t0 = t1 = -C / (2 * b);
  } else {
    // b^2 - A C with one rounding fewer: fma keeps b*b exact inside.
    const double disc = std::fma(b, b, -A * C);
    if (disc < 0) return false;
    const double q = -(b + std::copysign(std::sqrt(disc), b));  // no cancellation
    if (q == 0) {                                                 // b = 0 and A C = 0
      t0 = t1 = 0;
    } else {
      t0 = q / A;
      t1 = C / q;
    }
  }
  for (double* t : {&t0, &t1}) {
    double slope;
    const double f = cone_residual(c, *t, slope);
    // One Newton step, kept only if it does not make the residual worse (near a
    // graze the slope vanishes and the step would throw the root away).
    if (slope != 0 && std::isfinite(f / slope)) {
      const double better = *t - f / slope;
      double s2;
      if (std::abs(cone_residual(c, better, s2)) <= std::abs(f)) *t = better;
    }
  }
  if (t0 > t1) std::swap(t0, t1);
  return true;
}

// Both roots t0 <= t1 (not yet clipped to the height) along o + t d, the careful
// way; c is left holding the quadric about the moved origin o + shift d, and
// the roots returned are along the original ray (shift added back).
inline bool cone_roots_careful(const Vec3& o, const Vec3& d, const Vec3& base, double r0, const Vec3& apex,
                               double r1, ConeQuadric<double>& c, double& shift, double& t0, double& t1) {
  const Vec3 mid = 0.5 * (base + apex);
  shift = dot(mid - o, d) / dot(d, d);
  c = cone_quadric<double>(o + shift * d, d, base, r0, apex, r1);
  if (!cone_roots_stable(c, t0, t1)) return false;
  t0 += shift;
  t1 += shift;
  return true;
}

}  // namespace lockstep
