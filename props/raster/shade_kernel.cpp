// lockstep props/raster: the SIMD shading kernel (optimized/zbuffer/zbuffer_simd_kernels.h,
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
//   ShadeKernel.FlatFacingAsReference   flat_colors turns each face towards
//       the eye exactly as view_scene's lit() does: negated where
//       dot(n, normalize(eye - p)) < 0 in double. Faces seen nearly edge-on
//       (n tilted from the plane through the eye by 0 to 1e-5 radians, both
//       ways), the light well off each face's plane on a random side: a face
//       turned the reference's way is lit by the light exactly when the
//       reference's is (ambient only otherwise). Deciding in float -- what
//       the kernel did -- turns about half the faces tilted by less than
//       ~1e-7 the other way (CullingAgree.zbuffer__simd in deep mode found it);
//       the tilts up to ~1e-13 also exercise the lanes the kernel leaves to
//       the reference's own expression. Both surfaces' paths: float lanes and
//       (a high shine) double ones.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>
#include <vector>

#include "core/math.h"
#include "core/shading.h"

#include "hwy/aligned_allocator.h"
#include "optimized/zbuffer/zbuffer_simd_kernels.h"

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

TEST(ShadeKernel, FlatFacingAsReference) {
  constexpr uint64_t kSeed = 20261203;
  constexpr size_t kRequests = 4000;  // (not a multiple of 16: a padded tail)
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> coord(-10.0, 10.0);
  // The eye off the float grid (the kernel must decide on the double one).
  const Vec3 eye{0.1, -0.3, 0.7};
  const Vec3 light{3, 7, -2};
  const double tilts[] = {0, 1e-16, -1e-16, 1e-14, -1e-14, 1e-13, -1e-13, 1e-11, -1e-11,
                          1e-9, -1e-9, 1e-7, -1e-7, 1e-5, -1e-5};
  constexpr size_t kTilts = std::size(tilts);
  // Two surfaces (ids do not decrease): kd * colour, ks, shine; the second's
  // high shine takes the double lanes (kFloatShine).
  const opt::zsimd::FlatSurface surfaces[2] = {{{0.6, 0.3, 0.2, 0.0, 1.0}},
                                               {{0.6, 0.3, 0.2, 0.5, 1000.0}}};
  const size_t padded = (kRequests + 15) / 16 * 16;
  std::vector<double> in_planes[6];
  for (auto& v : in_planes) v.assign(padded, 0.0);
  std::vector<uint32_t> id(padded, 1);
  std::vector<Vec3> pos(kRequests), nrm(kRequests);
  for (size_t i = 0; i < kRequests; ++i) {
    // A point whose direction to the light is well off the direction to the
    // eye; the face's normal perpendicular to the eye's direction, towards
    // the light or away from it, then tilted.
    Vec3 p, perp;
    do {
      p = {coord(rng), coord(rng), coord(rng)};
      const Vec3 d = eye - p, lp = light - p;
      perp = lp - d * (dot(lp, d) / dot(d, d));
    } while (!(length(perp) > 0.3 * length(light - p)));
    const Vec3 n0 = normalize(perp) * ((rng() & 1) ? 1.0 : -1.0);
    const Vec3 n = normalize(n0 + tilts[i % kTilts] * normalize(eye - p));
    pos[i] = p, nrm[i] = n;
    for (int c = 0; c < 3; ++c) in_planes[c][i] = p[c], in_planes[3 + c][i] = n[c];
    id[i] = i < kRequests / 2 ? 0 : 1;
  }
  std::vector<float> lights = {float(light.x), float(light.y), float(light.z), 1, 1, 1, 1, 0, 0,
                               0, 0, 0, 0, 0, 0};
  ShadeParams sp;
  sp.nlights = 1;
  sp.light = lights.data();
  sp.eye[0] = float(eye.x), sp.eye[1] = float(eye.y), sp.eye[2] = float(eye.z);
  sp.flat_eye[0] = eye.x, sp.flat_eye[1] = eye.y, sp.flat_eye[2] = eye.z;
  const double* in[6];
  for (int k = 0; k < 6; ++k) in[k] = in_planes[k].data();
  std::vector<float> rgb(3 * padded);
  float* out[3] = {rgb.data(), rgb.data() + padded, rgb.data() + 2 * padded};
  opt::zsimd::flat_colors(sp, kRequests, in, id.data(), surfaces, out);

  // Ambient alone: kAmbient kd; lit: at least 0.3 kd more (N.L >= 0.3).
  const double ambient = kAmbient * surfaces[0].k[0];
  size_t flipped_near = 0, near = 0, mismatches = 0;
  std::ostringstream first;
  for (size_t i = 0; i < kRequests; ++i) {
    const Vec3 &p = pos[i], &n = nrm[i];
    const double ref_dot = dot(n, normalize(eye - p));  // core/viewing.cpp's lit()
    const Vec3 turned = ref_dot < 0 ? -n : n;
    const bool want_lit = dot(turned, light - p) > 0;
    const bool got_lit = out[0][i] > ambient + 0.1;
    if (std::abs(tilts[i % kTilts]) <= 1e-13) ++near, flipped_near += ref_dot < 0;
    if (got_lit == want_lit) continue;
    if (mismatches++ == 0) {
      char buf[512];
      std::snprintf(buf, sizeof buf,
                    "seed %llu, request %zu (surface %u, tilt %g): eye (%a %a %a) p (%a %a %a) "
                    "n (%a %a %a); reference dot(n, normalize(eye - p)) = %a (%s), so %s; "
                    "reference red %s %.6f; flat_colors red %.6f (%s), off by %.6f",
                    (unsigned long long)kSeed, i, id[i], tilts[i % kTilts], eye.x, eye.y, eye.z,
                    p.x, p.y, p.z, n.x, n.y, n.z, ref_dot, ref_dot < 0 ? "turned" : "kept",
                    want_lit ? "lit" : "ambient only", want_lit ? ">=" : "=",
                    want_lit ? ambient + 0.18 : ambient, out[0][i],
                    got_lit ? "lit" : "ambient only",
                    want_lit ? ambient + 0.18 - out[0][i] : out[0][i] - ambient);
      first << buf;
    }
  }
  EXPECT_EQ(mismatches, 0u) << "faces turned otherwise than by the reference, of " << kRequests
                            << "; the first: " << first.str();
  // The test can fail: the reference turns a good share of the faces nearest
  // edge-on either way (there the sign is its rounding's).
  EXPECT_GT(flipped_near, near / 10) << flipped_near << " of " << near;
  EXPECT_LT(flipped_near, near - near / 10) << flipped_near << " of " << near;
}

}  // namespace
}  // namespace lockstep::props::raster
