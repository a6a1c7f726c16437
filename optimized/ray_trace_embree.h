// lockstep optimized: ray tracing, the contract of core/ray_trace.h, fast.
//
//   opt::embree   optimized/ray_trace_embree.cpp  Embree 3 for every ray, TBB tiles,
//                 the robust self-intersection offset (Ray Tracing Gems ch. 6)
#pragma once

#include "core/ray_trace.h"

namespace lockstep::opt::embree {
struct Device;  // optimized/embree_scene.h
// Without a device: a new one for this frame (the CLI's one render per process).
Image trace_render(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
// On a device kept across frames (a session's).
Image trace_render_with(const Scene& scene, const FrameOptions& opts, FrameStats* stats,
                        const Device& device);
Vec3 trace_pixel(const Scene& scene, const TraceSettings& settings, int width, int height, int x,
                 int y, RayTree* tree);
Vec3 trace_pixel_with(const Scene& scene, const TraceSettings& settings, int width, int height,
                      int x, int y, RayTree* tree, const Device& device);
}  // namespace lockstep::opt::embree
