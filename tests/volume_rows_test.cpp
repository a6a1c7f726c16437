// The volume families' simd rows as the registry builds them (registry/volume_rows.cpp):
// the optimized kernels draw volumes with a cell on every axis and footprints
// of at most 4096 pixels, and say so (opt::simd::volume_cast_handles,
// volume_splat_handles); the row hands the rest to the reference, so a slice
// or a line drawn by `--impl simd` is the reference's image bit for bit, and
// the kernels themselves refuse it rather than draw it wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>

#include "core/family.h"
#include "core/volume.h"
#include "optimized/volume_raycast_simd.h"
#include "optimized/volume_splat_simd.h"
#include "registry/registry.h"

namespace lockstep {
namespace {

// nx x ny x nz samples of a smooth bump, values in [0, 1].
Volume bump(int nx, int ny, int nz) {
  Volume v;
  v.nx = nx, v.ny = ny, v.nz = nz;
  v.spacing = {1, 1, 1};
  v.data.resize(size_t(nx) * size_t(ny) * size_t(nz));
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) v.at(i, j, k) = float(0.5 + 0.5 * std::sin(0.7 * i + 1.1 * j + 0.4 * k));
  v.source = "bump";
  return v;
}

FrameOptions frame(int size, const char* key, const char* value) {
  FrameOptions o;
  o.width = o.height = size;
  o.threads = 1;
  o.params.set("view", "30,20");
  o.params.set(key, value);
  return o;
}

TEST(VolumeRows, SimdRowsDrawSlicesAndLinesAsTheReference) {
  struct Case {
    const char* family;
    const char* key;
    const char* value;
  };
  // Splatting draws slices itself (a voxel needs no cell); its kernel
  // refuses a footprint wider than 4096 pixels: samples 100 apart across x
  // (one of them) are Gaussians of sigma 60, seen across a frame 1.4 wide
  // (the bounding sphere's diameter) of 128 pixels, about 6,000 pixels
  // across. The frames below are 128 pixels wide.
  Volume wide = bump(1, 2, 2);
  wide.spacing = {100, 1, 1};
  EXPECT_FALSE(opt::simd::volume_splat_handles(wide, frame(128, "tf", "ramp")));
  const Case families[] = {{"volume", "tf", "ramp"}, {"volume_iso", "iso", "0.5"}, {"splat", "tf", "ramp"}};
  const int shapes[][3] = {{1, 6, 6}, {6, 1, 6}, {6, 6, 1}, {1, 1, 6}, {1, 1, 1}};
  int drawn = 0;
  for (const Case& c : families) {
    const Family* f = registry().find(c.family);
    ASSERT_NE(f, nullptr) << c.family;
    const FamilyImpl* simd = f->find("simd");
    const FamilyImpl* reference = f->find("reference");
    ASSERT_NE(simd, nullptr);
    ASSERT_NE(reference, nullptr);
    for (size_t q = 0; q < std::size(shapes); ++q) {
      const int* s = shapes[q];
      const bool splat = std::string(c.family) == "splat";
      if (splat && q > 0) continue;
      const Volume v = splat ? wide : bump(s[0], s[1], s[2]);
      const Input in = make_input(v, "bump", 128, 128);
      const FrameOptions o = frame(128, c.key, c.value);
      const std::string what = std::string(c.family) + " " + std::to_string(v.nx) + "x" + std::to_string(v.ny) +
                               "x" + std::to_string(v.nz) + (splat ? " spacing 100,1,1" : "");
      const Image a = simd->run_as<Image>(in, o, nullptr);
      const Image b = reference->run_as<Image>(in, o, nullptr);
      ASSERT_EQ(a.rgba.size(), b.rgba.size()) << what;
      for (size_t q = 0; q < a.rgba.size(); ++q)
        ASSERT_EQ(a.rgba[q], b.rgba[q]) << what << ": channel " << q % 4 << " of pixel " << q / 4 << ", simd row "
                                        << a.rgba[q] << ", reference " << b.rgba[q];
      ++drawn;
    }
  }
  EXPECT_EQ(drawn, 11);
}

TEST(VolumeRows, KernelsSayWhatTheyDrawAndRefuseTheRest) {
  EXPECT_TRUE(opt::simd::volume_cast_handles(bump(2, 2, 2)));
  for (const auto& v : {bump(1, 6, 6), bump(6, 1, 6), bump(6, 6, 1)}) {
    EXPECT_FALSE(opt::simd::volume_cast_handles(v));
    EXPECT_THROW(opt::simd::volume_raycast(v, frame(8, "tf", "ramp"), nullptr), std::invalid_argument);
    EXPECT_THROW(opt::simd::volume_iso(v, frame(8, "iso", "0.5"), nullptr), std::invalid_argument);
  }
  // Splatting: an ordinary frame is drawn; a few voxels in a frame so large
  // that one footprint is wider than 4096 pixels are not (decided without
  // drawing), nor is an empty volume.
  EXPECT_TRUE(opt::simd::volume_splat_handles(bump(6, 6, 6), frame(64, "tf", "ramp")));
  const Volume tiny = bump(2, 2, 2);
  const FrameOptions huge = frame(40000, "tf", "ramp");
  EXPECT_TRUE(opt::simd::volume_splat_handles(tiny, frame(3000, "tf", "ramp")));
  EXPECT_FALSE(opt::simd::volume_splat_handles(tiny, huge));
  EXPECT_THROW(opt::simd::volume_splat(tiny, huge, nullptr), std::invalid_argument);
  EXPECT_FALSE(opt::simd::volume_splat_handles(Volume{}, frame(8, "tf", "ramp")));
}

}  // namespace
}  // namespace lockstep
