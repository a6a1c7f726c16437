// lockstep props/raster: the z-buffer's shadow maps (shadows=map, a setting of
// the zbuffer family; core/shadow_map.h), the part "shadow_map" of its
// properties: fixed tests of lockstep_props, each running its RapidCheck
// property through props/driver/rc_run.h (a seed fixed per property; 100 cases,
// LOCKSTEP_DEEP=1: 1000).
//
//   ShadowMaps.zbuffer__cube_face_every_direction_once  any direction (random,
//       and on the cube's edges and corners: components equal in magnitude, or
//       0) falls in the closed frustum of the face cube_face gives it, and in
//       the open frustum of no other face: the six faces cover every direction
//       exactly once. ShadowMaps.zbuffer__cube_face_mutant_caught: the same
//       check of a wrong face selection (the second-largest axis) must fail.
//   ShadowMaps.zbuffer__texel_round_trip  the direction through a texel's
//       centre finds that texel again (any face, map sizes 1..4096).
//   ShadowMaps.zbuffer__no_occluder_same_as_unshadowed  a tilted ground quad
//       lit by a light in front of it (meeting every point within 78 degrees
//       of its normal), a triangle beyond the light
//       (nothing between the light and any surface): the reference's frame
//       with shadows=map (default bias, random map size 64..1024) equals the
//       frame with shadows=none bit for bit but on rare acne texels, at most
//       kNoOccluderAcneRate of the pixels over the run; the simd row's
//       shadowed frame equals the reference's within 1/255.
//   ShadowMaps.zbuffer__agree_shadow_rays  the same ground with one to three
//       triangles floating between it and the light: per pixel against the
//       reference ray tracer (depth 1, shadow rays), wrong pixels (over 1/255,
//       where the two agree without shadows) at most kAgreeRate of the
//       compared pixels over the run, at map_size 1024 and the default bias.
#include <gtest/gtest.h>
#include <rapidcheck.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <sstream>
#include <string>

#include "io/nff.h"
#include "core/shadow_map.h"
#include "optimized/zbuffer/zbuffer_simd.h"
#include "props/driver/rc_run.h"
#include "props/raster/parts.h"
#include "reference/raster.h"
#include "reference/ray_trace.h"

namespace lockstep::props::raster {
namespace {

// ---------------------------------------------------------------- cube faces

rc::Gen<Vec3> direction() {
  // Components from a few values that make ties (+-a, 0) or anything.
  return rc::gen::exec([] {
    const double a = *rc::gen::inRange(1, 1000000) / 1e6;
    auto comp = [&] {
      const int k = *rc::gen::inRange(0, 5);
      if (k == 0) return a;
      if (k == 1) return -a;
      if (k == 2) return 0.0;
      return (*rc::gen::inRange(-1000000, 1000001)) / 1e6;
    };
    Vec3 d{comp(), comp(), comp()};
    if (d == Vec3{}) d.x = 1;
    return d;
  });
}

// d in face f's frustum: closed (|x|, |y| <= z) or open (<, and z > 0).
bool in_frustum(int f, const Vec3& d, bool closed) {
  const Camera c = cube_face_camera({0, 0, 0}, f, 2);
  const double x = dot(d, c.right), y = dot(d, c.up), z = dot(d, c.forward);
  if (!(z > 0)) return false;
  return closed ? std::abs(x) <= z && std::abs(y) <= z : std::abs(x) < z && std::abs(y) < z;
}

void every_direction_once(const std::function<int(const Vec3&)>& face_of, const Vec3& d) {
  const int f = face_of(d);
  RC_ASSERT(f >= 0);
  RC_ASSERT(f < kCubeFaces);
  RC_ASSERT(in_frustum(f, d, true));
  for (int g = 0; g < kCubeFaces; ++g)
    if (g != f) RC_ASSERT(!in_frustum(g, d, false));
}

void cube_face_every_direction_once() {
  rc_run::run("shadow_maps.cube_face_every_direction_once.zbuffer",
              [] { every_direction_once(cube_face, *direction()); });
}

// The second-largest axis's face: a plausible slip (the wrong comparison).
int wrong_face(const Vec3& d) {
  const double ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
  if (ax >= ay && ax >= az) return ay >= az ? (d.y >= 0 ? 2 : 3) : (d.z >= 0 ? 4 : 5);
  return d.x >= 0 ? 0 : 1;
}

void cube_face_mutant_caught() {
  const std::string name = "shadow_maps.cube_face_mutant_caught.zbuffer";
  const rc_run::Params p = rc_run::params(name);
  rc_run::print_seed("lockstep", name, p, rc_run::ctest_line());
  const rc_run::Result r =
      rc_run::check(name, p, [] { every_direction_once(wrong_face, *direction()); });
  EXPECT_FALSE(r.passed) << "a wrong face selection passed the check";
}

void texel_round_trip() {
  rc_run::run("shadow_maps.texel_round_trip.zbuffer", [] {
    const int n = *rc::gen::inRange(1, 4097);
    const int f = *rc::gen::inRange(0, kCubeFaces);
    const int i = *rc::gen::inRange(0, n), j = *rc::gen::inRange(0, n);
    const CubeTexel t = cube_texel(cube_direction(f, i + 0.5, j + 0.5, n), n);
    RC_ASSERT(t.face == f);
    RC_ASSERT(t.i == i);
    RC_ASSERT(t.j == j);
  });
}

// ---------------------------------------------------------------- scenes

double uniform(double lo, double hi) {
  return lo + (hi - lo) * (*rc::gen::inRange(0, 1000001)) / 1e6;
}

// Without rejection loops: RapidCheck's small early sizes repeat values.
Vec3 unit() {
  const double z = uniform(-1, 1), phi = uniform(0, 2 * M_PI),
               s = std::sqrt(std::max(0.0, 1 - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

// A basis (u, w) of the plane with unit normal n.
void plane_basis(const Vec3& n, Vec3& u, Vec3& w) {
  u = normalize(cross(n, std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
  w = cross(n, u);
}

std::string v3(const Vec3& p) {
  char b[128];
  std::snprintf(b, sizeof b, "%.17g %.17g %.17g", p.x, p.y, p.z);
  return b;
}

struct Ground {
  Vec3 n, light;
  std::ostringstream nff;
};

// A ground quad of half-size h through the origin with normal n (facing n,
// counter-clockwise seen from n's side), a light in front, the eye in front.
void ground(Ground& g) {
  g.n = unit();
  Vec3 u, w;
  plane_basis(g.n, u, w);
  const double h = uniform(1, 3);
  // Directions at cos >= lo from n: around n by a random azimuth.
  auto around = [&](double lo) {
    const double c = uniform(lo, 1), phi = uniform(0, 2 * M_PI), sn = std::sqrt(1 - c * c);
    return c * g.n + sn * std::cos(phi) * u + sn * std::sin(phi) * w;
  };
  // The light above a point of the quad, high enough that it meets every
  // point of the quad within 78 degrees of the normal (tan <= 4.7, below the
  // bias's cap of 10: beyond 84 degrees acne returns, core/shadow_map.h).
  const Vec3 foot = uniform(-h, h) * u + uniform(-h, h) * w;
  double reach = 0;
  for (const Vec3& corner : {-h * u - h * w, h * u - h * w, h * u + h * w, -h * u + h * w})
    reach = std::max(reach, length(corner - foot));
  g.light = foot + std::max(uniform(0.3, 10), reach / 4.7) * g.n;
  const Vec3 to_eye = around(0.3);
  g.nff << "v\nfrom " << v3(uniform(4, 8) * to_eye) << "\nat 0 0 0\nup " << v3(u)
        << "\nangle 50\nhither 0.01\nresolution 24 24\nb 0.1 0.2 0.3\nl " << v3(g.light) << "\n";
  g.nff << "f 0.8 0.7 0.6 0.9 0.3 8 0 1\np 4\n"
        << v3(-h * u - h * w) << "\n"
        << v3(h * u - h * w) << "\n"
        << v3(h * u + h * w) << "\n"
        << v3(-h * u + h * w) << "\n";
}

Image draw(Image (*fn)(const Scene&, const FrameOptions&, FrameStats*), const Scene& sc, int size,
           const std::string& params) {
  FrameOptions o;
  o.width = o.height = size;
  o.threads = 1;
  std::istringstream in(params);
  std::string kv;
  while (in >> kv) o.params.set(kv.substr(0, kv.find('=')), kv.substr(kv.find('=') + 1));
  return fn(sc, o, nullptr);
}

double max_diff(const Image& a, const Image& b, int x, int y) {
  double m = 0;
  for (int c = 0; c < 3; ++c)
    m = std::max(m, std::abs(double(a.pixel(x, y)[c]) - double(b.pixel(x, y)[c])));
  return m;
}

// Acne with nothing to shadow: the default slope bias is short on rare
// texels (the textbook failure). Measured: 1 pixel of about 340,000 (590
// cases, seed 2639015970186460638: one pixel at map_size 512 only, none at
// 256, 1024 or 2048), 0 in 2,000- and 800-case runs. The bound allows 2 such
// pixels in a 100-case run (a Poisson count of mean 0.2 reaches 3 once in
// about 1,000 runs); each one is printed with its scene.
constexpr double kNoOccluderAcneRate = 5e-5;

void no_occluder_same_as_unshadowed() {
  long pixels = 0, acne = 0;
  const bool passed = rc_run::run("shadow_maps.no_occluder_same_as_unshadowed.zbuffer", [&] {
    Ground g;
    ground(g);
    // A triangle beyond the light, on the far side of the plane through the
    // light parallel to the ground: no segment from the light to a surface
    // point crosses it, nor the ground.
    Vec3 u, w;
    plane_basis(g.n, u, w);
    auto beyond = [&] {
      return g.light + uniform(0.1, 2) * g.n + uniform(-1, 1) * u + uniform(-1, 1) * w;
    };
    g.nff << "f 0.3 0.6 0.9 0.8 0.2 4 0 1\np 3\n"
          << v3(beyond()) << "\n"
          << v3(beyond()) << "\n"
          << v3(beyond()) << "\n";
    const Scene sc = parse_nff(g.nff.str(), "no-occluder");
    const int n = 64 << *rc::gen::inRange(0, 5);
    const std::string map = "shading=phong shadows=map map_size=" + std::to_string(n);
    const Image none = draw(ref::zbuffer, sc, 24, "shading=phong");
    const Image shadowed = draw(ref::zbuffer, sc, 24, map);
    const Image simd = draw(opt::simd::zbuffer, sc, 24, map);
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x) {
        ++pixels;
        if (max_diff(none, shadowed, x, y) != 0.0) {
          ++acne;
          std::printf("NoOccluder: acne at pixel %d,%d, map_size %d\n%s\n", x, y, n,
                      g.nff.str().c_str());
        }
        RC_ASSERT(max_diff(simd, shadowed, x, y) <= 1.0 / 255);
      }
  });
  ASSERT_TRUE(passed);
  const double rate = pixels ? double(acne) / double(pixels) : 0;
  std::printf("ShadowMaps.zbuffer__no_occluder_same_as_unshadowed: %ld acne pixels of %ld (%.3g; bound %.3g)\n", acne,
              pixels, rate, kNoOccluderAcneRate);
  EXPECT_LE(rate, kNoOccluderAcneRate);
}

// Measured: 100-case runs 6.8e-4 .. 1.1e-3 of the compared pixels (four
// seeds), a 1000-case run 5.0e-4 (66 of 133211): a texel's jagged shadow edge.
// The bound: about 3x the worst 100-case run.
constexpr double kAgreeRate = 0.003;

void agree_shadow_rays() {
  long compared = 0, wrong = 0;
  const bool passed = rc_run::run("shadow_maps.agree_shadow_rays.zbuffer", [&] {
    Ground g;
    ground(g);
    const int k = *rc::gen::inRange(1, 4);
    for (int t = 0; t < k; ++t) {
      // A triangle floating between the ground and the light.
      const Vec3 c = uniform(0.2, 0.8) * g.light + uniform(-0.5, 0.5) * unit();
      if (dot(c, g.n) < 0.05) continue;
      g.nff << "f 0.3 0.6 0.9 0.8 0.2 4 0 1\np 3\n"
            << v3(c) << "\n"
            << v3(c + uniform(0.2, 1) * unit()) << "\n"
            << v3(c + uniform(0.2, 1) * unit()) << "\n";
    }
    const Scene sc = parse_nff(g.nff.str(), "agree");
    const Image none_zb = draw(ref::zbuffer, sc, 24, "shading=phong");
    const Image none_rt = draw(ref::trace_render, sc, 24, "depth=1 shadows=none");
    const Image oracle = draw(ref::trace_render, sc, 24, "depth=1 shadows=rays");
    const Image map = draw(ref::zbuffer, sc, 24, "shading=phong shadows=map map_size=1024");
    for (int y = 0; y < 24; ++y)
      for (int x = 0; x < 24; ++x) {
        if (!std::isfinite(none_zb.depth[size_t(y) * 24 + size_t(x)])) continue;
        if (max_diff(none_zb, none_rt, x, y) > 1.0 / 255) continue;
        ++compared;
        if (max_diff(map, oracle, x, y) > 1.0 / 255) ++wrong;
      }
  });
  ASSERT_TRUE(passed);
  const double rate = compared ? double(wrong) / double(compared) : 0;
  std::printf("ShadowMaps.zbuffer__agree_shadow_rays: %ld wrong of %ld compared pixels (%.4g)\n", wrong, compared, rate);
  EXPECT_GT(compared, 1000);
  EXPECT_LE(rate, kAgreeRate);
}

}  // namespace

void shadow_map_part(const Family& family, FamilyProperties& out) {
  const std::string fam(family.name);
  struct Named {
    const char* name;
    void (*body)();
  };
  for (const Named& t : {Named{"cube_face_every_direction_once", cube_face_every_direction_once},
                         Named{"cube_face_mutant_caught", cube_face_mutant_caught},
                         Named{"texel_round_trip", texel_round_trip},
                         Named{"no_occluder_same_as_unshadowed", no_occluder_same_as_unshadowed},
                         Named{"agree_shadow_rays", agree_shadow_rays}})
    out.fixed.push_back({"ShadowMaps", fam + "__" + t.name, t.body});
}

}  // namespace lockstep::props::raster
