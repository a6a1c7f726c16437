// lockstep core: float RGBA images and their files.
//
// Pixels are linear float RGBA, row 0 at the top. Files: io/image_io.h (the
// format follows the extension: .exr and .png through OpenEXR and libpng,
// every other format through OpenImageIO's module).
// Writing is atomic: the image goes to a temporary file in the same folder that
// is renamed into place only when complete, so a failure never leaves a
// half-written output behind.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "core/large_buffer.h"
#include "core/math.h"

namespace lockstep {

// Image's planes: NoInitAllocator (core/large_buffer.h) leaves new floats
// uninitialised (value-initialisation of a 256 MB frame is a whole extra pass
// over memory); Image(w, h) still zeroes explicitly; Image::uninitialized() is
// for renderers that write every pixel. Planes of 4 MiB and up are on huge
// pages where the kernel allows (core/large_buffer.h).
//
// Large buffers (kSpacedBytes and up) start on a page and are followed by at
// least a page of unused address space, never touched, so never backed by
// memory: consecutive buffers are never a power of two apart. Without the
// gap, buffers allocated one after another from a heap that does not use mmap
// for them (the benchmarks' mallopt(M_MMAP_MAX, 0)) sit exactly size + 16
// bytes apart: two 4096^2 float layers 256 MiB + 16 B apart, the same address
// bits up to bit 27, and streaming both at once (out = L0 over L1) ran at well
// under half the speed of the same layers a page further apart (measured on
// the 2-core AMD EPYC VM: 55-75 ms of CPU per 4096^2 float two-layer
// composite against 21-29 ms; the 8-bit layers of Layer::rgba8, 64 MiB + 16 B
// apart, about 200 ms against 24). Page alignment also makes every large
// buffer 64-byte aligned: vector loads never straddle cache lines.
//
// Huge pages, history. Frames of 2-64 MiB once started on a 2 MiB boundary
// with MADV_HUGEPAGE (issue #21, cold first frame): a fresh 1024^2 z-buffer
// frame's 16 MiB colour and 4 MiB depth then took 13 faults instead of 5,120,
// but 1 frame in 4-8 took 100-190 ms (fresh huge pages that the VM's host had
// not backed yet), so the advice went. Issue #35 measured again, on whole
// one-shot calls (core/large_buffer.h); BENCHMARKS.md has the figures.
struct Image {
  int width = 0, height = 0;
  std::vector<float, NoInitAllocator<float>> rgba;  // width * height * 4
  std::vector<float, NoInitAllocator<float>> depth;  // width * height, or empty: no depth plane (raster families fill it; resize leaves it unwritten)

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

}  // namespace lockstep
