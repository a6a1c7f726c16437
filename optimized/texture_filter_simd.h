// lockstep optimized: texture filtering, fast (the contract: reference/texture_filter.h).
//
// One texel is one 4-lane float vector (RGBA; a texel fetch is one 16-byte
// load, no gather), the pyramid is built in those vectors, pixels go in TBB
// tiles (optimized/tiling.h); positions and footprints are computed in double
// as the reference does (texel coordinates reach 10^5 and more, where float
// would move a bilinear weight by 1/256), the colours in float.
#pragma once

#include <array>
#include <memory>

#include "core/family.h"
#include "core/image.h"
#include "core/texture.h"

namespace lockstep::opt::simd {

Image texture_filter(const TextureScene& scene, const FrameOptions& opts, FrameStats* stats);

// Area sampling (filter=area) at single pixels of a width x height frame:
// error=E's yardstick (registry/texture_row.cpp). Thread-safe reads.
class AreaSampler {
 public:
  AreaSampler(const TextureScene& scene, int width, int height);
  ~AreaSampler();
  AreaSampler(const AreaSampler&) = delete;
  AreaSampler& operator=(const AreaSampler&) = delete;
  // RGBA; the background (alpha 1) where the pixel's centre misses the quad.
  std::array<float, 4> at(int x, int y) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lockstep::opt::simd
