// lockstep optimized: rasterization (declarations; the contract is reference/raster.h).
//
//   simd      optimized/zbuffer_simd.cpp  Highway edge functions over tiles, TBB
//   llvmpipe  optimized/raster_llvmpipe.cpp  Mesa's software rasteriser through OSMesa
//             (a production peer; built only where libOSMesa is found:
//             LOCKSTEP_HAVE_OSMESA)
#pragma once

#include "reference/raster.h"

namespace lockstep {

namespace opt::simd {
// Same contract as ref::zbuffer_visibility; threads = 0: all cores.
void zbuffer_visibility(const ScreenMesh& mesh, const RasterSettings& s, int threads, Visibility& vis);
Image zbuffer(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
}  // namespace opt::simd

namespace opt::llvmpipe {
// True when this build has the OSMesa row; version() then names Mesa's version.
bool available();
std::string version();
// Why these settings are beyond the row (shading other than flat or gouraud,
// spp > 1, silhouettes, affine interpolation), or "" when it can draw them
// (ImageImpl::unsupported; zbuffer throws InputError with the same words).
std::string unsupported(const Params& params);
Image zbuffer(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
}  // namespace opt::llvmpipe

}  // namespace lockstep
