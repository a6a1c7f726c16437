// NFF cones in the optimized rows (issue #22): the double ray-cone routine the
// Embree user geometry and the simd caster share (optimized/ray_cone.h)
// against the long double oracle, every ray-cast row's trace() against the
// reference on random cone scenes, and the rasterizers' tessellation
// (core/viewing.cpp tessellate_cone, cone_segments) against the cone itself.
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "core/camera.h"
#include "io/nff.h"
#include "core/raster.h"
#include "core/ray_trace.h"
#include "core/scene.h"
#include "core/shading.h"
#include "optimized/ray_cast_simd.h"
#include "optimized/ray_cast_embree.h"
#include "optimized/ray_cast_auto.h"
#include "optimized/ray_cast_simd_kernels.h"
#include "optimized/ray_cone.h"
#include "reference/ray_cast.h"
#include "core/cone_quadric.h"

namespace lockstep {
namespace {

using L = long double;

// The oracle: the quadric in long double, roots polished by Newton steps in
// long double (as tests/cones_test.cpp), then NFF's rules: the finite part,
// the visible side (the sign of f' at the root), the nearest in range.
L oracle_nearest(const opt::ConeShape& c, const Vec3& o, const Vec3& d, double tmin, double tmax,
                 bool solid) {
  const ConeQuadric<L> q = cone_quadric<L>(Vec3T<L>(o), Vec3T<L>(d), Vec3T<L>(c.base),
                                                     L(c.r0), Vec3T<L>(c.apex), L(c.r1));
  L t0, t1;
  if (!cone_roots_textbook<L>(q, t0, t1)) return L(kInfinity);
  L best = L(kInfinity);
  for (L t : {t0, t1}) {
    L slope = 0;
    for (int i = 0; i < 4; ++i) {
      const Vec3T<L> w = q.qp + t * q.dp;
      const L r = q.rho + t * q.kappa;
      const L f = dot(w, w) - r * r;
      slope = L(2) * (dot(w, q.dp) - r * q.kappa);
      if (slope == 0) break;
      t -= f / slope;
    }
    if (!(t > tmin && t < tmax) || !cone_in_height(q, t)) continue;
    if (!solid && (c.inside ? !(slope > 0) : !(slope < 0))) continue;
    best = std::min(best, t);
  }
  return best;
}

struct RandomCone {
  opt::ConeShape shape;
  Vec3 target;  // a point on its side
};

RandomCone random_cone(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1), pos(0.1, 1.0), unit(0, 1);
  Vec3 axis;
  do axis = {u(rng), u(rng), u(rng)};
  while (length(axis) < 0.3);
  const Vec3 base{u(rng), u(rng), u(rng)};
  const double r0 = unit(rng) < 0.15 ? 0.0 : pos(rng);
  const double r1 = unit(rng) < 0.3 ? (r0 > 0 ? r0 : 0.5) : pos(rng);  // cylinders too
  RandomCone rc{opt::cone_shape(base, r0, base + axis, r1, unit(rng) < 0.25), {}};
  const double f = unit(rng), a = 2 * M_PI * unit(rng);
  const Vec3 n = normalize(axis);
  const Vec3 x = normalize(cross(n, std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
  const Vec3 y = cross(n, x);
  rc.target = base + f * axis + (r0 + f * (r1 - r0)) * (std::cos(a) * x + std::sin(a) * y);
  return rc;
}

// opt::cone_nearest against the oracle: rays from `scale` away at a point of the
// side, or near it (misses and grazes too). Returns the largest |t - oracle| of
// the rays where both hit, and counts where one hit and the other did not.
struct KernelErrors {
  double worst = 0;
  int both = 0, disagree = 0;
};
KernelErrors kernel_errors(double scale, uint64_t seed, bool solid) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  KernelErrors e;
  for (int i = 0; i < 4000; ++i) {
    const RandomCone rc = random_cone(rng);
    const Vec3 aim = rc.target + 0.05 * Vec3{u(rng), u(rng), u(rng)};
    const Vec3 o = normalize(Vec3{u(rng), u(rng), u(rng)}) * scale + aim;
    const Vec3 d = normalize(aim - o);
    const double t = opt::cone_nearest(rc.shape, o, d, 0.0, kInfinity, solid);
    const L l = oracle_nearest(rc.shape, o, d, 0.0, kInfinity, solid);
    const bool th = t < kInfinity, lh = l < L(kInfinity);
    if (th && lh) {
      ++e.both;
      e.worst = std::max(e.worst, double(std::abs(L(t) - l)));
    } else if (th != lh) {
      ++e.disagree;
    }
  }
  return e;
}

TEST(OptKernel, CarefulDoubleAgreesWithTheOracle) {
  for (const bool solid : {false, true}) {
    const KernelErrors e = kernel_errors(3.0, 11, solid);
    std::printf("solid %d: %d rays hit both, worst |t - oracle| %.3g, %d hit/miss disagreements\n",
                int(solid), e.both, e.worst, e.disagree);
    EXPECT_GT(e.both, 1500);
    // Measured 8.3e-14 for both (seed 11; t ~ 3). The rays are aimed within
    // 0.05 of the side, so some nearly graze it, where the root itself is
    // ill-conditioned (tests/cones_test.cpp leaves those out and holds 1e-13):
    // the bound is 1e-12.
    EXPECT_LT(e.worst, 1e-12);
    // Hit/miss may differ only where a ray grazes the silhouette or an open end
    // within rounding; none are expected among 4000 random rays (measured 0).
    EXPECT_LE(e.disagree, 2);
  }
}

TEST(OptKernel, FarOriginsKeepTheirDigits) {
  const KernelErrors e = kernel_errors(1e5, 12, false);
  std::printf("far: %d rays hit both, worst |t - oracle| %.3g (t ~ 1e5), %d disagreements\n",
              e.both, e.worst, e.disagree);
  EXPECT_GT(e.both, 1500);
  EXPECT_LT(e.worst, 1e-14 * 1e5);
  EXPECT_LE(e.disagree, 2);
}

// The SIMD cone kernel (optimized/ray_cast_simd_kernels.h cone_t) runs
// cone_nearest's arithmetic lane by lane: every answer must be the scalar
// routine's, bit for bit, on either side rule, for rays aimed at the side
// (hits, grazes, misses), from near and far, with ranges that cut roots off,
// and with lanes of empty ranges (the callers' padding); on every Highway
// target compiled in that the machine runs (hwy::SetSupportedTargetsForTest,
// as props/ray_cast/simd_targets.cpp), not only the one dispatch picks.
TEST(OptKernel, SimdConeKernelIsTheCarefulFormBitForBit) {
  for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    std::mt19937_64 rng(21);
    std::uniform_real_distribution<double> u(-1, 1), unit(0, 1);
    constexpr size_t kRays = 64;  // a multiple of the packet
    int hits = 0, compared = 0;
    for (int cone = 0; cone < 400; ++cone) {
      const RandomCone rc = random_cone(rng);
      std::vector<double> ox(kRays), oy(kRays), oz(kRays), dx(kRays), dy(kRays), dz(kRays),
          tmin(kRays), tmax(kRays), t(kRays);
      for (size_t i = 0; i < kRays; ++i) {
        const Vec3 aim = rc.target + (unit(rng) < 0.5 ? 0.05 : 1.0) * Vec3{u(rng), u(rng), u(rng)};
        const double scale = unit(rng) < 0.2 ? 1e4 : 3.0;
        const Vec3 o = normalize(Vec3{u(rng), u(rng), u(rng)}) * scale + aim;
        const Vec3 d = (aim - o) * (0.5 + unit(rng));  // not of unit length
        ox[i] = o.x, oy[i] = o.y, oz[i] = o.z, dx[i] = d.x, dy[i] = d.y, dz[i] = d.z;
        tmin[i] = unit(rng) < 0.2 ? unit(rng) : 0.0;
        tmax[i] = unit(rng) < 0.2 ? unit(rng) * 1.2 : kInfinity;
        if (i % 13 == 12) tmin[i] = tmax[i] = 0;  // padding
      }
      const opt::simd::ConeRays rays{ox.data(), oy.data(), oz.data(),   dx.data(),
                                     dy.data(), dz.data(), tmin.data(), tmax.data()};
      for (const bool solid : {false, true}) {
        opt::simd::cone_t(rc.shape, rays, t.data(), kRays, solid);
        for (size_t i = 0; i < kRays; ++i) {
          const double s = opt::cone_nearest(rc.shape, {ox[i], oy[i], oz[i]}, {dx[i], dy[i], dz[i]},
                                             tmin[i], tmax[i], solid);
          ++compared;
          hits += s < kInfinity;
          EXPECT_EQ(std::bit_cast<uint64_t>(t[i]), std::bit_cast<uint64_t>(s))
              << hwy::TargetName(target) << " cone " << cone << " ray " << i << " solid " << solid
              << ": simd " << t[i] << ", scalar " << s;
        }
      }
    }
    std::printf("%d answers compared on %s, %d hits\n", compared, opt::simd::target_name(), hits);
    EXPECT_EQ(std::string(opt::simd::target_name()), std::string(hwy::TargetName(target)));
    EXPECT_GT(hits, compared / 5);
    hwy::SetSupportedTargetsForTest(0);  // back to the real CPU
  }
}

// A random scene of cones (some inside-visible), spheres and a floor, in NFF.
Scene cone_scene(uint64_t seed, int cones) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-2, 2), pos(0.05, 0.6), unit(0, 1);
  std::string text =
      "v\nfrom 0 1 8\nat 0 0 0\nup 0 1 0\nangle 45\nhither 0.01\nresolution 96 96\nb 0.1 0.1 "
      "0.3\nl 3 5 6\n"
      "f 0.8 0.6 0.4 0.7 0.3 10 0 1\np 4\n-4 -2.5 -4\n-4 -2.5 4\n4 -2.5 4\n4 -2.5 -4\n";
  for (int i = 0; i < cones; ++i) {
    char buf[400];
    const double r0 = pos(rng), r1 = unit(rng) < 0.2 ? 0.0 : pos(rng);
    const double sign = unit(rng) < 0.2 ? -1 : 1;
    std::snprintf(
        buf, sizeof buf,
        "f %.3f %.3f 0.5 0.8 0.2 20 0 1\nc %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
        unit(rng), unit(rng), u(rng), u(rng), u(rng), sign * r0, u(rng), u(rng), u(rng), sign * r1);
    text += buf;
    if (i % 3 == 0) {
      std::snprintf(buf, sizeof buf, "s %.17g %.17g %.17g %.17g\n", u(rng), u(rng), u(rng),
                    pos(rng));
      text += buf;
    }
  }
  return parse_nff(text, "cones-" + std::to_string(seed) + ".nff");
}

// Every ray-cast row's trace() against the reference's, on random rays through
// random cone scenes: the same primitive and t within the rows' refined bound,
// except at near-ties (two surfaces within float's reach of each other along
// the ray) and grazes, which are counted.
TEST(Rows, TraceAgreesWithTheReferenceOnConeScenes) {
  using TraceFn = void (*)(const Scene&, std::span<const Ray>, std::span<Hit>, FrameStats*);
  const std::pair<const char*, TraceFn> rows[] = {
      {"simd", opt::simd::trace}, {"embree", opt::embree::trace}, {"auto", opt::autosel::trace}};
  for (const auto& [name, fn] : rows) {
    size_t rays_total = 0, cone_hits = 0, same = 0, near_tie = 0, other = 0;
    double worst_t = 0;
    for (uint64_t seed = 1; seed <= 6; ++seed) {
      const Scene s = cone_scene(seed, 12);
      std::mt19937_64 rng(100 + seed);
      std::uniform_real_distribution<double> u(-2.5, 2.5);
      std::vector<Ray> rays(3000);
      for (Ray& r : rays) {
        const Vec3 o{u(rng), 1 + u(rng), 8};
        r = Ray{o, normalize(Vec3{u(rng), u(rng), u(rng)} - o), 0.0, kInfinity};
      }
      std::vector<Hit> want(rays.size()), got(rays.size());
      ref::trace(s, rays, want, nullptr);
      fn(s, rays, got, nullptr);
      for (size_t i = 0; i < rays.size(); ++i) {
        ++rays_total;
        const Hit &w = want[i], &g = got[i];
        if (w.hit() && w.prim >= s.cone_first_prim()) ++cone_hits;
        if (w.prim == g.prim) {
          ++same;
          if (w.hit()) worst_t = std::max(worst_t, std::abs(w.t - g.t) / w.t);
          continue;
        }
        // A different answer is a near-tie when both are hits within 1e-5 of t
        // (float kernels decide spheres and triangles), or a graze: the
        // reference's surface seen within 1e-4 of edge-on.
        const bool tie = w.hit() && g.hit() && std::abs(w.t - g.t) <= 1e-5 * w.t;
        bool graze = false;
        if (w.hit()) {
          const Vec3 p = rays[i].o + w.t * rays[i].d;
          graze = std::abs(dot(normalize(rays[i].d), outward_normal(s, w.prim, p))) < 1e-4;
        }
        (tie || graze ? near_tie : other) += 1;
      }
    }
    std::printf(
        "%s: %zu rays, %zu on cones (reference), %zu same primitive (worst relative t %.3g), %zu "
        "near-ties "
        "or grazes, %zu other\n",
        name, rays_total, cone_hits, same, worst_t, near_tie, other);
    EXPECT_GT(cone_hits, rays_total / 10) << "the scenes should put cones in front of many rays";
    EXPECT_EQ(other, 0u) << name;
    EXPECT_LE(near_tie, rays_total / 1000) << name;
    EXPECT_LT(worst_t, 1e-12) << name;
  }
}

// The tessellation: vertices on the cone, smooth normals that are the cone's
// own, a closed band (every edge shared by two facets except along the open
// ends), and a facet count whose bound is within tess_error pixels.
TEST(Tessellation, VerticesNormalsAndTheSilhouetteBound) {
  std::mt19937_64 rng(5);
  for (int i = 0; i < 200; ++i) {
    const RandomCone rc = random_cone(rng);
    const opt::ConeShape& c = rc.shape;
    Scene s;
    add_cone(s, c.base, c.r0, c.apex, c.r1, c.inside, add_material(s, Material{}));
    const int n = 3 + i % 40;
    const ConeMesh m = tessellate_cone(c.base, c.r0, c.apex, c.r1, c.inside, n);
    const size_t want_tris = size_t(n) * ((c.r0 > 0 && c.r1 > 0) ? 2 : 1);
    ASSERT_EQ(m.tri.size(), want_tris);
    for (size_t v = 0; v < m.position.size(); ++v) {
      const Vec3& p = m.position[v];
      // On the surface: its distance from the axis is the radius at its height.
      const Vec3 axis = c.apex - c.base;
      const double h = length(axis);
      const double sh = dot(p - c.base, axis / h);
      const double r = length(p - c.base - sh * axis / h);
      EXPECT_NEAR(r, c.r0 + (c.r1 - c.r0) * sh / h, 1e-12);
      EXPECT_NEAR(length(m.normal[v]), 1.0, 1e-12);
      if (r > 0) {  // away from a pointed tip the normal is the cone's own, on the visible side
        const Vec3 want = c.inside ? -cone_outward_normal(s, 0, p) : cone_outward_normal(s, 0, p);
        EXPECT_NEAR(length(m.normal[v] - want), 0.0, 1e-12);
      }
    }
    // Winding: each facet's normal points to the visible side (as its vertices' normals).
    for (const auto& t : m.tri) {
      const Vec3 fn =
          cross(m.position[t[1]] - m.position[t[0]], m.position[t[2]] - m.position[t[0]]);
      EXPECT_GT(dot(fn, m.normal[t[0]] + m.normal[t[1]] + m.normal[t[2]]), 0);
    }
  }
  // The facet count: the smallest N with R (1 - cos(pi / N)) <= tess_error.
  Camera cam = Camera::from_view(View{}, 512, 512);
  for (const double e : {0.05, 0.25, 1.0, 4.0}) {
    for (const double r : {0.01, 0.1, 1.0}) {
      const int n = cone_segments(r, r, 5.0, 5.0, cam, 0.01, e);
      const double r_px = r / ((5.0 - r) * cam.pitch);
      if (n < 512) {
        EXPECT_LE(r_px * (1 - std::cos(M_PI / n)), e * (1 + 1e-12)) << r << " " << e;
      }
      if (n > 3) {
        EXPECT_GT(r_px * (1 - std::cos(M_PI / (n - 1))), e) << r << " " << e;
      }
    }
  }
}

}  // namespace
}  // namespace lockstep
