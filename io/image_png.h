// lockstep io: PNG files through libpng itself, not through OpenImageIO's
// module (io/oiio.h), so that a render to .png does not map OpenImageIO's
// ~300 libraries (issue #31, item 6).
//
// The writer makes the file OpenImageIO's PNG writer made for lockstep: 8-bit
// RGBA, each float rounded as OpenImageIO rounded it (the float v * 255
// rounded half away from zero, clamped; NaN is 0), colour un-premultiplied in 8 bits as OpenImageIO
// did it (c * 255 / a, truncated, for a > 0), zlib level 6, no filters, an oFFs chunk of (0, 0) and
// nothing else: byte for byte the same file (tests/cli/image_io_parity.sh). The reader takes 8-bit
// grey, grey + alpha, RGB and RGBA files, not interlaced, without palette, tRNS, gAMA, sRGB or iCCP
// chunks, and declines the rest, which the caller hands to OpenImageIO.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"

namespace lockstep::io {

// Writes image to path (its own name: no temporary, no rename). Throws
// std::exception when the file cannot be written; the caller removes it then.
void write_png(const Image& image, const std::string& path);

struct Png8 {
  int width = 0, height = 0;
  int channels = 0;              // 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA
  std::vector<uint8_t> samples;  // the file's own values, interleaved
};
// The file's samples, or nullopt when the file is not one this reader takes
// or does not read (missing, truncated, corrupt): the caller asks OpenImageIO
// then, which reads it or reports why not.
std::optional<Png8> read_png(const std::string& path);

}  // namespace lockstep::io
