// lockstep pairs: the ray-tracing family's rows (Whitted; core/ray_trace.h).
//
// The family (raytrace: an NFF scene -> an image, with reflected, refracted
// and shadow rays) and its typed row: each implementation's frame and its
// one-pixel ray tree. The reference is first. props/ray_trace reads the typed
// row; everything generic (verify, render, frame benchmarks) sees the family
// through pairs/registry.h.
#pragma once

#include "core/family.h"
#include "core/ray_trace.h"

namespace lockstep {

struct TracerFns {
  TraceRenderFn render;
  TracePixelFn pixel;
};

const KernelRow<TracerFns>& ray_trace_row();
Family ray_trace_family();

}  // namespace lockstep
