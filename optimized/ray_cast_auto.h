// lockstep optimized: ray casting by the simd or the embree row, picked by the
// scene's size (optimized/ray_cast_auto.cpp).
#pragma once

#include <span>

#include "core/ray_cast.h"

namespace lockstep {

namespace opt::autosel {
// Picks simd below the measured crossover (BENCHMARKS.md), embree above.
void trace(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, FrameStats* stats);
Image render(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
// True when auto would use embree for this scene.
bool prefers_embree(const Scene& scene);
}  // namespace opt::autosel

}  // namespace lockstep
