// lockstep texture study (issue #32): speed against accuracy of every filter
// of every row of the texture family, against the pixel's exact box filter
// (props/texture/oracle.h).
//
// The scene: corpus/textures/zoneplate_plane.texscene (a zone plate tiled
// over a plane receding from the camera: every frequency at every
// minification) at 192 x 192 (the oracle clips every texel of every footprint).
// Each row draws it with each filter on one thread (best of 15 runs, of 3
// where a frame takes over 50 ms); the error is over the interior pixels (all four corners on
// the quad), RGB channels: RMS and the 99th percentile of the per-pixel
// largest channel error.
//
// CSV on stdout: row,filter,rms,p99,max,seconds,lookups,ns_per_lookup,
// setup_seconds: the lookups alone, without the one-shot costs (setup_seconds:
// every row's build_seconds, timed inside its frame: the pyramid, or the
// reference's copy of level 0 for bilinear; OpenImageIO's make_texture,
// llvmpipe's context, shader compilation and upload).
// bench/scripts/texture_chart.py draws it (bench/charts/texture_speed_accuracy.svg).
// --two-threads: every row on two threads (a process of its own: llvmpipe
// reads its thread count once per process), for the two-thread comparison.
// Claims checked (a ctest runs --quick at 96 x 96): supersampling converges
// (super8 below super4 below super2 below point, in RMS), anisotropic
// filtering and EWA are more accurate than trilinear, trilinear more than
// point, and the simd row's error equals the reference's within 1e-5 for
// every filter. No claim about speed (benchmarks state those).
// --plane: the issue's own scene instead (the registry's benchmark input: a
// 1024^2 zone plate tiled over a plane receding from the camera, 1024^2
// pixels; its texture's pyramid, 22 MB, is far larger than the caches),
// trilinear and aniso16, every row warm (the peers through their sessions),
// one thread and two (not the reference: single-threaded; not llvmpipe: it
// reads its thread count once per process), lookups alone (no oracle: it
// would take hours at this size).
// CSV: row,filter,threads,seconds,lookups,ns_per_lookup,setup_seconds.
#include <algorithm>
#include <functional>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "bench/studies/study.h"
#include "core/process_memory.h"
#include "core/run_resources.h"
#include "io/texture_scene.h"
#include "props/texture/oracle.h"
#include "registry/registry.h"

using namespace lockstep;

namespace {

// The 1024^2 plane, every row (see --plane above).
int plane_study(const Family& fam) {
  std::printf("row,filter,threads,seconds,lookups,ns_per_lookup,setup_seconds\n");
  RunResources resources;
  for (const BenchInput& b : fam.bench()) {
    const std::string filter = b.params.get("filter", "");
    if (filter != "trilinear" && filter != "aniso16") continue;
    const Input in = b.make ? b.make() : b.input;
    const TextureScene& scene = input_as<TextureScene>(in);
    for (const FamilyImpl& impl : fam.impls) {
      for (int threads : {1, 2}) {
        // The reference is single-threaded; llvmpipe reads its thread count
        // once per process (the two-thread figure would be its first one's).
        if (threads == 2 && (&impl == &fam.reference() || impl.name == "llvmpipe")) continue;
        FrameOptions o;
        o.width = b.width;
        o.height = b.height;
        o.threads = threads;
        o.params = b.params;
        std::function<Output(const Input&, const FrameOptions&, FrameStats*)> run = impl.run;
        FrameStats st;
        if (impl.session) {
          run = impl.session(in, o, resources);
          run(in, o, &st);  // the session's first frame (module, make, upload): not timed
        }
        double t = 1e300, setup = 0;
        int runs = 15;  // best of 15, of 3 for frames over 50 ms (as below)
        for (int k = 0; k < runs; ++k) {
          st = FrameStats{};
          const Stopwatch w;
          (void)run(in, o, &st);
          const double whole = w.seconds();
          if (k == 0 && whole > 0.05) runs = 3;
          const double one_shot = st.build_seconds;
          if (whole - one_shot < t) t = whole - one_shot, setup = one_shot;
        }
        std::printf("%s,%s,%d,%.6g,%llu,%.6g,%.6g\n", std::string(impl.name).c_str(), filter.c_str(), threads, t,
                    (unsigned long long)st.items, 1e9 * t / double(std::max<uint64_t>(st.items, 1)), setup);
        std::fflush(stdout);
      }
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // As bench/: a frame's memory is the last frame's, from the heap (warm:
  // no fresh pages a frame).
  keep_freed_memory();
  bool quick = false, two = false, plane = false;
  if (!study::parse_flags(argc, argv, {{"--quick", &quick}, {"--two-threads", &two}, {"--plane", &plane}},
                          "lockstep_texture_study [--quick] [--two-threads] [--plane]"))
    return 2;
  study::Claims claims{"lockstep_texture_study"};
  const Family* fam = registry().find("texture");
  if (!fam) return 3;
  if (plane) return plane_study(*fam);
  TextureScene scene = read_texture_scene(LOCKSTEP_CORPUS_DIR "/textures/zoneplate_plane.texscene");
  const int size = quick ? 96 : 192;
  scene.width = scene.height = size;
  const TexelMap map = TexelMap::make(scene, size, size);
  // The oracle, once.
  std::vector<props::texture::BoxValue> box(size_t(size) * size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) box[size_t(y) * size + x] = props::texture::pixel_box_filter(scene, map, x, y);
  const Input in = make_input<TextureScene>(scene, "zoneplate_plane", size, size, scene.background);
  const char* filters[] = {"point",   "bilinear", "super2",  "super4",  "super8", "mip_nearest", "trilinear",
                           "aniso2",  "aniso4",   "aniso8",  "aniso16", "ewa",    "area"};
  std::printf("row,filter,rms,p99,max,seconds,lookups,ns_per_lookup,setup_seconds\n");
  std::map<std::string, double> rms_of;
  RunResources resources;
  // Every row reports its one-shot set-up (the reference's and the simd
  // row's pyramid, or the reference's copy of level 0 for bilinear; the
  // peers' texture set-up) as build_seconds, timed inside the frame: taken
  // off, every row's figure is its lookups alone.
  // error=E (registry/texture_row.cpp): a filter per tile, on the simd row;
  // its search is its one-shot cost (build_seconds), taken off like a pyramid.
  std::vector<std::string> settings(std::begin(filters), std::end(filters));
  const char* errors[] = {"0.2", "0.1", "0.05", "0.02"};
  for (const char* e : errors) settings.push_back(std::string("error") + e);
  for (const FamilyImpl& impl : fam->impls) {
    for (const std::string& setting : settings) {
      const bool by_error = setting.rfind("error", 0) == 0;
      if (by_error && impl.name != "simd") continue;
      const char* filter = setting.c_str();
      FrameOptions o;
      o.width = o.height = size;
      o.threads = two ? 2 : 1;
      if (by_error) o.params.set("error", setting.substr(5));
      else o.params.set("filter", filter);
      if (impl.unsupported && !impl.unsupported(o.params).empty()) continue;
      FrameStats st;
      Image img;
      // Warm frames: a row with a session (the peers: OpenImageIO's .tx and
      // TextureSystem, llvmpipe's context and uploaded texture) runs through
      // one, as an application keeps them; its first frame (module, make,
      // upload) is not timed. The frame's time less its one-shot set-up (the
      // row's build_seconds).
      std::function<Output(const Input&, const FrameOptions&, FrameStats*)> run = impl.run;
      if (impl.session) {
        run = impl.session(in, o, resources);
        run(in, o, &st);
      }
      double t = 1e300, setup = 0;
      // Best of 15, or of 3 for frames over 50 ms (area sampling, the
      // reference's supersampling and EWA): every row alike.
      int runs = 15;
      for (int k = 0; k < runs; ++k) {
        st = FrameStats{};
        const Stopwatch w;
        img = take_output<Image>(run(in, o, &st));
        const double whole = w.seconds();
        if (k == 0 && whole > 0.05) runs = 3;
        const double one_shot = st.build_seconds;
        if (whole - one_shot < t) t = whole - one_shot, setup = one_shot;
      }
      std::vector<double> errs;
      double sq = 0;
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          const auto& b = box[size_t(y) * size + x];
          if (!b.interior) continue;
          double e = 0;
          for (int c = 0; c < 3; ++c) {
            const double d = img.pixel(x, y)[c] - b.rgba[size_t(c)];
            sq += d * d / 3;
            e = std::max(e, std::abs(d));
          }
          errs.push_back(e);
        }
      std::sort(errs.begin(), errs.end());
      const double rms = std::sqrt(sq / double(errs.size()));
      const double p99 = errs[size_t(0.99 * double(errs.size() - 1))];
      rms_of[std::string(impl.name) + "/" + filter] = rms;
      std::printf("%s,%s,%.6g,%.6g,%.6g,%.6g,%llu,%.6g,%.6g\n", std::string(impl.name).c_str(), filter, rms, p99,
                  errs.back(), t, (unsigned long long)st.items, 1e9 * t / double(std::max<uint64_t>(st.items, 1)),
                  setup);
      std::fflush(stdout);
    }
  }
  auto r = [&](const char* k) { return rms_of[std::string("reference/") + k]; };
  claims.check(r("super8") < r("super4") && r("super4") < r("super2") && r("super2") < r("point"),
               "supersampling converges: rms super8 < super4 < super2 < point");
  claims.check(r("trilinear") < r("point"), "trilinear is more accurate than point sampling");
  claims.check(r("aniso16") < r("trilinear") && r("ewa") < r("trilinear"),
               "aniso16 and ewa are more accurate than trilinear");
  for (const char* e : errors) {
    const double rms = rms_of[std::string("simd/error") + e];
    claims.check(rms <= std::atof(e), std::string("error=") + e + " keeps the frame's RMS against the box filter under it (" +
                                          std::to_string(rms) + ")");
  }
  for (const char* f : filters)
    if (rms_of.count(std::string("simd/") + f))
      claims.check(std::abs(rms_of[std::string("simd/") + f] - r(f)) < 1e-5,
                   std::string("simd's error equals the reference's for ") + f);
  return claims.exit_code();
}
