// lockstep registry: the ray-tracing family's rows (Whitted; core/ray_trace.h).
//
// The family (ray_trace: an NFF scene -> an image, with reflected, refracted
// and shadow rays) and its typed row: each implementation's frame and its
// one-pixel ray tree. The reference is first. props/ray_trace reads the typed
// row; everything generic (verify, render, frame benchmarks) sees the family
// through registry/registry.h.
#pragma once

#include <functional>

#include "core/family.h"
#include "core/ray_trace.h"

namespace lockstep {

// A tracer's frame and one-pixel ray tree for a whole run of many scenes (the
// properties' cases), sharing what they keep (the embree row: one Embree device).
struct TracerRun {
  std::function<Image(const Scene&, const FrameOptions&, FrameStats*)> render;
  std::function<Vec3(const Scene&, const TraceSettings&, int, int, int, int, RayTree*)> pixel;
};

struct TracerFns {
  TraceRenderFn render;
  TracePixelFn pixel;
  // Empty, or starts a run that keeps its state across calls (the embree row's
  // device, made at its first call, shared with every other embree row of the
  // caller's run); the family's FamilyImpl::session is the same.
  TracerRun (*session)(RunResources& run) = nullptr;
};

// fn's session in run when it has one, else its functions as they are.
TracerRun start_run(const TracerFns& fn, RunResources& run);

const KernelRow<TracerFns>& ray_trace_row();
Family ray_trace_family();

}  // namespace lockstep
