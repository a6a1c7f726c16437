// lockstep props/raster: the SIMD shading kernel (optimized/zbuffer_simd_kernels.h,
// shade_tile) on hand-made tiles, for what a whole scene reaches only by
// accident.
//
//   ShadeKernel.VanishedNormalTakesFaceNormal   A sample whose interpolated
//       normal is exactly 0 (opposite vertex normals cancel there) is lit with
//       its triangle's face normal, as the reference's fragments are: the same
//       colour as a triangle whose normal planes hold that face normal. Scenes
//       never hit it on purpose (the zero must be exact), so it is tested here.
//   ShadeKernel.ConstantAttenuation   A light with attenuation c1 alone (and
//       no spot) scales every lane alike: c1 = 2 lights as half the intensity.
//   ShadeKernel.MaterialPerLane   A 16-sample block holding triangles of two
//       materials lights each sample with its own (the kernel broadcasts one
//       material per block, and gathers per lane when a block holds several).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <sstream>
#include <vector>

#include "hwy/aligned_allocator.h"
#include "optimized/zbuffer_simd_kernels.h"

namespace lockstep::props::raster {
namespace {

using opt::zsimd::TilePlanes;
using opt::zsimd::ShadeMaterial;
using opt::zsimd::ShadeParams;

constexpr int kCols = 16;

// One row of kCols samples at pixel centres, the eye at the origin looking
// down +z (the sample at eye depth z is eye + z dir, dir = (u - 8, 0, 1) / 16
// at pixel u), one light, Phong shading.
struct Tile {
  std::vector<float> lights = {2, 1, -3, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0};
  std::vector<ShadeMaterial> materials = {{{0.6f, 0.3f, 0.2f}, 0.5f, 20.0f},
                                          {{0.1f, 0.5f, 0.7f}, 0.0f, 1.0f}};
  std::array<std::array<int32_t, 2>, 1> centre = {{{128, 128}}};
  ShadeParams params() const {
    ShadeParams p;
    p.shading = Shading::kPhong;
    p.nlights = 1;
    p.light = lights.data();
    p.materials = materials.data();
    p.dir0[0] = -0.5f, p.dir0[1] = 0.0f, p.dir0[2] = 1.0f;
    p.dir_u[0] = 1.0f / 16, p.dir_u[1] = 0.0f, p.dir_u[2] = 0.0f;
    p.dir_v[0] = 0.0f, p.dir_v[1] = -1.0f / 16, p.dir_v[2] = 0.0f;
    p.background[0] = p.background[1] = p.background[2] = 0.25f;
    p.offsets = centre.data();
    p.spp = 1;
    p.buf_w = kCols, p.buf_h = 1;
    return p;
  }
};

// A triangle at eye depth 4 everywhere (w = 1/4, exact), its normal planes
// (attribute / z under perspective) holding normal n: constant n w.
TilePlanes constant_triangle(const float n[3], const float face[3], uint32_t material) {
  TilePlanes L{};
  L.p[0][0] = 0.25f;
  for (int c = 0; c < 3; ++c) L.p[1 + c][0] = n[c] * 0.25f;
  for (int c = 0; c < 3; ++c) L.tri.face[c] = face[c];
  L.tri.material = material;
  return L;
}

// The tile's RGBA pixels (tri: the triangle id per sample, -1 none; planes: per id).
std::vector<float> shade(const ShadeParams& p, const std::array<int32_t, kCols>& tri,
                         const std::vector<TilePlanes>& planes) {
  std::vector<const TilePlanes*> where;
  for (const TilePlanes& t : planes) where.push_back(&t);
  auto ids = hwy::AllocateAligned<int32_t>(kCols);
  std::copy(tri.begin(), tri.end(), ids.get());
  auto rgb = hwy::AllocateAligned<float>(3 * kCols);
  auto z = hwy::AllocateAligned<float>(kCols);
  auto image = hwy::AllocateAligned<float>(4 * kCols);
  auto depth = hwy::AllocateAligned<float>(kCols);
  opt::zsimd::shade_tile(p, ids.get(), where.data(), kCols, 1, rgb.get(), z.get(),
                    image.get(), 4 * kCols, depth.get(), kCols);
  return std::vector<float>(image.get(), image.get() + 4 * kCols);
}

std::string pixels(const std::vector<float>& v) {
  std::ostringstream os;
  for (size_t i = 0; i < v.size(); i += 4)
    os << " (" << v[i] << ' ' << v[i + 1] << ' ' << v[i + 2] << ')';
  return os.str();
}

TEST(ShadeKernel, VanishedNormalTakesFaceNormal) {
  const Tile tile;
  const ShadeParams p = tile.params();
  const float face[3] = {0.3f, 0.0f, -0.9539392f};  // unit, towards the eye and the light
  const float zero[3] = {0, 0, 0};
  std::array<int32_t, kCols> tri;
  tri.fill(0);
  tri[kCols - 1] = -1;  // one empty sample: background, not a face normal
  const auto vanished = shade(p, tri, {constant_triangle(zero, face, 0)});
  const auto planar = shade(p, tri, {constant_triangle(face, face, 0)});
  // And a triangle facing the other way round the light: were the vanished
  // normal left at 0 (ambient only) or taken from elsewhere, it would show.
  const float other[3] = {-0.6f, 0.0f, -0.8f};
  const auto turned = shade(p, tri, {constant_triangle(other, other, 0)});
  for (int i = 0; i < 4 * (kCols - 1); ++i) {
    ASSERT_EQ(vanished[i], planar[i]) << "sample " << i / 4 << "\n  vanished:" << pixels(vanished)
                                      << "\n  planar:  " << pixels(planar);
  }
  EXPECT_NE(vanished[0], turned[0]) << pixels(vanished) << "\n" << pixels(turned);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(vanished[4 * (kCols - 1) + c], 0.25f);
}

TEST(ShadeKernel, ConstantAttenuation) {
  // f_att = min(1, 1 / c1) with c2 = c3 = 0, the same for every lane (the
  // kernel takes it once per light): a light of intensity 1 at c1 = 2 lights
  // as one of intensity 0.5 at c1 = 1, and unlike one of intensity 1.
  const float n[3] = {0.3f, 0.0f, -0.9539392f};
  std::array<int32_t, kCols> tri;
  tri.fill(0);
  auto lit = [&](float intensity, float c1) {
    Tile tile;
    for (int c = 0; c < 3; ++c) tile.lights[3 + c] = intensity;
    tile.lights[6] = c1;
    return shade(tile.params(), tri, {constant_triangle(n, n, 0)});
  };
  const auto halved = lit(1.0f, 2.0f), half = lit(0.5f, 1.0f), full = lit(1.0f, 1.0f);
  for (size_t i = 0; i < halved.size(); ++i)
    ASSERT_EQ(halved[i], half[i]) << "channel " << i << "\n  c1 = 2:" << pixels(halved)
                                  << "\n  half: " << pixels(half);
  EXPECT_NE(halved[0], full[0]) << pixels(halved) << "\n" << pixels(full);
}

TEST(ShadeKernel, MaterialPerLane) {
  const Tile tile;
  const ShadeParams p = tile.params();
  const float n[3] = {0.3f, 0.0f, -0.9539392f};
  const std::vector<TilePlanes> planes = {constant_triangle(n, n, 0), constant_triangle(n, n, 1)};
  std::array<int32_t, kCols> all0, all1, mixed;
  all0.fill(0), all1.fill(1);
  for (int i = 0; i < kCols; ++i) mixed[i] = (i * 7 + 3) % 5 < 2 ? 1 : 0;
  const auto a = shade(p, all0, planes), b = shade(p, all1, planes), m = shade(p, mixed, planes);
  for (int i = 0; i < kCols; ++i)
    for (int c = 0; c < 4; ++c) {
      const float want = (mixed[i] ? b : a)[4 * i + c];
      ASSERT_EQ(m[4 * i + c], want) << "sample " << i << " (material " << mixed[i] << ")\n  mixed:"
                                    << pixels(m) << "\n  one:  " << pixels(a)
                                    << "\n  other:" << pixels(b);
    }
  EXPECT_NE(a[0], b[0]);
}

}  // namespace
}  // namespace lockstep::props::raster
