// lockstep core: float RGBA images and their files.
//
// Pixels are linear float RGBA, row 0 at the top. Files go through
// OpenImageIO, so the format follows the extension (.png, .exr, .tif, ...).
// Writing is atomic: the image goes to a temporary file in the same folder that
// is renamed into place only when complete, so a failure never leaves a
// half-written output behind.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/math.h"

namespace lockstep {

// An allocator that leaves new floats uninitialised (value-initialisation of a
// 256 MB frame is a whole extra pass over memory). Image(w, h) still zeroes
// explicitly; Image::uninitialized() is for renderers that write every pixel.
template <class T>
struct NoInitAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = NoInitAllocator<U>;
  };
  NoInitAllocator() = default;
  template <class U>
  NoInitAllocator(const NoInitAllocator<U>&) {}
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

struct Image {
  int width = 0, height = 0;
  std::vector<float, NoInitAllocator<float>> rgba;  // width * height * 4
  std::vector<float> depth;  // width * height, or empty: no depth plane (raster families fill it)

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgba(size_t(w) * size_t(h) * 4, 0.0f) {}
  // Every pixel left for the caller to write.
  static Image uninitialized(int w, int h) {
    Image img;
    img.width = w;
    img.height = h;
    img.rgba.resize(size_t(w) * size_t(h) * 4);
    return img;
  }
  float* pixel(int x, int y) { return rgba.data() + (size_t(y) * size_t(width) + size_t(x)) * 4; }
  const float* pixel(int x, int y) const {
    return rgba.data() + (size_t(y) * size_t(width) + size_t(x)) * 4;
  }
  void set(int x, int y, const Vec3& c, float alpha = 1.0f) {
    float* p = pixel(x, y);
    p[0] = float(c.x);
    p[1] = float(c.y);
    p[2] = float(c.z);
    p[3] = alpha;
  }
};

// Throws InputError when the file is missing or unreadable. Any channel count is
// accepted: grey is replicated, a missing alpha is 1.
Image read_image(const std::string& path);
// Throws InputError when the file cannot be written; nothing is left behind then.
// .exr files are zip-compressed (lossless).
void write_image(const Image& image, const std::string& path);
// The same with another OpenEXR compression for .exr files, e.g. "pxr24" (lossy:
// floats rounded to 24 bits, relative error <= 2^-16; the golden images use it,
// at a quarter of zip's size).
void write_image(const Image& image, const std::string& path, const std::string& exr_compression);

}  // namespace lockstep
