// lockstep registry: the raster families' rows (an NFF scene -> an image with depth).
//
//   zbuffer   reference (reference/zbuffer.cpp), simd, llvmpipe (Mesa, a peer)
//   scanline  reference, simd
//   painter   reference, simd
//
// All read the same NFF scenes as ray_cast and take the settings of
// core/raster.h (raster_params()) through FrameOptions::params.
#pragma once

#include "core/family.h"

namespace lockstep {

Family zbuffer_family();
Family scanline_family();
Family painter_family();

}  // namespace lockstep
