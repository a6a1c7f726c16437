// lockstep props/raster: SimdTargets.zbuffer__simd and FlatShine.zbuffer__simd --
// the simd z-buffer on every compiled Highway target (registered in visibility.cpp).
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "kinds/image_metrics.h"
#include "optimized/zbuffer/zbuffer_simd.h"
#include "props/raster/visibility.h"

namespace lockstep::props::raster::vis {

namespace {

struct TargetGuard {
  explicit TargetGuard(int64_t t) { hwy::SetSupportedTargetsForTest(t); }
  ~TargetGuard() { hwy::SetSupportedTargetsForTest(0); }  // back to the real CPU
};

}  // namespace

// Dispatch picks one target on this machine (AVX-512 here); the kernels' other
// targets (AVX2: 4 double lanes and two halves per block; SSE4: 4 and 2; the
// scalar one) must agree too. Fixed soups (std::mt19937) through the agreement
// check, and corpus frames against the reference, per compiled target.
void every_target(const Family& family) {
  const auto targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  std::vector<VisCase> cases;
  std::mt19937 rng(7);
  for (int n = 0; n < 40; ++n) {
    VisCase c;
    c.width = 20 + int(rng() % 50), c.height = 10 + int(rng() % 40);
    c.spp = n % 3 == 0 ? 4 : 1;
    c.depth = n % 4 == 1   ? DepthFormat::kFixed24
              : n % 4 == 2 ? DepthFormat::kReversed
                           : DepthFormat::kFloat;
    for (int t = 0; t < 12; ++t) {
      std::array<VisCase::Vertex, 3> tri;
      const bool huge = t % 5 == 4;
      if (t % 5 == 3) {  // an edge across the guard band through the frame (double lanes)
        const double px = double(rng() % uint32_t(c.width * kSubpixel)),
                     py = double(rng() % uint32_t(c.height * kSubpixel));
        const double a = double(rng() % 1000) * 2 * M_PI / 1000, len = double(1 << 24) - 4096;
        tri[0] = {int32_t(px - len * std::cos(a)), int32_t(py - len * std::sin(a)),
                  1 + double(rng() % 60000) / 1000};
        tri[1] = {int32_t(px + len * std::cos(a)), int32_t(py + len * std::sin(a)),
                  1 + double(rng() % 60000) / 1000};
        tri[2] = {int32_t(rng() % uint32_t(c.width * kSubpixel)),
                  int32_t(rng() % uint32_t(c.height * kSubpixel)),
                  1 + double(rng() % 60000) / 1000};
        c.tris.push_back(tri);
        continue;
      }
      for (auto& v : tri) {
        const int32_t span = huge ? (1 << 24) : (c.width + 4) * kSubpixel;
        v.x = int32_t(int64_t(rng() % uint32_t(2 * span)) - span / 2 + c.width * kSubpixel / 2);
        v.y = int32_t(int64_t(rng() % uint32_t(2 * span)) - span / 2 + c.height * kSubpixel / 2);
        if (rng() % 3 == 0) v.x = v.x / kSubpixel * kSubpixel + kSubpixel / 2;  // on sample columns
        v.z = 1 + double(rng() % 60000) / 1000;
      }
      c.tris.push_back(tri);
    }
    cases.push_back(c);
  }
  const FamilyImpl* simd = family.find("simd");
  ASSERT_NE(simd, nullptr);
  CompareOptions cmp;
  cmp.fail_threshold = family.tol.abs;
  cmp.fail_percent = 100.0 * (1.0 - family.tol.fraction);
  for (const int64_t t : targets) {
    TargetGuard guard(t);
    ASSERT_EQ(std::string(opt::zsimd_target_name()), std::string(hwy::TargetName(t)))
        << "dispatch did not follow SetSupportedTargetsForTest";
    const Subject subj{"simd", simd_1};
    for (size_t i = 0; i < cases.size(); ++i) {
      const Verdict v = agreement(subj, cases[i]);
      EXPECT_TRUE(v.passed()) << "Highway target " << hwy::TargetName(t) << ", soup " << i << ": "
                              << v.first_failure();
    }
    // (clip-tris: single-triangle polygons through the hither plane and the
    // guard band, two-sided back faces: the image path's polygon loop under
    // every culling mode. mount-3: a run of single-triangle polygons that hide
    // one another, polygon_run's, in both float depth formats.)
    const std::vector<std::pair<const char*, std::vector<const char*>>> frames = {
        {"gears-2", {}}, {"teapot-2", {}}, {"balls-2", {}}, {"spotlights", {}},
        {"mount-3", {"shading=flat", "shading=flat depth=reversed", "shading=flat cull=projection"}},
        {"clip-tris",
         {"shading=flat", "shading=flat cull=projection", "shading=flat cull=none",
          "shading=flat depth=reversed", "shading=phong"}}};
    int nframes = 0;
    for (const auto& [name, own] : frames)
      for (const char* params :
           own.empty() ? std::vector<const char*>{"shading=flat", "shading=phong",
                                                  "shading=gouraud spp=4",
                                                  "shading=toon silhouette=1 spp=9"}
                       : own) {
        ++nframes;
        const std::string path = std::string(LOCKSTEP_CORPUS_DIR) + "/scenes/" + name + ".nff";
        const Input in = family.load(path);
        FrameOptions o;
        o.width = 67, o.height = 45, o.threads = 1;
        std::istringstream ps(params);
        for (std::string kv; ps >> kv;)
          o.params.set(kv.substr(0, kv.find('=')), kv.substr(kv.find('=') + 1));
        FrameStats want_stats, got_stats;
        const Image want = family.reference().run_as<Image>(in, o, &want_stats);
        const Image got = simd->run_as<Image>(in, o, &got_stats);
        const ImageError e = compare_images(got, want, cmp);
        EXPECT_TRUE(e.pass) << name << " " << params << " on Highway target " << hwy::TargetName(t)
                            << ": " << describe(e);
        // The triangle count the stats line reports (the set-up's own count,
        // whatever it leaves out): the reference's.
        EXPECT_EQ(got_stats.items, want_stats.items)
            << name << " " << params << " on Highway target " << hwy::TargetName(t);
      }
    std::printf("[ lockstep ] zbuffer simd on %-7s: %zu soups, %d corpus frames checked\n",
                hwy::TargetName(t), cases.size(), nframes);
  }
}

// Flat colours are lit in float lanes, in double ones where a surface's shine
// is high (FlatColors): corpus/scenes/shiny.nff's highlights of every
// sharpness, on every compiled target, within 1.5e-5 of the reference's double
// lighting on every pixel (measured 6.3e-6, on the shine-250 sphere; 1.1e-5 on
// balls-2 at shine 250, 512^2; lit in float, the shine-1e5 quad would be off
// by 5.6e-3).
void flat_shine(const Family& family) {
  const FamilyImpl* simd = family.find("simd");
  ASSERT_NE(simd, nullptr);
  const Input in = family.load(std::string(LOCKSTEP_CORPUS_DIR) + "/scenes/shiny.nff");
  FrameOptions o;
  o.width = 96, o.height = 96, o.threads = 1;
  o.params.set("shading", "flat");
  const Image want = family.reference().run_as<Image>(in, o, nullptr);
  constexpr double kBound = 1.5e-5;
  for (const int64_t t : hwy::SupportedAndGeneratedTargets()) {
    TargetGuard guard(t);
    const Image got = simd->run_as<Image>(in, o, nullptr);
    double worst = 0;
    int wx = 0, wy = 0;
    for (int y = 0; y < o.height; ++y)
      for (int x = 0; x < o.width; ++x)
        for (int c = 0; c < 3; ++c) {
          const double e = std::abs(double(got.pixel(x, y)[c]) - double(want.pixel(x, y)[c]));
          if (e > worst) worst = e, wx = x, wy = y;
        }
    EXPECT_LE(worst, kBound) << "shiny.nff flat on Highway target " << hwy::TargetName(t)
                             << ": pixel (" << wx << ", " << wy << ") simd "
                             << got.pixel(wx, wy)[0] << " " << got.pixel(wx, wy)[1] << " "
                             << got.pixel(wx, wy)[2] << ", reference " << want.pixel(wx, wy)[0]
                             << " " << want.pixel(wx, wy)[1] << " " << want.pixel(wx, wy)[2];
    std::printf("[ lockstep ] shiny.nff flat on %-7s: largest colour error %.2e (bound %.0e)\n",
                hwy::TargetName(t), worst, kBound);
  }
}

}  // namespace lockstep::props::raster::vis
