// lockstep optimized: alpha compositing, same contract as reference/composite.h.
//
//   opt::simd  Highway premultiplied over (float and exact 8-bit), every layer
//              streamed through memory once, TBB over bands of rows,
//              front-to-back with early termination per block of pixels
//   opt::oiio  OpenImageIO's ImageBufAlgo::over, chained (a production peer)
#pragma once

#include "core/family.h"
#include "core/layers.h"

namespace lockstep::opt {
namespace simd {
Image composite(const LayerStack& stack, const FrameOptions& opts, FrameStats* stats);
}
namespace oiio {
Image composite(const LayerStack& stack, const FrameOptions& opts, FrameStats* stats);
}
}  // namespace lockstep::opt
