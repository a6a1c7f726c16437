// Timing of the texture family by hand (not built by default: ninja lockstep_texture_timing).
//
//   lockstep_texture_timing SCENE.texscene [SIZE [FILTER [REPS]]]
//
// Prints, for the scene at SIZE x SIZE (default 192) and FILTER (default
// trilinear): the reference's frame and the simd row's on one thread, each
// its lookups alone (each row's build_seconds, its pyramid, taken off),
// best of REPS (default 20) by wall time, ns a lookup,
// the ratio, and the two images' largest channel difference.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/process_memory.h"
#include "core/timer.h"
#include "io/texture_scene.h"
#include "optimized/texture_filter_simd.h"
#include "reference/texture_filter.h"

using namespace lockstep;

namespace {

// The best of reps runs of f, less what f returns (its one-shot set-up).
template <class F>
double best_of(int reps, F f) {
  double best = 1e30;
  for (int r = 0; r < reps; ++r) {
    const Stopwatch w;
    const double off = f();
    best = std::min(best, w.seconds() - off);
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SCENE.texscene [SIZE [FILTER [REPS]]]\n", argv[0]);
    return 2;
  }
  keep_freed_memory();
  TextureScene scene = read_texture_scene(argv[1]);
  const int size = argc > 2 ? std::atoi(argv[2]) : 192;
  const std::string filter = argc > 3 ? argv[3] : "trilinear";
  const int reps = argc > 4 ? std::atoi(argv[4]) : 20;
  scene.width = scene.height = size;
  FrameOptions o;
  o.width = o.height = size;
  o.threads = 1;
  o.params.set("filter", filter);
  Image a, b;
  FrameStats st;
  double pyramid = 0;
  const double t_ref = best_of(std::max(1, reps / 4), [&] {
    a = ref::texture_filter(scene, o, &st);
    pyramid = st.build_seconds;
    return st.build_seconds;
  });
  const double t_simd = best_of(reps, [&] {
    FrameStats s;
    b = opt::simd::texture_filter(scene, o, &s);
    return s.build_seconds;
  });
  double diff = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      for (int c = 0; c < 3; ++c) diff = std::max(diff, double(std::abs(a.pixel(x, y)[c] - b.pixel(x, y)[c])));
  const double n = double(std::max<uint64_t>(st.items, 1));
  std::printf("%s %dx%d %s: %llu lookups; reference %.2f ns, simd %.2f ns a lookup (1 thread): %.2fx; pyramid %.3f ms; "
              "largest difference %.3g\n",
              argv[1], size, size, filter.c_str(), (unsigned long long)st.items, 1e9 * t_ref / n, 1e9 * t_simd / n,
              t_ref / t_simd, 1e3 * pyramid, diff);
  return 0;
}
