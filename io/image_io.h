// lockstep io: image files. The format follows the extension: .exr and .png
// through OpenEXR and libpng directly (io/image_exr.cpp, io/image_png.cpp),
// every other format, every file those decline and every failure through
// OpenImageIO in lockstep_oiio.so (io/oiio.h), opened by the first read or
// write that needs it. Writing is atomic (a temporary file renamed into place).
#pragma once

#include <string>

#include "core/image.h"

namespace lockstep {

// Throws InputError when the file is missing or unreadable. Any channel count is
// accepted: grey is replicated, a missing alpha is 1.
Image read_image(const std::string& path);
// Throws InputError when the file cannot be written; nothing is left behind then.
// .exr files are zlib-compressed (lossless) one scanline per block at zlib level
// 1 ("zips:1"): on a 1024^2 float RGBA z-buffer frame OpenEXR writes it 1.5-3x
// faster than the default "zip" (16 scanlines, level 6), the file 3.5 MB
// against 2.9 MB (issue #21, one-shot cost; the writer was most of a one-shot
// render's own time). Any OpenEXR reader reads both.
void write_image(const Image& image, const std::string& path);
// The same with another OpenEXR compression for .exr files, e.g. "pxr24" (lossy:
// floats rounded to 24 bits, relative error <= 2^-16; the golden images use it,
// at a quarter of zip's size).
void write_image(const Image& image, const std::string& path, const std::string& exr_compression);
// Whether a writer exists for path's extension (.exr and .png without opening
// OpenImageIO's module; any other extension asks it).
bool image_has_writer(const std::string& path);

}  // namespace lockstep
