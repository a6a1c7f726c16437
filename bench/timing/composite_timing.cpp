// lockstep: a small timing program for the compositing family (run by hand).
//
//   ninja -C build lockstep_composite_timing && build/bench/lockstep_composite_timing [threads] [reps]
//
// Prints median wall times over `reps` runs (default 5) on `threads` threads
// (default 2) for:
//   * 4096^2 float, 2 premultiplied layers: opt::simd into a reused (already
//     touched) buffer, opt::simd::composite (a fresh Image: allocation, zero
//     fill and first touch of the output included), opt::oiio::composite, and
//     memcpy of the same number of bytes moved (2 reads + 1 write of 16 B per
//     pixel: 3 * 4096^2 * 16 B), split over the same threads. GB/s counts
//     reads + writes.
//   * the first-touch cost alone: allocating and zero-filling a 4096^2 Image.
//   * 4096^2 unorm8, 2 layers: simd vs oiio.
//   * 2048^2 float, 32 layers opaque from layer 2 on: simd front-to-back with
//     early termination, simd without it, simd back-to-front, oiio.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <thread>
#include <vector>

#include "optimized/composite_simd.h"
#include "optimized/composite_oiio.h"
#include "optimized/tiling.h"
#include "reference/synthetic_stack.h"

namespace {

using Clock = std::chrono::steady_clock;

double median_seconds(int reps, const std::function<void()>& fn) {
  std::vector<double> t;
  fn();  // warm-up (page faults of inputs, thread pools)
  for (int r = 0; r < reps; ++r) {
    const auto t0 = Clock::now();
    fn();
    t.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

void row(const char* what, double seconds, double pixels, double bytes) {
  std::printf("  %-52s %8.2f ms  %8.1f Mpix/s  %6.2f GB/s\n", what, seconds * 1e3,
              pixels / seconds / 1e6, bytes / seconds / 1e9);
}

// memcpy of `bytes` split over `threads` threads (each thread its own slice).
void parallel_memcpy(char* dst, const char* src, size_t bytes, int threads) {
  std::vector<std::thread> pool;
  const size_t slice = (bytes / size_t(threads) + 4095) & ~size_t(4095);
  for (int t = 0; t < threads; ++t) {
    const size_t b = std::min(bytes, size_t(t) * slice), e = std::min(bytes, b + slice);
    pool.emplace_back([=] { std::memcpy(dst + b, src + b, e - b); });
  }
  for (auto& th : pool) th.join();
}

}  // namespace

int main(int argc, char** argv) {
  using namespace lockstep;
  const int threads = argc > 1 ? std::atoi(argv[1]) : 2;
  const int reps = argc > 2 ? std::atoi(argv[2]) : 5;
  FrameOptions o;
  o.threads = threads;
  std::printf("lockstep composite timing: %d threads, median of %d, Highway target %s\n", threads,
              reps, opt::simd::composite_target_name());

  {
    const int n = 4096;
    const double px = double(n) * n, bytes = 3.0 * px * 16;
    std::printf("\n%dx%d float, 2 premultiplied layers (%.0f MB moved per frame)\n", n, n,
                bytes / 1e6);
    const LayerStack s = synthetic_stack(n, n, 2, -1, Alpha::premultiplied, Storage::f32, 1);
    std::vector<float> out(size_t(px) * 4);  // touched once here
    row("simd, into a reused buffer",
        median_seconds(reps, [&] { opt::simd::composite_into(s, o, out.data(), nullptr); }), px,
        bytes);
    row("simd, fresh Image (alloc + zero + first touch)",
        median_seconds(reps, [&] { opt::simd::composite(s, o, nullptr); }), px, bytes);
    row("oiio over, fresh Image",
        median_seconds(reps, [&] { opt::oiio::composite(s, o, nullptr); }), px, bytes);
    std::vector<char> src(size_t(bytes / 2)), dst(size_t(bytes / 2));
    std::memset(src.data(), 1, src.size());
    row("memcpy of 1.5 images (same bytes moved)",
        median_seconds(reps, [&] { parallel_memcpy(dst.data(), src.data(), src.size(), threads); }),
        px, bytes);
    row("first touch alone: Image(4096, 4096)",
        median_seconds(reps,
                       [&] {
                         Image img(n, n);
                         if (img.rgba[1] != 0) std::abort();
                       }),
        px, px * 16);
    // Bytes-equivalent check of the 85% target in the same units.
  }
  {
    const int n = 4096;
    const double px = double(n) * n, bytes = px * (4 + 4 + 16);
    std::printf("\n%dx%d unorm8, 2 straight layers (8-bit in, float out: %.0f MB moved)\n", n, n,
                bytes / 1e6);
    LayerStack s = synthetic_stack(n, n, 2, -1, Alpha::straight, Storage::unorm8, 2);
    for (Layer& l : s.layers) l.image.rgba = {};  // ignored with unorm8; frees 512 MB
    std::vector<float> out(size_t(px) * 4);
    row("simd, into a reused buffer",
        median_seconds(reps, [&] { opt::simd::composite_into(s, o, out.data(), nullptr); }), px,
        bytes);
    row("oiio over (UINT8 buffers), fresh Image",
        median_seconds(reps, [&] { opt::oiio::composite(s, o, nullptr); }), px, bytes);
  }
  {
    const int n = 2048, L = 32;
    const double px = double(n) * n, bytes = (L + 1.0) * px * 16;
    std::printf(
        "\n%dx%d float, %d premultiplied layers, opaque from layer 2 (all layers read: %.0f MB)\n",
        n, n, L, bytes / 1e6);
    LayerStack s = synthetic_stack(n, n, L, 2, Alpha::premultiplied, Storage::f32, 3);
    std::vector<float> out(size_t(px) * 4);
    s.order = Order::front_to_back;
    s.early_stop = true;
    const double ftb =
        median_seconds(reps, [&] { opt::simd::composite_into(s, o, out.data(), nullptr); });
    row("simd ftb, early termination (reused buffer)", ftb, px, bytes);
    const double ftb_fresh = median_seconds(reps, [&] { opt::simd::composite(s, o, nullptr); });
    row("simd ftb, early termination (fresh Image)", ftb_fresh, px, bytes);
    s.early_stop = false;
    row("simd ftb, no early termination",
        median_seconds(reps, [&] { opt::simd::composite_into(s, o, out.data(), nullptr); }), px,
        bytes);
    s.order = Order::back_to_front;
    row("simd btf",
        median_seconds(reps, [&] { opt::simd::composite_into(s, o, out.data(), nullptr); }), px,
        bytes);
    s.order = Order::front_to_back;
    const double oi = median_seconds(reps, [&] { opt::oiio::composite(s, o, nullptr); });
    row("oiio over chained (31 overs), fresh Image", oi, px, bytes);
    std::printf(
        "  simd ftb early termination vs oiio: %.1fx (reused buffer), %.1fx (fresh Image)\n",
        oi / ftb, oi / ftb_fresh);
  }
  return 0;
}
