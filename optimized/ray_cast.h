// lockstep optimized: ray casting, the same contract as core/ray_cast.h, fast.
//
//   opt::simd     optimized/ray_cast_simd.cpp    Highway 8-ray packets, TBB tiles
//                 (kernels: ray_cast_simd_kernels.cpp; float scene: simd_scene.cpp;
//                 per-tile culling: cone_cull.cpp; tiles: tiling.h)
//   opt::embree   optimized/ray_cast_embree.cpp  Embree 3 (a production peer)
//   opt::autosel  optimized/ray_cast_auto.cpp    simd or embree by scene size
#pragma once

#include <span>

#include "core/ray_cast.h"

namespace lockstep {

namespace opt::simd {
void ray_sphere(std::span<const Ray> rays, const Sphere& sphere, std::span<double> t);
void ray_plane(std::span<const Ray> rays, const Plane& plane, std::span<double> t);
void ray_polygon(std::span<const Ray> rays, const Scene& scene, uint32_t poly, std::span<double> t);
// The cone kernel (ray_cast_simd_kernels.h cone_t): double, 4 or 8 rays a time.
void ray_cone(std::span<const Ray> rays, const Scene& scene, uint32_t cone, std::span<double> t);
void trace(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, FrameStats* stats);
Image render(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
// Name of the Highway target the kernels dispatch to on this machine (e.g. "AVX2").
const char* target_name();
}  // namespace opt::simd

namespace opt::embree {
struct Device;  // optimized/embree_scene.h
void trace(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, FrameStats* stats);
// On a device kept across calls (a session's: verify, the properties).
void trace_with(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, FrameStats* stats,
                const Device& device);
// Without a device: a new one for this frame (the CLI's one render per process).
Image render(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
// On a device kept across frames (a session's).
Image render_with(const Scene& scene, const FrameOptions& opts, FrameStats* stats,
                  const Device& device);
// The same traversal with shading off: each pixel's t, grey (bench/timing/embree_raw.cpp).
Image render_unshaded(const Scene& scene, const FrameOptions& opts, FrameStats* stats,
                      const Device& device);
}  // namespace opt::embree

namespace opt::autosel {
// Picks simd below the measured crossover (BENCHMARKS.md), embree above.
void trace(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, FrameStats* stats);
Image render(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
// True when auto would use embree for this scene.
bool prefers_embree(const Scene& scene);
}  // namespace opt::autosel

}  // namespace lockstep
