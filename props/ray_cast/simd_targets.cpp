// Every Highway target the simd kernels were compiled for (AVX-512, AVX2, SSE4,
// SSSE3 on x86-64-v3 builds; whatever the machine supports) renders like the
// reference, not only the one dispatch picks on this machine. The layout follows
// Highway's own tests: restrict the supported targets with
// hwy::SetSupportedTargetsForTest, run, compare, restore.
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <string>

#include "kinds/image_metrics.h"
#include "io/nff.h"
#include "optimized/ray_cast_simd.h"
#include "registry/ray_cast_row.h"

namespace lockstep {
namespace {

struct TargetGuard {
  explicit TargetGuard(int64_t t) { hwy::SetSupportedTargetsForTest(t); }
  ~TargetGuard() { hwy::SetSupportedTargetsForTest(0); }  // back to the real CPU
};

TEST(SimdTargets, EveryCompiledTargetRendersLikeTheReference) {
  const auto targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  const auto& pair = ray_cast_rows().ray_cast;
  const auto* simd = pair.find("simd");
  ASSERT_NE(simd, nullptr);
  CompareOptions cmp;
  cmp.fail_threshold = pair.tol.color_abs;
  cmp.fail_percent = 100.0 * (1.0 - pair.tol.pixel_fraction);
  for (const char* name : {"balls-1", "gears-2", "teapot-2", "sidedness"}) {
    const std::string path = std::string(LOCKSTEP_CORPUS_DIR) + "/scenes/" + name + ".nff";
    const Scene scene = read_nff(path);
    FrameOptions opts;
    opts.width = 96;
    opts.height = 64;
    opts.threads = 1;
    const Image want = pair.impls[0].fn.render(scene, opts, nullptr);
    for (const int64_t t : targets) {
      TargetGuard guard(t);
      ASSERT_EQ(std::string(opt::simd::target_name()), std::string(hwy::TargetName(t)))
          << "dispatch did not follow SetSupportedTargetsForTest";
      const Image got = simd->fn.render(scene, opts, nullptr);
      const ImageError e = compare_images(got, want, cmp);
      EXPECT_TRUE(e.pass) << name << " on Highway target " << hwy::TargetName(t) << ": " << describe(e)
                          << " (worst pixel " << e.max_x << "," << e.max_y << ")";
      std::printf("[ lockstep ] simd on %-7s %-10s %s\n", hwy::TargetName(t), name, describe(e).c_str());
    }
  }
}

}  // namespace
}  // namespace lockstep
