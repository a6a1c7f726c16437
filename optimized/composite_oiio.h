// lockstep optimized: compositing by OpenImageIO's ImageBufAlgo::over, a
// production peer (optimized/composite_oiio.cpp, through the OpenImageIO module).
#pragma once

#include "core/family.h"
#include "io/layers.h"

namespace lockstep {

namespace opt::oiio {
Image composite(const LayerStack& stack, const FrameOptions& opts, FrameStats* stats);
}  // namespace opt::oiio

}  // namespace lockstep
