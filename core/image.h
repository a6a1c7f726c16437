// lockstep core: float RGBA images and their files.
//
// Pixels are linear float RGBA, row 0 at the top. Files go through
// OpenImageIO, so the format follows the extension (.png, .exr, .tif, ...).
// Writing is atomic: the image goes to a temporary file in the same folder that
// is renamed into place only when complete, so a failure never leaves a
// half-written output behind.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "core/math.h"

namespace lockstep {

// An allocator that leaves new floats uninitialised (value-initialisation of a
// 256 MB frame is a whole extra pass over memory). Image(w, h) still zeroes
// explicitly; Image::uninitialized() is for renderers that write every pixel.
//
// Large buffers (kSpacedBytes and up) start on a page and are followed by at
// least a page (less 8 bytes) of unused address space, never touched, so never
// backed by memory: consecutive buffers are never a power of two apart.
// Without the gap, buffers allocated one after another from a heap that does
// not use mmap for them (the benchmarks' mallopt(M_MMAP_MAX, 0)) sit exactly
// size + 16 bytes apart: two 4096^2 float layers 256 MiB + 16 B apart, the same
// address bits up to bit 27, and streaming both at once (out = L0 over L1) ran
// at well under half the speed of the same layers a page further apart
// (measured on the 2-core AMD EPYC VM: 55-75 ms of CPU per 4096^2 float
// two-layer composite against 21-29 ms; the 8-bit layers of Layer::rgba8,
// 64 MiB + 16 B apart, about 200 ms against 24). Default glibc mmaps such
// blocks, a page apart already. Page alignment also makes every large buffer
// 64-byte aligned: vector loads never straddle cache lines.
// Blocks from kHugeMinBytes up to kHugeMaxBytes start on a 2 MiB boundary and
// ask the kernel for 2 MiB pages (transparent huge pages, MADV_HUGEPAGE: the
// "madvise" mode of Debian's kernels). A fresh frame's first touch then costs
// one fault per 2 MiB instead of one per 4 KiB page: a 1024^2 z-buffer frame's
// 16 MiB colour and 4 MiB depth are 5120 faults otherwise, most of its cold
// first frame (issue #21, "One-shot cost"). Aligned to a 2 MiB boundary, every
// byte of the block lies in whole huge pages; aligned to 4 KiB only, the parts
// before the first and after the last 2 MiB boundary (up to 2 MiB at each end)
// still took 4 KiB pages: 1,033 faults of a z-buffer frame against 13 aligned
// (measured on the 2-core EPYC VM; a fault there costs 2-6 us of a loaded
// machine, a huge page's fault about 0.1-1 ms, mostly zeroing it).
// Advice only: where the kernel has no huge page at hand the block gets small
// ones, as before. Up to 64 MiB (a 2048^2 float RGBA frame): on the
// compositor's 4096^2 layers (256 MiB, from the benchmarks' brk heap) the
// advice made the cold frame slower (2-layers, one thread: first_ms 1.2-1.8 s
// against 0.45-0.54 s without, on a loaded machine), and they keep their 4 KiB
// alignment (see NoInitAllocator).
constexpr size_t kHugePage = size_t(1) << 21;
constexpr size_t kHugeMinBytes = kHugePage;
constexpr size_t kHugeMaxBytes = size_t(64) << 20;
inline bool huge_block(size_t bytes) { return bytes >= kHugeMinBytes && bytes <= kHugeMaxBytes; }

template <class T>
struct NoInitAllocator : std::allocator<T> {
  using value_type = T;
  static constexpr size_t kPage = 4096;
  static constexpr size_t kSpacedBytes = size_t(1) << 20;
  template <class U>
  struct rebind {
    using other = NoInitAllocator<U>;
  };
  NoInitAllocator() = default;
  template <class U>
  NoInitAllocator(const NoInitAllocator<U>&) {}
  // The block is bytes + 2 alignments (a page; 2 MiB for huge_block sizes)
  // from plain operator new, the buffer starts on the first alignment boundary
  // past a pointer-sized header that remembers the block. (Not aligned
  // operator new: glibc's memalign asks for more than it keeps, so a freed
  // frame could not take the next one of the same size and every "warm" frame
  // was fresh pages again.) The unused address space before and after the
  // buffer is never touched (but for the header's page), so never backed.
  static size_t alignment(size_t bytes) { return huge_block(bytes) ? kHugePage : kPage; }
  T* allocate(size_t n) {
    if (n * sizeof(T) < kSpacedBytes) return std::allocator<T>::allocate(n);
    if (n > std::allocator_traits<std::allocator<T>>::max_size(*this) - 2 * kHugePage / sizeof(T))
      throw std::bad_array_new_length();
    const size_t bytes = n * sizeof(T), align = alignment(bytes);
    char* block = static_cast<char*>(::operator new(bytes + 2 * align));
    const uintptr_t start =
        (reinterpret_cast<uintptr_t>(block) + sizeof(char*) + align - 1) & ~uintptr_t(align - 1);
    if (align == kHugePage) (void)madvise(reinterpret_cast<void*>(start), bytes, MADV_HUGEPAGE);
    reinterpret_cast<char**>(start)[-1] = block;
    return reinterpret_cast<T*>(start);
  }
  void deallocate(T* p, size_t n) noexcept {
    if (n * sizeof(T) < kSpacedBytes) return std::allocator<T>::deallocate(p, n);
    ::operator delete(reinterpret_cast<char**>(p)[-1]);
  }
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

}  // namespace lockstep
