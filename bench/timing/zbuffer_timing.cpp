// Timing of the z-buffer family by hand (not built by default: ninja lockstep_zbuffer_timing).
//
//   lockstep_zbuffer_timing SCENE.nff [SIZE [SHADING [SPP [REPS]]]]
//
// Prints, for the scene at SIZE x SIZE: the shared set-up (ref::view_scene), the
// reference frame (ref::zbuffer, one thread), opt::simd::zbuffer and its
// visibility pass alone on 1 and 2 threads (best of REPS), triangles and pixels
// per second, and the agreement of the two frames (largest channel error,
// fraction of pixels over 1/255, depth).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <limits>
#include <string>

#include "io/nff.h"
#include "core/process_memory.h"
#include "core/timer.h"
#include "optimized/zbuffer/zbuffer_simd.h"
#include "reference/raster.h"

using namespace lockstep;

double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// The best wall time of reps runs; with LOCKSTEP_TIMING_CPU set, the best
// process CPU time instead (all threads together: on a loaded machine, the
// one-thread figure that preemption does not inflate).
template <class F>
double best_of(int reps, F f) {
  static const bool cpu = std::getenv("LOCKSTEP_TIMING_CPU") != nullptr;
  double best = 1e30;
  for (int r = 0; r < reps; ++r) {
    const double c0 = cpu_seconds();
    Stopwatch w;
    f();
    best = std::min(best, cpu ? cpu_seconds() - c0 : w.seconds());
  }
  return best;
}

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SCENE.nff [SIZE [SHADING [SPP [REPS]]]]\n", argv[0]);
    return 2;
  }
  // As bench/: frames come from the heap and go back to it (no fresh pages per frame).
  lockstep::keep_freed_memory();
  const Scene scene = read_nff(argv[1]);
  const int size = argc > 2 ? std::atoi(argv[2]) : 1024;
  const std::string shading = argc > 3 ? argv[3] : "flat";
  const std::string spp = argc > 4 ? argv[4] : "1";
  const int reps = argc > 5 ? std::atoi(argv[5]) : 5;
  FrameOptions o;
  o.width = o.height = size;
  o.params.set("shading", shading);
  o.params.set("spp", spp);
  const RasterSettings s = raster_settings(o.params, "timing");
  ScreenMesh mesh;
  const double t_setup = best_of(reps, [&] { mesh = view_scene(scene, size, size, s); });
  const double tris = double(mesh.tris.size()), pix = double(size) * size;
  std::printf("%s %dx%d shading=%s spp=%s: %zu screen triangles (culled %llu, from spheres %llu)\n", argv[1], size,
              size, shading.c_str(), spp.c_str(), mesh.tris.size(),
              (unsigned long long)mesh.culled, (unsigned long long)mesh.sphere_tris);
  ScreenMesh fast;
  const double t_fast =
      best_of(reps, [&] { fast = opt::simd::view_scene(scene, size, size, s, 1); });
  bool same = fast.tris.size() == mesh.tris.size() && fast.culled == mesh.culled &&
              fast.degenerate == mesh.degenerate;
  for (size_t i = 0; same && i < mesh.tris.size(); ++i)
    for (int k = 0; k < 3; ++k)
      same = same && fast.tris[i].v[k].x == mesh.tris[i].v[k].x &&
             fast.tris[i].v[k].y == mesh.tris[i].v[k].y &&
             fast.tris[i].v[k].z == mesh.tris[i].v[k].z;
  std::printf(
      "  view_scene (reference set-up)    %8.2f ms; opt::simd::view_scene 1 thr %8.2f ms (%s)\n",
      t_setup * 1e3, t_fast * 1e3, same ? "same mesh" : "MESH DIFFERS");
  Image ref_img;
  FrameOptions o1 = o;
  o1.threads = 1;
  const double t_ref =
      best_of(std::max(1, reps / 3), [&] { ref_img = ref::zbuffer(scene, o1, nullptr); });
  Visibility rv;
  const double t_ref_vis =
      best_of(std::max(1, reps / 3), [&] { ref::zbuffer_visibility(mesh, s, rv); });
  std::printf("  ref::zbuffer              1 thr  %8.2f ms  (visibility %8.2f ms)\n", t_ref * 1e3,
              t_ref_vis * 1e3);
  for (int threads : {1, 2}) {
    FrameOptions ot = o;
    ot.threads = threads;
    Image img;
    const double t = best_of(reps, [&] { img = opt::simd::zbuffer(scene, ot, nullptr); });
    Visibility v;
    const double tv = best_of(reps, [&] { opt::simd::zbuffer_visibility(mesh, s, threads, v); });
    std::printf(
        "  simd::zbuffer             %d thr  %8.2f ms  %7.2f Mtris/s %8.1f Mpix/s  setup share "
        "%4.1f%%  "
        "(visibility %6.2f ms)  %5.1fx ref\n",
        threads, t * 1e3, tris / t * 1e-6, pix / t * 1e-6, 100 * t_fast / t, tv * 1e3, t_ref / t);
    if (threads == 1) {
      double worst = 0, dworst = 0;
      long over = 0, tri_diff = 0, count_diff = 0;
      for (size_t i = 0; i < img.rgba.size(); i += 4) {
        double e = 0;
        for (int c = 0; c < 3; ++c)
          e = std::max(e, double(std::fabs(img.rgba[i + c] - ref_img.rgba[i + c])));
        worst = std::max(worst, e);
        over += e > 1.0 / 255;
        const double za = img.depth[i / 4], zb = ref_img.depth[i / 4];
        if (std::isfinite(za) || std::isfinite(zb))
          dworst = std::max(dworst, std::fabs(za - zb) / std::max(1.0, std::fabs(zb)));
      }
      for (size_t i = 0; i < v.tri.size(); ++i)
        tri_diff += v.tri[i] != rv.tri[i], count_diff += v.count[i] != rv.count[i];
      std::printf(
          "  agreement: max channel %.3g, pixels > 1/255: %ld (%.4f%%), depth rel %.3g; samples "
          "with other tri %ld, "
          "other count %ld\n",
          worst, over, 100.0 * over / pix, dworst, tri_diff, count_diff);
    }
  }
  return 0;
}
