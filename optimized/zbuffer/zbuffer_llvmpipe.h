// lockstep optimized: the z-buffer drawn by Mesa's llvmpipe through OSMesa, a
// production peer (optimized/raster_llvmpipe.cpp; its GL context and module:
// optimized/raster_llvmpipe.h), the contract of core/raster.h. Built only where
// libOSMesa is found (LOCKSTEP_HAVE_OSMESA); available() says.
#pragma once

#include <string>

#include "core/family.h"
#include "core/raster.h"

namespace lockstep {

namespace opt::llvmpipe {
// True when this build has the OSMesa row; version() then names Mesa's version.
bool available();
std::string version();
// Why these settings are beyond the row (shading other than flat or gouraud,
// spp > 1, silhouettes, affine interpolation), or "" when it can draw them
// (FamilyImpl::unsupported; zbuffer throws InputError with the same words).
std::string unsupported(const Params& params);
Image zbuffer(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
}  // namespace opt::llvmpipe

}  // namespace lockstep
