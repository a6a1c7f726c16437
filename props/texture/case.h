// lockstep props/texture: a texture-filtering case (a small scene and a filter)
// and its bit-exact text form (hex floats), for counterexample files.
#pragma once

#include <string>

#include "core/texture.h"

namespace lockstep::props::texture {

struct TexCase {
  TextureScene scene;  // scene.width x scene.height is the frame size
  std::string filter = "trilinear";
  std::string tiles;  // a filter per tile (core/texture.h, filter_tiles), or empty
};

std::string write_case(const TexCase& c);
// InputError(file, 0, ...) when the text is not a case.
TexCase read_case(const std::string& text, const std::string& file);

}  // namespace lockstep::props::texture
