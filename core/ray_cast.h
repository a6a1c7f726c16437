// lockstep core: the ray-casting contract.
//
// Every ray-casting implementation (namespace ref: reference/ray_cast.h;
// opt::simd, opt::embree, opt::autosel: optimized/ray_cast_simd.h, ray_cast_embree.h, ray_cast_auto.h) provides functions
// of exactly the types below, and registry/ray_cast_row.cpp lists which implementation
// provides which. Properties, benchmarks, the corpus and the CLI only ever call
// them through the registry (registry/registry.h).
//
// Kernels: one primitive, every ray, *no* culling; t[i] is the nearest root of
// ray i in (tmin, tmax), +inf on a miss. t is in units of |d|.
//   ray_sphere   substitute the ray into |P - c|^2 = r^2
//   ray_plane    n.P + d = 0
//   ray_polygon  plane, then inside the polygon (concave allowed)
//   ray_cone     the cone's quadric, roots on its finite part (0 <= height <= h)
//
// Frames: the whole scene, nearest *visible* hit (NFF sidedness: see
// core/shading.h visible_side), shading by core/shading.h.
//   trace        arbitrary rays -> Hit (t in units of |d| of each ray); rays
//                start at their origin or later (0 <= tmin): sidedness is decided
//                from where the ray starts, which a negative tmin would move
//   render       the scene's viewpoint at opts.width x opts.height (core/camera.h)
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>

#include "core/family.h"
#include "core/image.h"
#include "core/math.h"
#include "core/scene.h"

namespace lockstep {

// Frames are run with the registry's FrameOptions and report FrameStats
// (core/family.h): items = rays traced, build_seconds = acceleration structure.
using RaySphereFn = void (*)(std::span<const Ray> rays, const Sphere& sphere, std::span<double> t);
using RayPlaneFn = void (*)(std::span<const Ray> rays, const Plane& plane, std::span<double> t);
using RayPolygonFn = void (*)(std::span<const Ray> rays, const Scene& scene, uint32_t poly,
                              std::span<double> t);
// Cones (NFF 'c', open-ended, either side: no culling): the scene's cone `cone`.
using RayConeFn = void (*)(std::span<const Ray> rays, const Scene& scene, uint32_t cone,
                           std::span<double> t);
using TraceFn = void (*)(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits,
                         FrameStats* stats);
using RenderFn = Image (*)(const Scene& scene, const FrameOptions& opts, FrameStats* stats);

}  // namespace lockstep
