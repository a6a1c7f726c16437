// The ray-tracing family's speed against accuracy (issue #22): how deep a ray
// tree a scene needs. Built by default; bench/run.sh runs it (step ray_trace_depth).
//
//   lockstep_ray_trace_depth [--size N] [--reps R] [--max-depth D] SCENE.nff...
//
// For each scene, opt::embree::trace_render (robust offset, shadow rays, the
// default cut-off) on one thread at N x N (default 512) for depth 1 .. D
// (default 10): the median of R (default 3) wall times per frame, the rays
// traced, and two image errors, a pixel counting as changed when a channel
// differs by more than 1/255 (an 8-bit level):
//   vs_answer  pixels that differ from the depth-D frame (the reference
//              answer: what the scene converges to)
//   vs_prev    pixels changed by this extra level (against depth - 1)
// CSV on stdout; bench/scripts/ray_trace_depth_chart.py draws the chart and writes
// bench/results/ray_trace_depth.json. The depth-D frame is the answer because
// the weights along a path fall geometrically (kr, kt < 1 in every SPD scene)
// and the cut-off (1/256) stops rays that could change no 8-bit level: the
// chart shows whether the last levels still change pixels (then D was too
// small, and the table says so in its vs_prev column).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/nff.h"
#include "core/ray_trace.h"
#include "core/timer.h"
#include "optimized/ray_trace_embree.h"

using namespace lockstep;

namespace {

int changed(const Image& a, const Image& b) {
  int n = 0;
  for (int j = 0; j < a.height; ++j)
    for (int i = 0; i < a.width; ++i) {
      const float* p = a.pixel(i, j);
      const float* q = b.pixel(i, j);
      bool diff = false;
      for (int c = 0; c < 3; ++c) diff = diff || !(std::fabs(p[c] - q[c]) <= 1.0f / 255);
      n += diff;
    }
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  int size = 512, reps = 3, max_depth = 10;
  std::vector<std::string> scenes;
  for (int a = 1; a < argc; ++a) {
    auto value = [&](const char* name) {
      if (a + 1 >= argc) {
        std::fprintf(stderr, "lockstep_ray_trace_depth: %s needs a value\n", name);
        std::exit(2);
      }
      return std::atoi(argv[++a]);
    };
    if (std::strcmp(argv[a], "--size") == 0)
      size = value("--size");
    else if (std::strcmp(argv[a], "--reps") == 0)
      reps = value("--reps");
    else if (std::strcmp(argv[a], "--max-depth") == 0)
      max_depth = value("--max-depth");
    else
      scenes.push_back(argv[a]);
  }
  if (scenes.empty() || size < 1 || reps < 1 || max_depth < 2 || max_depth > 32) {
    std::fprintf(
        stderr,
        "usage: lockstep_ray_trace_depth [--size N] [--reps R] [--max-depth 2..32] SCENE.nff...\n");
    return 2;
  }
  std::printf("scene,depth,size,ms,rays,vs_answer,vs_prev,pixels\n");
  try {
    for (const std::string& path : scenes) {
      const Scene scene = read_nff(path);
      std::string name = path.substr(path.find_last_of('/') + 1);
      name = name.substr(0, name.rfind(".nff"));
      std::vector<Image> frames;
      std::vector<double> ms;
      std::vector<uint64_t> rays;
      for (int d = 1; d <= max_depth; ++d) {
        FrameOptions o;
        o.width = o.height = size;
        o.threads = 1;
        o.params.set("depth", std::to_string(d));
        std::vector<double> t;
        Image img;
        FrameStats stats;
        for (int r = 0; r < reps; ++r) {
          const Stopwatch w;
          img = opt::embree::trace_render(scene, o, &stats);
          t.push_back(1e3 * w.seconds());
        }
        std::sort(t.begin(), t.end());
        ms.push_back(t[t.size() / 2]);
        rays.push_back(stats.items);
        frames.push_back(std::move(img));
      }
      const Image& answer = frames.back();
      for (int d = 1; d <= max_depth; ++d)
        std::printf("%s,%d,%d,%.3f,%llu,%d,%d,%d\n", name.c_str(), d, size, ms[d - 1],
                    (unsigned long long)rays[d - 1], changed(frames[d - 1], answer),
                    d > 1 ? changed(frames[d - 1], frames[d - 2]) : 0, size * size);
      std::fflush(stdout);
    }
  } catch (const InputError& e) {
    std::fprintf(stderr, "lockstep_ray_trace_depth: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lockstep_ray_trace_depth: %s\n", e.what());
    return 1;
  }
  return 0;
}
