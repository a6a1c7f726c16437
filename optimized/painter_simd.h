// lockstep optimized: the painter's algorithm (optimized/painter_simd.cpp; the
// plan it shares is core/painter_plan.h, the reference reference/painter.h).
#pragma once

#include "optimized/zbuffer/zbuffer_simd.h"
#include "optimized/zbuffer/zbuffer_llvmpipe.h"
#include "core/painter_plan.h"

namespace lockstep::opt::simd {
// Same plan and image as ref::painter: the depth sort with Highway's vqsort,
// the pair tests over TBB threads (the reference's exact predicates), owners
// painted span by span with SIMD stores, each visible sample shaded once.
Image painter(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
// The depth sort alone (== ref painter_sort), for the tests and the benchmarks.
std::vector<uint32_t> depth_sort(const std::vector<PainterTri>& tris);
}  // namespace lockstep::opt::simd
