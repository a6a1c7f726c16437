// lockstep optimized: the scanline z-buffer (the contract is core/raster.h
// and reference/scanline.h).
//
//   simd  optimized/scanline_simd.cpp  the reference's edge table, active edge
//         list and exact integer edge walk; spans filled by Highway vectors
//         (depth test + write, 8 floats per AVX2 vector, 16 per AVX-512) with
//         the stored depth interpolated directly (it is affine in screen space);
//         bands of rows on TBB; the visible samples shaded by the simd
//         z-buffer's SIMD kernel (opt::simd::shade_visibility, optimized/zbuffer/zbuffer_simd.h).
#pragma once

#include "core/raster.h"

namespace lockstep {

namespace opt::simd {
// Same contract as ref::scanline_visibility; threads = 0: all cores.
void scanline_visibility(const ScreenMesh& mesh, const RasterSettings& s, int threads,
                         Visibility& vis);
Image scanline(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
// A session's buffers (registry/raster_rows.cpp) kept from frame to frame (see
// opt::simd::zbuffer_into): the frame and the per-sample visible triangles.
using VisibleBuffer = std::vector<uint32_t, NoInitAllocator<uint32_t>>;
// Sized for scene's frames at opts (its settings' samples per pixel), every page touched now.
VisibleBuffer visible_buffer(const Scene& scene, const FrameOptions& opts);
// The frame drawn into img (img and visible resized where the frame needs it).
void scanline_into(const Scene& scene, const FrameOptions& opts, FrameStats* stats, Image& img,
                   VisibleBuffer& visible);
// The Highway target the span fills run on ("AVX2", "AVX3", ...).
const char* scanline_target_name();
// Float lanes per vector of that target (the span fill's step).
size_t scanline_lanes();
}  // namespace opt::simd

}  // namespace lockstep
