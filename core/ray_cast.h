// lockstep core: the ray-casting contract.
//
// Every ray-casting implementation (namespace ref, opt::simd, opt::embree,
// opt::autosel) provides the functions below with exactly these signatures, and
// core/pairs.h lists which implementation provides which. Properties, benchmarks,
// the corpus and the CLI only ever call them through that table.
//
// Kernels: one primitive, every ray, *no* culling; t[i] is the nearest root of
// ray i in (tmin, tmax), +inf on a miss. t is in units of |d|.
//   ray_sphere   substitute the ray into |P - c|^2 = r^2
//   ray_plane    n.P + d = 0
//   ray_polygon  plane, then inside the polygon (concave allowed)
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

#include "core/image.h"
#include "core/math.h"
#include "core/scene.h"

namespace lockstep {

struct RenderOptions {
  int width = 256;
  int height = 256;
  int threads = 0;                         // 0: all cores
  std::function<void(double)> progress;    // called with the fraction done, may be empty
};

// What a render or trace measured about itself.
struct RenderStats {
  double build_seconds = 0;  // acceleration structure (Embree BVH), 0 when none
  double trace_seconds = 0;  // intersection and shading
  uint64_t rays = 0;
  std::string chosen;  // for auto: which implementation it picked and why
};

using RaySphereFn = void (*)(std::span<const Ray> rays, const Sphere& sphere, std::span<double> t);
using RayPlaneFn = void (*)(std::span<const Ray> rays, const Plane& plane, std::span<double> t);
using RayPolygonFn = void (*)(std::span<const Ray> rays, const Scene& scene, uint32_t poly,
                              std::span<double> t);
using TraceFn = void (*)(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits,
                         RenderStats* stats);
using RenderFn = Image (*)(const Scene& scene, const RenderOptions& opts, RenderStats* stats);

namespace ref {
// Textbook, double precision.
void ray_sphere(std::span<const Ray> rays, const Sphere& sphere, std::span<double> t);
void ray_plane(std::span<const Ray> rays, const Plane& plane, std::span<double> t);
void ray_polygon(std::span<const Ray> rays, const Scene& scene, uint32_t poly, std::span<double> t);
// The same textbook formulas evaluated in float (inputs rounded to float), for
// the speed/accuracy chart: how much the method, not the code, loses.
void ray_sphere_f32(std::span<const Ray> rays, const Sphere& sphere, std::span<double> t);
void ray_plane_f32(std::span<const Ray> rays, const Plane& plane, std::span<double> t);
void trace(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, RenderStats* stats);
Image render(const Scene& scene, const RenderOptions& opts, RenderStats* stats);
}  // namespace ref

namespace opt::simd {
void ray_sphere(std::span<const Ray> rays, const Sphere& sphere, std::span<double> t);
void ray_plane(std::span<const Ray> rays, const Plane& plane, std::span<double> t);
void ray_polygon(std::span<const Ray> rays, const Scene& scene, uint32_t poly, std::span<double> t);
void trace(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, RenderStats* stats);
Image render(const Scene& scene, const RenderOptions& opts, RenderStats* stats);
// Name of the Highway target the kernels dispatch to on this machine (e.g. "AVX2").
const char* target_name();
}  // namespace opt::simd

namespace opt::embree {
void trace(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, RenderStats* stats);
Image render(const Scene& scene, const RenderOptions& opts, RenderStats* stats);
}  // namespace opt::embree

namespace opt::autosel {
// Picks simd below the measured crossover (BENCHMARKS.md), embree above.
void trace(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, RenderStats* stats);
Image render(const Scene& scene, const RenderOptions& opts, RenderStats* stats);
// True when auto would use embree for this scene.
bool prefers_embree(const Scene& scene);
}  // namespace opt::autosel

}  // namespace lockstep
