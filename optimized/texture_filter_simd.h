// lockstep optimized: texture filtering, fast (the contract: reference/texture_filter.h).
//
// One texel is one 4-lane float vector (RGBA; a texel fetch is one 16-byte
// load, no gather), the pyramid is built in those vectors, pixels go in TBB
// tiles (optimized/tiling.h); positions and footprints are computed in double
// as the reference does (texel coordinates reach 10^5 and more, where float
// would move a bilinear weight by 1/256), the colours in float.
#pragma once

#include "core/family.h"
#include "core/image.h"
#include "core/texture.h"

namespace lockstep::opt::simd {

Image texture_filter(const TextureScene& scene, const FrameOptions& opts, FrameStats* stats);

}  // namespace lockstep::opt::simd
