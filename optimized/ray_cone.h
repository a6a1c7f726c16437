// lockstep optimized: NFF's open-ended cones for the optimized rows, in double.
//
// The Embree rows (a user geometry, optimized/embree_cones.cpp), the simd ray
// caster (a scalar pass over the cones after the float packet kernel) and the
// hit refinement (optimized/refine.h) all decide a cone hit here, with the
// careful root form of core/cone_quadric.h (origin moved near the cone, the
// root that does not cancel first, the other from the product, one Newton
// step each). The simd rows run the same arithmetic 4 (AVX2) or 8 (AVX-512)
// rays at a time in double (ray_cast_simd_kernels.h cone_t, bit for bit the
// same as cone_nearest); a float cone kernel would need the same care as the
// sphere's (optimized/refine.h) to pass the 1/255 colour bound, and is not
// written.
//
// What is precomputed per cone: its bounding sphere (for a cheap rejection of
// rays that pass clear of it) and its ends in the caller's frame.
#pragma once

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "core/math.h"
#include "core/scene.h"
#include "core/cone_quadric.h"

namespace lockstep::opt {

struct ConeShape {
  Vec3 base, apex;  // in the caller's frame
  double r0 = 0, r1 = 0;
  bool inside = false;  // NFF's negative radii: only the inside is visible
  Vec3 centre;          // bounding sphere: the axis' midpoint ...
  double bound = 0;     // ... and a radius that holds both end discs
  // The quadric's per-cone pieces, rounded exactly as cone_quadric rounds
  // them (so that the SIMD kernel, which reads them, matches cone_nearest bit
  // for bit): unit axis u, height h, slope k.
  Vec3 u;
  double h = 0, k = 0;
};

inline ConeShape cone_shape(const Vec3& base, double r0, const Vec3& apex, double r1, bool inside) {
  const Vec3 axis = apex - base;
  const double h = std::sqrt(dot(axis, axis));
  ConeShape c{base, apex, r0, r1, inside, 0.5 * (base + apex), 0, axis / h, h, (r1 - r0) / h};
  // Every point of an end disc is within sqrt((h/2)^2 + r^2) of the midpoint.
  const double half = 0.5 * length(apex - base);
  c.bound = std::sqrt(half * half + std::max(r0, r1) * std::max(r0, r1)) * (1 + 1e-12);
  return c;
}

// The nearest root in (tmin, tmax) of the ray o + t d on the cone's finite
// part and on its visible side (solid: either side, ray tracing's rule);
// kInfinity if none. d need not be of unit length.
inline double cone_nearest(const ConeShape& c, const Vec3& o, const Vec3& d, double tmin,
                           double tmax, bool solid) {
  // The ray misses the bounding sphere: no work (most rays, most cones).
  const double dd = dot(d, d);
  const Vec3 f = o - c.centre;
  const double b = dot(f, d) / dd;
  const Vec3 perp = f - b * d;
  if (dot(perp, perp) > c.bound * c.bound) return kInfinity;
  ConeQuadric<double> q;
  double shift, t0, t1;
  if (!cone_roots_careful(o, d, c.base, c.r0, c.apex, c.r1, q, shift, t0, t1))
    return kInfinity;
  for (const double t : {t0, t1}) {
    if (!(t > tmin && t < tmax) || !cone_in_height(q, t - shift)) continue;
    if (!solid) {
      double slope;  // d.n for the outward normal, times 2: < 0 where the ray enters from outside
      cone_residual(q, t - shift, slope);
      if (c.inside ? !(slope > 0) : !(slope < 0)) continue;
    }
    return t;
  }
  return kInfinity;
}

// The kernel row's careful form (core/ray_cast.h RayConeFn): cone_nearest one
// ray at a time, in world coordinates, either side.
inline void ray_cone_careful(std::span<const Ray> rays, const Scene& scene, uint32_t cone,
                             std::span<double> t) {
  const ConeShape c = cone_shape(scene.cone_base[cone], scene.cone_r0[cone], scene.cone_apex[cone],
                                 scene.cone_r1[cone], scene.cone_inside[cone] != 0);
  for (size_t i = 0; i < rays.size(); ++i)
    t[i] = cone_nearest(c, rays[i].o, rays[i].d, rays[i].tmin, rays[i].tmax, true);
}

// Every cone of a scene in a frame (point(), the world-to-frame map).
template <class ToFrame>
std::vector<ConeShape> cone_shapes(const Scene& scene, ToFrame point) {
  std::vector<ConeShape> out;
  out.reserve(scene.cone_count());
  for (uint32_t i = 0; i < scene.cone_count(); ++i)
    out.push_back(cone_shape(point(scene.cone_base[i]), scene.cone_r0[i], point(scene.cone_apex[i]),
                             scene.cone_r1[i], scene.cone_inside[i] != 0));
  return out;
}

}  // namespace lockstep::opt
