// lockstep registry: the texture-filtering family's row (a texture scene -> an image).
#pragma once

#include "core/family.h"

namespace lockstep {

// reference, simd, oiio (OpenImageIO's TextureSystem, a production peer) (issue #32).
Family texture_family();

}  // namespace lockstep
