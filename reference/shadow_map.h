// lockstep reference: pass 1 of shadow mapping (Williams 1978), textbook style
// -- each light's depth drawn into the six faces of its cube map by the
// reference z-buffer itself (namespace ref). The cube's geometry, what a texel
// stores and the test of pass 2 are core/shadow_map.h; pass 2 is ref::zbuffer
// with shadows=map (reference/zbuffer.cpp).
#pragma once

#include "core/raster.h"
#include "core/scene.h"
#include "core/shadow_map.h"

namespace lockstep::ref {

// Every light's cube map, map_size x map_size per face: for each face, the
// viewing pipeline (core/viewing.cpp) with the face's camera, then
// ref::zbuffer_visibility, then the distance of each texel's nearest surface.
ShadowMaps shadow_maps(const Scene& scene, const RasterSettings& s);

}  // namespace lockstep::ref
