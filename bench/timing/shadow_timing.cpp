// Timing of the z-buffer's shadows by hand (issue #22; not built by default:
// ninja lockstep_shadow_timing).
//
//   lockstep_shadow_timing SCENE.nff [SIZE [MAP_SIZE [REPS]]]
//
// For the scene at SIZE x SIZE (shading phong), in turn within each
// repetition (A/B on a shared machine: every variant sees the same load), the
// medians of REPS runs of:
//   - shadow maps' pass 1 (every light's cube at MAP_SIZE): the reference's
//     (ref::shadow_maps, one thread), the simd row's before issue #22's last
//     item (core build_shadow_maps over opt::simd::zbuffer_visibility: the
//     Visibility copied out, then walked again for the distances) and now
//     (opt::simd::shadow_maps: the distances written from the tiles), on 1
//     and 2 threads; the new maps must equal the old ones texel for texel (and
//     the texels that differ from the reference's, by the float ulp of the
//     simd raster's depth plane, are counted);
//   - whole frames with shadows=map and shadows=volume (z-pass and z-fail):
//     ref::zbuffer against opt::simd::zbuffer on 1 and 2 threads; the images
//     must be equal.
// Exit 1 when something is not equal.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "io/nff.h"
#include "core/shadow_map.h"
#include "core/process_memory.h"
#include "core/timer.h"
#include "optimized/zbuffer/zbuffer_simd.h"
#include "reference/raster.h"
#include "reference/shadow_map.h"

using namespace lockstep;

namespace {

struct Variant {
  std::string name;
  std::function<void()> run;
  std::vector<double> seconds;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

// Texels that differ (the count, and the largest difference printed).
size_t map_differences(const ShadowMaps& a, const ShadowMaps& b, const char* name) {
  if (a.cubes.size() != b.cubes.size()) return 1;
  size_t n = 0;
  double worst = 0;
  for (size_t c = 0; c < a.cubes.size(); ++c)
    for (int f = 0; f < kCubeFaces; ++f)
      for (size_t i = 0; i < a.cubes[c].dist[size_t(f)].size(); ++i) {
        const float x = a.cubes[c].dist[size_t(f)][i], y = b.cubes[c].dist[size_t(f)][i];
        if (x == y) continue;
        ++n;
        if (std::isfinite(x) && std::isfinite(y))
          worst = std::max(worst, double(std::abs(x - y)) / double(std::abs(x)));
        else
          worst = std::numeric_limits<double>::infinity();
      }
  if (n)
    std::fprintf(stderr, "pass 1 simd %s: %zu texels differ (largest %.3g relative)\n", name, n,
                 worst);
  return n;
}

bool same_images(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height &&
         std::equal(a.rgba.begin(), a.rgba.end(), b.rgba.begin(), b.rgba.end());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SCENE.nff [SIZE [MAP_SIZE [REPS]]]\n", argv[0]);
    return 2;
  }
  lockstep::keep_freed_memory();
  const Scene scene = read_nff(argv[1]);
  const int size = argc > 2 ? std::atoi(argv[2]) : 512;
  const std::string map_size = argc > 3 ? argv[3] : "1024";
  const int reps = argc > 4 ? std::atoi(argv[4]) : 5;
  auto options = [&](const std::string& shadows, bool zfail, int threads) {
    FrameOptions o;
    o.width = o.height = size;
    o.threads = threads;
    o.params.set("shading", "phong");
    o.params.set("shadows", shadows);
    o.params.set("map_size", map_size);
    if (zfail) o.params.set("zfail", "1");
    return o;
  };
  const RasterSettings s = raster_settings(options("map", false, 1).params, "timing");

  ShadowMaps ref_maps, old_maps, new_maps;
  std::vector<Variant> v;
  v.push_back({"pass1 reference", [&] { ref_maps = ref::shadow_maps(scene, s); }, {}});
  for (int t : {1, 2}) {
    v.push_back({"pass1 simd before, " + std::to_string(t) + " thread(s)",
                 [&, t] {
                   old_maps = build_shadow_maps(
                       scene, s,
                       [t](const ScreenMesh& f, const RasterSettings& d, Visibility& vis) {
                         opt::simd::zbuffer_visibility(f, d, t, vis);
                       });
                 },
                 {}});
    v.push_back({"pass1 simd now, " + std::to_string(t) + " thread(s)",
                 [&, t] { new_maps = opt::simd::shadow_maps(scene, s, t); },
                 {}});
  }
  bool ok = true;
  std::vector<std::pair<Image, Image>> frames;
  for (const auto& [shadows, zfail] :
       {std::pair<std::string, bool>{"map", false}, {"volume", false}, {"volume", true}}) {
    const std::string what = shadows + (shadows == "volume" ? (zfail ? " z-fail" : " z-pass") : "");
    auto ref_image = std::make_shared<Image>();
    v.push_back({"frame " + what + " reference",
                 [&, shadows, zfail, ref_image, what] {
                   *ref_image = ref::zbuffer(scene, options(shadows, zfail, 1), nullptr);
                 },
                 {}});
    for (int t : {1, 2})
      v.push_back(
          {"frame " + what + " simd, " + std::to_string(t) + " thread(s)",
           [&, shadows, zfail, ref_image, t, what] {
             const Image img = opt::simd::zbuffer(scene, options(shadows, zfail, t), nullptr);
             if (!ref_image->rgba.empty() && !same_images(img, *ref_image)) {
               std::fprintf(stderr, "frame %s simd (%d threads) differs from the reference's\n",
                            what.c_str(), t);
               ok = false;
             }
           },
           {}});
  }
  for (int r = 0; r < reps; ++r)
    for (Variant& x : v) {
      Stopwatch w;
      x.run();
      x.seconds.push_back(w.seconds());
    }
  // The simd raster's depth plane is within a few ulps of the reference's
  // (optimized/zbuffer/zbuffer_simd.cpp set_up): a texel's float distance may differ by
  // one ulp, in both the old and the new pass 1 (printed, not a failure); the
  // new pass 1 must equal the old one exactly.
  map_differences(ref_maps, old_maps, "before, against the reference");
  if (map_differences(old_maps, new_maps, "now, against before")) ok = false;
  std::printf("%s %dx%d map_size %s, %zu lights, median of %d (A/B in turn):\n", argv[1], size,
              size, map_size.c_str(), scene.lights.size(), reps);
  for (const Variant& x : v)
    std::printf("  %-40s %9.1f ms\n", x.name.c_str(), 1e3 * median(x.seconds));
  std::printf("pass 1 now equal to before, frames equal to the reference's: %s\n",
              ok ? "yes" : "NO");
  return ok ? 0 : 1;
}
