// lockstep optimized: ray casting through Embree 3, a production peer
// (optimized/ray_cast_embree.cpp), the contract of core/ray_cast.h.
#pragma once

#include <span>

#include "core/ray_cast.h"

namespace lockstep {

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

}  // namespace lockstep
