// lockstep: the llvmpipe row's agreement with the reference and its timings (run by hand).
//
//   ninja -C build lockstep_llvmpipe_check
//   build/bench/lockstep_llvmpipe_check agree SCENE.nff... [--size N]...   (default sizes 512 1024)
//   build/bench/lockstep_llvmpipe_check time SCENE.nff [--size N] [--shading flat|gouraud] [--reps R]
//
// agree: for each scene, size and shading (flat, gouraud) renders
// ref::zbuffer and opt::llvmpipe::zbuffer with the same settings and prints
//   cover      pixels covered by one and not the other, of all pixels
//   owner      pixels both cover where llvmpipe shows another triangle's colour
//              (a reference neighbour's, within 1/255): the pixel centre is near
//              an edge between two triangles and the two snaps put it on
//              different sides; of the pixels both cover
//   depth_rel  largest relative eye-z error over the other pixels both cover
//   steps      the same in steps of llvmpipe's 24-bit depth buffer at that depth
//   col_max    largest channel difference over those pixels (interpolation)
//   unexp      pixels both cover whose colour is off by more than 1/255 with no
//              neighbour to explain it, and the largest such difference
// LLVMPIPE_CHECK_SHOW=N prints the first N pixels whose colours differ, and
// each new largest depth error (pixel, both depths, the reference's dz/dx).
//
// time: one Context, the first draw (context creation, LLVM compilation) and
// then R warm draws of the same mesh: median and best of each phase. The thread
// count is LP_NUM_THREADS (llvmpipe reads it once per process): run
//   LP_NUM_THREADS=0 build/bench/lockstep_llvmpipe_check time ...   (one thread does all)
//   LP_NUM_THREADS=2 build/bench/lockstep_llvmpipe_check time ...   (two rasteriser threads)
// Also prints the cold cost of a whole opt::llvmpipe::zbuffer call in this
// process (the first: llvmpipe's screen, LLVM's initialisation) and a warm one.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "io/nff.h"
#include "core/timer.h"
#include "optimized/zbuffer/zbuffer_llvmpipe.h"
#include "optimized/raster_llvmpipe.h"
#include "reference/raster.h"

using namespace lockstep;

namespace {

struct Agreement {
  double cover_frac = 0;   // coverage differs, of all pixels
  double depth_rel = 0;    // largest relative eye-z error, both covered, same triangle
  double depth_steps = 0;  // the same in steps of the 24-bit buffer at that depth
  double owner_frac =
      0;  // both covered, the colour of another triangle (a neighbour's): of both-covered pixels
  double color_max = 0;  // largest channel difference of the rest (same triangle: interpolation)
  long unexplained =
      0;  // both covered, colour off by more than 1/255, and no neighbour has llvmpipe's colour
  double unexplained_max = 0;
};

double channel_diff(const float* a, const float* b) {
  double c = 0;
  for (int k = 0; k < 3; ++k) c = std::max(c, std::abs(double(a[k]) - double(b[k])));
  return c;
}

// The first `limit` pixels both cover whose colours differ by more than 1/255,
// with the reference colours around them.
void print_differing(const Image& r, const Image& l, int limit) {
  int shown = 0;
  auto rc = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= r.width || y >= r.height) return std::string("-");
    const float* p = r.pixel(x, y);
    char b[64];
    std::snprintf(b, sizeof b, "%.3f,%.3f,%.3f", p[0], p[1], p[2]);
    return std::string(b);
  };
  for (int y = 0; y < r.height && shown < limit; ++y)
    for (int x = 0; x < r.width && shown < limit; ++x) {
      const size_t i = size_t(y) * r.width + x;
      if (!std::isfinite(r.depth[i]) || !std::isfinite(l.depth[i])) continue;
      if (channel_diff(l.pixel(x, y), r.pixel(x, y)) <= 1.0 / 255) continue;
      ++shown;
      const float* lp = l.pixel(x, y);
      std::printf(
          "    (%d, %d): ref %s z %.7g | llvmpipe %.3f,%.3f,%.3f z %.7g | ref above %s below %s "
          "left %s right %s\n",
          x, y, rc(x, y).c_str(), r.depth[i], lp[0], lp[1], lp[2], l.depth[i], rc(x, y - 1).c_str(),
          rc(x, y + 1).c_str(), rc(x - 1, y).c_str(), rc(x + 1, y).c_str());
    }
}

// near_z, far_z: the mesh's, for the depth buffer's step.
Agreement compare(const Image& r, const Image& l, double near_z, double far_z) {
  Agreement a;
  const size_t n = size_t(r.width) * size_t(r.height);
  size_t cover_diff = 0, both = 0, owner = 0;
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x) {
      const size_t i = size_t(y) * r.width + x;
      const bool cr = std::isfinite(r.depth[i]), cl = std::isfinite(l.depth[i]);
      if (cr != cl) ++cover_diff;
      if (!(cr && cl)) continue;
      ++both;
      const double c = channel_diff(l.pixel(x, y), r.pixel(x, y));
      if (c > 1.0 / 255) {
        // Another triangle won the pixel: llvmpipe's colour is a neighbour's in the reference.
        bool neighbour = false;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if ((dx || dy) && xx >= 0 && yy >= 0 && xx < r.width && yy < r.height &&
                channel_diff(l.pixel(x, y), r.pixel(xx, yy)) <= 1.0 / 255)
              neighbour = true;
          }
        if (neighbour) {
          ++owner;
        } else {
          ++a.unexplained;
          a.unexplained_max = std::max(a.unexplained_max, c);
        }
        continue;
      }
      a.color_max = std::max(a.color_max, c);
      const double zr = r.depth[i], e = std::abs(double(l.depth[i]) - zr);
      a.depth_rel = std::max(a.depth_rel, e / zr);
      const double steps = e / opt::llvmpipe::depth_step(zr, near_z, far_z);
      if (steps > a.depth_steps && std::getenv("LLVMPIPE_CHECK_SHOW")) {
        // The depth change to the next pixel, as a measure of the surface's slope.
        const double zx =
            x + 1 < r.width && std::isfinite(r.depth[i + 1]) ? r.depth[i + 1] - zr : 0;
        std::printf("    depth (%d, %d): ref %.9g llvmpipe %.9g, %.1f steps; ref dz/dx %.3g\n", x,
                    y, zr, double(l.depth[i]), steps, zx);
      }
      a.depth_steps = std::max(a.depth_steps, steps);
    }
  a.cover_frac = double(cover_diff) / double(n);
  a.owner_frac = both ? double(owner) / double(both) : 0;
  return a;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

int agree(const std::vector<std::string>& scenes, std::vector<int> sizes) {
  if (sizes.empty()) sizes = {512, 1024};
  std::printf("%-12s %5s %-8s %7s %9s %9s %9s %8s %9s %6s %9s\n", "scene", "size", "shading",
              "tris", "cover", "owner", "depth_rel", "steps", "col_max", "unexp", "unexp_max");
  for (const std::string& path : scenes) {
    const Scene scene = read_nff(path);
    std::string name = path.substr(path.find_last_of('/') + 1);
    name = name.substr(0, name.find('.'));
    for (int size : sizes) {
      for (const char* shading : {"flat", "gouraud"}) {
        FrameOptions opts;
        opts.width = opts.height = size;
        opts.params.set("shading", shading);
        FrameStats rs, ls;
        const Image r = ref::zbuffer(scene, opts, &rs);
        const Image l = opt::llvmpipe::zbuffer(scene, opts, &ls);
        const ScreenMesh mesh = view_scene(scene, size, size, raster_settings(opts.params, path));
        const Agreement a = compare(r, l, mesh.near_z, mesh.far_z);
        std::printf("%-12s %5d %-8s %7llu %9.2e %9.2e %9.2e %8.0f %9.2e %6ld %9.2e\n", name.c_str(),
                    size, shading, (unsigned long long)ls.items, a.cover_frac, a.owner_frac,
                    a.depth_rel, a.depth_steps, a.color_max, a.unexplained, a.unexplained_max);
        if (std::getenv("LLVMPIPE_CHECK_SHOW"))
          print_differing(r, l, std::atoi(std::getenv("LLVMPIPE_CHECK_SHOW")));
        std::fflush(stdout);
      }
    }
  }
  return 0;
}

int time_draws(const std::string& path, int size, const std::string& shading, int reps) {
  const Scene scene = read_nff(path);
  FrameOptions opts;
  opts.width = opts.height = size;
  opts.params.set("shading", shading);
  const RasterSettings s = raster_settings(opts.params, path);

  // A whole call, cold (the first in this process) and warm.
  for (const char* what : {"zbuffer call, cold (first in the process)", "zbuffer call, warm"}) {
    FrameStats stats;
    const Stopwatch clock;
    const Image img = opt::llvmpipe::zbuffer(scene, opts, &stats);
    std::printf("%-44s %8.2f ms (build_seconds %.2f ms: context + shader compilation)\n", what,
                1e3 * clock.seconds(), 1e3 * stats.build_seconds);
  }

  Stopwatch clock;
  const ScreenMesh mesh = view_scene(scene, size, size, s);
  std::printf("view_scene (reference, double, 1 thread)    %8.2f ms, %zu triangles\n",
              1e3 * clock.seconds(), mesh.tris.size());
  opt::llvmpipe::Context ctx(size, size, 0, nullptr);
  std::printf("context creation                            %8.2f ms; LP_NUM_THREADS=%s\n",
              1e3 * ctx.create_seconds(), ctx.thread_count().c_str());
  Image img;
  opt::llvmpipe::DrawTimes first;
  ctx.draw(mesh, scene.background, s, img, &first);
  std::printf("first draw: compile %.2f ms, upload %.2f ms, draw %.2f ms, readback %.2f ms\n",
              1e3 * first.compile, 1e3 * first.upload, 1e3 * first.draw, 1e3 * first.readback);
  std::vector<double> up, dr, rb, total;
  // Process CPU time over the warm draws: above the wall time, llvmpipe's threads ran at once.
  const std::clock_t cpu0 = std::clock();
  const Stopwatch wall;
  for (int i = 0; i < reps; ++i) {
    opt::llvmpipe::DrawTimes t;
    ctx.draw(mesh, scene.background, s, img, &t);
    up.push_back(t.upload);
    dr.push_back(t.draw);
    rb.push_back(t.readback);
    total.push_back(t.upload + t.draw + t.readback);
  }
  std::printf(
      "warm draws (%d): median upload %.2f, draw %.2f (best %.2f), readback %.2f, total %.2f ms\n",
      reps, 1e3 * median(up), 1e3 * median(dr), 1e3 * *std::min_element(dr.begin(), dr.end()),
      1e3 * median(rb), 1e3 * median(total));
  std::printf(
      "warm draws: process CPU time / wall time %.2f (llvmpipe's threads in parallel when above "
      "1)\n",
      double(std::clock() - cpu0) / CLOCKS_PER_SEC / wall.seconds());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(
        stderr,
        "usage: %s agree SCENE... [--size N]... | time SCENE [--size N] [--shading S] [--reps R]\n",
        argv[0]);
    return 2;
  }
  const std::string mode = argv[1];
  std::vector<std::string> scenes;
  std::vector<int> sizes;
  std::string shading = "flat";
  int reps = 20;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--size" && i + 1 < argc)
      sizes.push_back(std::atoi(argv[++i]));
    else if (a == "--shading" && i + 1 < argc)
      shading = argv[++i];
    else if (a == "--reps" && i + 1 < argc)
      reps = std::atoi(argv[++i]);
    else
      scenes.push_back(a);
  }
  try {
    if (mode == "agree") return agree(scenes, sizes);
    if (mode == "time" && scenes.size() == 1)
      return time_draws(scenes[0], sizes.empty() ? 1024 : sizes[0], shading, reps);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  std::fprintf(stderr, "unknown mode or arguments\n");
  return 2;
}
