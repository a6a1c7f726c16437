// lockstep registry: the compositing family's row (a layer stack -> an image).
#pragma once

#include "core/family.h"

namespace lockstep {

// reference, simd, oiio (OpenImageIO's ImageBufAlgo::over, a production peer).
Family composite_family();

}  // namespace lockstep
