// Ray-sphere intersection, the textbook way.
//
// Source: the algebraic method in Glassner (ed.), "An Introduction to Ray
// Tracing", ch. 2 (Haines, "Essential Ray Tracing Algorithms"), as taught in
// most graphics courses. Written as a template so that the same formula can be
// evaluated in float and in double for the accuracy charts.
#pragma once

#include <cmath>

#include "core/math.h"

namespace lockstep::ref {

// Both roots t0 <= t1 of |o + t d - c|^2 = r^2; false when the ray misses.
template <typename T>
bool sphere_roots(const Vec3T<T>& o, const Vec3T<T>& d, const Vec3T<T>& c, T r, T& t0, T& t1) {
  // Substitute P(t) = o + t d into (P - c).(P - c) - r^2 = 0 to get A t^2 + B t + C = 0.
  const Vec3T<T> oc = o - c;
  const T A = dot(d, d);
  const T B = T(2) * dot(d, oc);
  const T C = dot(oc, oc) - r * r;
  // The discriminant decides: < 0 the line misses, = 0 it grazes, > 0 it cuts the sphere twice.
  const T disc = B * B - T(4) * A * C;
  if (disc < T(0)) return false;
  if (disc == T(0)) {
    t0 = t1 = -B / (T(2) * A);  // graze: one double root
    return true;
  }
  const T root = std::sqrt(disc);
  t0 = (-B - root) / (T(2) * A);  // nearer root
  t1 = (-B + root) / (T(2) * A);  // farther root
  return true;
}

}  // namespace lockstep::ref
