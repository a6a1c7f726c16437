// lockstep io: OpenEXR files through OpenEXR itself (libOpenEXR), not through
// OpenImageIO's module (io/oiio.h), so that a render to .exr does not map
// OpenImageIO's ~300 libraries (issue #31, item 6).
//
// The writer makes the file OpenImageIO's OpenEXR writer made for lockstep:
// float R, G, B, A (stored A, B, G, R: OpenEXR sorts channel names), scanlines,
// the data and display windows at the origin, the same header attributes
// (capDate is the local time of writing, as OpenImageIO's DateTime was) and
// the same compression and zlib level: byte for byte the same file but for the
// capDate (tests/cli/image_io_parity.sh). The reader takes the files lockstep
// writes and reads (RGB or RGBA, half or float, one part, not deep) and
// declines the rest, which the caller hands to OpenImageIO.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/image.h"

namespace lockstep::io {

// A compression this writer makes as OpenImageIO did: "none", "rle", "zips",
// "zip", "piz", "pxr24", with ":LEVEL" for zip and zips (zlib level 1-9).
bool exr_compression_known(const std::string& compression);
// Writes image to path (its own name: no temporary, no rename). Throws
// std::exception when the file cannot be written; the caller removes it then.
void write_exr(const Image& image, const std::string& path, const std::string& compression);

struct ExrPixels {
  int width = 0, height = 0;
  int channels = 0;  // 3 (R, G, B) or 4 (R, G, B, A), interleaved in that order
  std::vector<float> values;
};
// The file's data window as floats, or nullopt when the file is not one this
// reader takes (other channels, integer channels, subsampled, deep, an
// "oiio:UnassociatedAlpha" attribute) or does not read (missing, truncated,
// not OpenEXR): the caller asks OpenImageIO then, which reads it or reports why not.
std::optional<ExrPixels> read_exr(const std::string& path);

}  // namespace lockstep::io
