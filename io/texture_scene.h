// lockstep io: texture scenes (.texscene), the texture-filtering family's input.
//
// A text file, one statement a line, '#' starts a comment:
//
//   texture checker 256 8        # procedural, sampled to SIZE x SIZE texels:
//                                #   checker SIZE CELLS   black and white checks, CELLS a side
//                                #   zoneplate SIZE [K]   0.5 + 0.5 sin(pi K r^2 / SIZE), r from the
//                                #                        centre in texels: K r / SIZE cycles a texel
//                                #                        (K = 1: Nyquist at the edge's midpoints)
//                                #   noise SIZE SEED      a sum of 16 cosines below 1/4 cycle a texel
//   texture file photo.png [srgb|linear]   # an image file, relative to this file; 8-bit PNG and
//                                # JPEG are sRGB-decoded by default, others read as linear
//   wrap repeat                  # repeat | clamp | mirror (default repeat)
//   quad  ox oy oz  sx sy sz  tx ty tz   # P(s, t) = o + s S + t T, s, t in [0, 1]
//   repeat 8 8                   # the texture tiles 8 x 8 times across the quad (default 1 1)
//   from 0 1 3                   # the camera, as NFF's viewpoint (core/camera.h)
//   at 0 0 0
//   up 0 1 0
//   angle 45
//   hither 1e-3                  # optional
//   background 0.2 0.3 0.5       # what pixels that miss the quad show
//   resolution 256 256
//
// Every error is an InputError naming the file and the line.
#pragma once

#include <string>

#include "core/texture.h"

namespace lockstep {

TextureScene read_texture_scene(const std::string& path);
// The same from text in memory (name: the file named in errors; folder: where
// `texture file` paths are relative to).
TextureScene parse_texture_scene(const std::string& text, const std::string& name, const std::string& folder);
// A texture by the words of a `texture` line after the keyword ("checker 256 8",
// "file photo.png srgb"; a file's path relative to folder); InputError(file,
// line, ...) when malformed or unreadable.
Texture texture_from_words(const std::string& spec, const std::string& folder, const std::string& file, int line);
// A procedural texture by its words ("checker 256 8"); InputError(file, line, ...) when malformed.
Texture procedural_texture(const std::string& spec, const std::string& file, int line);

// Limits: textures and images at most 16384 a side and 2^26 texels (1 GiB
// of float RGBA); larger ones are refused as absurd (InputError).
inline constexpr int kMaxTextureSide = 16384;
inline constexpr long kMaxTexels = long(1) << 26;

}  // namespace lockstep
