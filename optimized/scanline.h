// lockstep optimized: the scanline z-buffer (the contract is core/raster.h
// and reference/scanline.h).
//
//   simd  optimized/scanline_simd.cpp  the reference's edge table, active edge
//         list and exact integer edge walk; spans filled by Highway vectors
//         (depth test + write, 8 floats per AVX2 vector, 16 per AVX-512) with
//         the stored depth interpolated directly (it is affine in screen space);
//         bands of rows on TBB; the visible samples shaded by the simd
//         z-buffer's SIMD kernel (opt::simd::shade_visibility, optimized/raster.h).
#pragma once

#include "core/raster.h"

namespace lockstep {

namespace opt::simd {
// Same contract as ref::scanline_visibility; threads = 0: all cores.
void scanline_visibility(const ScreenMesh& mesh, const RasterSettings& s, int threads,
                         Visibility& vis);
Image scanline(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
// The Highway target the span fills run on ("AVX2", "AVX3", ...).
const char* scanline_target_name();
// Float lanes per vector of that target (the span fill's step).
size_t scanline_lanes();
}  // namespace opt::simd

}  // namespace lockstep
