// lockstep optimized: ray casting with Highway 8-ray packets over TBB tiles
// (optimized/ray_cast_simd.cpp; kernels: ray_cast_simd_kernels.cpp; float
// scene: simd_scene.cpp; per-tile culling: cone_cull.cpp; tiles: tiling.h),
// the contract of core/ray_cast.h.
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

}  // namespace lockstep
