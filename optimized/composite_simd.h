// lockstep optimized: alpha compositing, same contract as reference/composite.h:
// Highway premultiplied over (float and exact 8-bit), every layer streamed
// through memory once, TBB over bands of rows, front-to-back with early
// termination per block of pixels (optimized/composite_simd.cpp).
#pragma once

#include "core/family.h"
#include "io/layers.h"

namespace lockstep {

namespace opt::simd {
Image composite(const LayerStack& stack, const FrameOptions& opts, FrameStats* stats);
// The same into a caller's buffer of width * height * 4 floats (its contents are
// ignored: every value is written once, with streaming stores). For timing
// without the allocation and first touch of a fresh Image, and for callers that
// reuse a frame buffer.
void composite_into(const LayerStack& stack, const FrameOptions& opts, float* out,
                    FrameStats* stats);
// The Highway target the kernels dispatch to on this CPU (e.g. "AVX3").
const char* composite_target_name();
}  // namespace opt::simd

}  // namespace lockstep
