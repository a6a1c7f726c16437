// lockstep optimized: refining the winning hit in double.
//
// The float kernels decide *which* primitive a ray hits first; its t carries
// float's relative error (~6e-8), which is fine for the decision but not for a
// hit point 1e6 radii from the camera, where the shading normal (P - c)/r would
// be off by several percent. So once per pixel, the winner's t is recomputed in
// double: the numerically stable sphere form (Ray Tracing Gems ch. 7) or the
// plane equation. Cost: one primitive per ray, not one per primitive.
#pragma once

#include <cmath>

#include "core/math.h"
#include "core/scene.h"
#include "core/cone_quadric.h"

namespace lockstep::opt {

// Both roots of the ray against the sphere, stable form; false on a miss.
inline bool stable_sphere_roots(const Vec3& o, const Vec3& d, const Vec3& c, double r, double& t0,
                                double& t1) {
  const double len = length(d);
  const Vec3 u = d / len;
  const Vec3 f = o - c;
  const double b = dot(f, u);
  // Squared distance from the centre to the line, from the perpendicular vector:
  // no cancellation between b^2 and |f|^2 even when the sphere is tiny and far.
  const Vec3 l = f - b * u;
  const double disc = r * r - dot(l, l);
  if (disc < 0) return false;
  const double cc = dot(f, f) - r * r;
  const double q = -b - std::copysign(std::sqrt(disc), b);
  double a0 = q != 0 ? cc / q : 0.0, a1 = q;
  if (a0 > a1) std::swap(a0, a1);
  t0 = a0 / len;
  t1 = a1 / len;
  return true;
}

// Recomputes hit.t in double for the primitive the kernel chose. Keeps the
// kernel's t when double precision disagrees about there being a hit at all
// (a graze that float saw and double did not).
inline void refine_hit(const Scene& scene, const Ray& ray, Hit& hit) {
  if (!hit.hit()) return;
  if (hit.prim < scene.sphere_count()) {
    const double r = scene.sphere_radius[hit.prim];
    double t0, t1;
    if (!stable_sphere_roots(ray.o, ray.d, scene.sphere_center[hit.prim], std::abs(r), t0, t1)) return;
    // The root nearest the float answer is the one the kernel meant.
    hit.t = std::abs(t0 - hit.t) <= std::abs(t1 - hit.t) ? t0 : t1;
  } else if (hit.prim >= scene.cone_first_prim()) {
    // Cones: the careful roots (core/cone_quadric.h), the one nearest the kernel's.
    const uint32_t c = hit.prim - scene.cone_first_prim();
    ConeQuadric<double> q;
    double shift, t0, t1;
    if (!cone_roots_careful(ray.o, ray.d, scene.cone_base[c], scene.cone_r0[c],
                                 scene.cone_apex[c], scene.cone_r1[c], q, shift, t0, t1))
      return;
    hit.t = std::abs(t0 - hit.t) <= std::abs(t1 - hit.t) ? t0 : t1;
  } else {
    const Plane& pl = scene.poly_plane[hit.prim - scene.sphere_count()];
    const double den = dot(pl.n, ray.d);
    if (den == 0) return;
    const double t = -(dot(pl.n, ray.o) + pl.d) / den;
    if (std::isfinite(t)) hit.t = t;
  }
}

// Renders: float's t is good to ~1e-7 relative, which shading needs better only
// for a sphere seen from more than ~1000 radii away (its normal is (P - c)/r).
inline bool needs_far_sphere_refinement(const Scene& scene, const Hit& hit) {
  return hit.hit() && hit.prim < scene.sphere_count() && hit.t > 1e3 * std::abs(scene.sphere_radius[hit.prim]);
}
inline void refine_far_sphere_hit(const Scene& scene, const Ray& ray, Hit& hit) {
  if (needs_far_sphere_refinement(scene, hit)) refine_hit(scene, ray, hit);
}

}  // namespace lockstep::opt
