// lockstep reference: Whitted ray tracing, the textbook way (declarations; the
// contract, the settings and the ray tree are in core/ray_trace.h).
#pragma once

#include "core/ray_trace.h"

namespace lockstep::ref {
Image trace_render(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
Vec3 trace_pixel(const Scene& scene, const TraceSettings& settings, int width, int height, int x,
                 int y, RayTree* tree);
}  // namespace lockstep::ref
