// lockstep reference: ray casting, the textbook way (declarations; the
// contract and the function types are in core/ray_cast.h).
//
//   ray_sphere   reference/ray_sphere.cpp   (Glassner ch. 2, the quadratic)
//   ray_plane    reference/ray_plane.cpp
//   ray_polygon  reference/ray_polygon.cpp  (plane, then the crossings test)
//   ray_cone_t   reference/ray_cone.cpp     (the cone's quadric, core/cone_quadric.h)
//   trace/render reference/ray_cast.cpp     (brute force over every primitive)
#pragma once

#include <span>

#include "core/ray_cast.h"

namespace lockstep {

namespace ref {
// Textbook, double precision.
void ray_sphere(std::span<const Ray> rays, const Sphere& sphere, std::span<double> t);
void ray_plane(std::span<const Ray> rays, const Plane& plane, std::span<double> t);
void ray_polygon(std::span<const Ray> rays, const Scene& scene, uint32_t poly, std::span<double> t);
// The same textbook formulas evaluated in float (inputs rounded to float), for
// the speed/accuracy chart: how much the method, not the code, loses.
void ray_sphere_f32(std::span<const Ray> rays, const Sphere& sphere, std::span<double> t);
void ray_plane_f32(std::span<const Ray> rays, const Plane& plane, std::span<double> t);
void trace(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, FrameStats* stats);
// The nearest visible hit along one ray by brute force over every primitive
// (what trace() does per ray). Spheres follow NFF's sidedness (seen from
// outside, from inside for r < 0), or are solids: the first root in range,
// whatever its side (ray tracing: a refracted ray leaves a glass ball through
// its far wall; core/ray_trace.h). Polygons follow NFF's sidedness either way.
enum class SphereSides : uint8_t { kNff, kSolid };
// Cones follow the same rule as spheres (NFF: the outside, or the inside when
// the file's radii were negative; kSolid: either side).
Hit nearest_hit(const Scene& scene, const Ray& ray, SphereSides sides = SphereSides::kNff);
// The nearest root of cone `cone` in (ray.tmin, tmax) on its visible side (as
// above), kInfinity if none; the stable form, or the textbook one.
double ray_cone_t(const Scene& scene, uint32_t cone, const Ray& ray, double tmax, SphereSides sides,
                  bool textbook = false);
// The kernel row (core/ray_cast.h RayConeFn): the textbook quadric, either side.
void ray_cone(std::span<const Ray> rays, const Scene& scene, uint32_t cone, std::span<double> t);
Image render(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
}  // namespace ref

}  // namespace lockstep
