// lockstep optimized: texture filtering by OpenImageIO's TextureSystem, a peer row.
//
// The texture is made tiled and mipmapped by ImageBufAlgo::make_texture (a
// temporary .tx file, as maketx makes one, removed when done; its time is the
// frame's build_seconds, shown apart; a session makes it once), then each pixel whose centre sees the quad is
// one TextureSystem::texture call with the footprint's derivatives (the
// projective map's, as our rows use). Filters: point (InterpClosest, no
// MIP), bilinear (no MIP), mip_nearest (MipModeOneLevel), trilinear,
// anisoN (MipModeAniso, anisotropic = N); area, superN and EWA it has not
// (unsupported). Its calls are in the OpenImageIO module (io/oiio.h).
#pragma once

#include <functional>
#include <string>

#include "core/family.h"
#include "core/image.h"
#include "core/texture.h"

namespace lockstep::opt::oiio {

Image texture_filter(const TextureScene& scene, const FrameOptions& opts, FrameStats* stats);
// Frames of one scene's texture, made tiled and mipmapped once (on the first
// frame: its build_seconds) and sampled frame after frame, as an application
// keeps its .tx and TextureSystem (the row's FamilyImpl::session).
std::function<Image(const TextureScene&, const FrameOptions&, FrameStats*)> texture_session(const TextureScene& scene);
// The reason it cannot draw these settings, or "".
std::string texture_unsupported(const Params& params);

}  // namespace lockstep::opt::oiio
