// lockstep props/ray_trace: a shadow ray ends at its light (core/ray_trace.h:
// "each light's diffuse + specular term only when a shadow ray from the hit
// reaches that light"; "shadow rays are blocked by anything between the hit
// and the light").
//
// No other test put an occluder on the far side of a point light: a shadow
// ray given an infinite tfar instead of the distance to the light (the embree
// row's `load(r, o, d, 0.0, tfar)` in the one-ray tracer, the shadow stream's
// `load(..., 0.0, dist)` in the frame's wavefront) passed every property.
//
// Each case: a one-sided diffuse square (kd 0.8, white, Ks = T = 0: no
// secondary rays) through a point P with unit normal n, seen from an eye
// straight at P (the centre pixel of an odd frame looks along the view
// direction), a point light L = P + dist l (l.n >= 1/2) and one sphere on the
// shadow ray's line, centred on it:
//   beyond  its near surface a relative 1e-3 .. 2 (log-uniform) of dist past L:
//           the point is lit;
//   at      its near surface a relative 1e-4 .. 1e-3 of dist past L (the
//           surface passes within 1e-3 of the light, on the far side): lit;
//   short   its far surface a relative 1e-3 .. 1e-1 of dist before L (wholly
//           between P and L): the point is in shadow.
// Scenes stay within about 30 units of the origin, dist in [1, 8]: the
// smallest gap, 1e-4 of dist, is over 50 float ulps of any coordinate (Embree
// traverses in float), so the answer is the geometry's, not rounding's.
// The exact answer, written here from core/shading.h's formulas at the exact
// P: lit = ambient + the light's Phong term (kAmbient kd C + kd C Ip (n.l)),
// shadowed = ambient alone (kAmbient kd C); the two differ by at least 0.4.
// Every row of registry/ray_trace_row.h, both entry points (the frame: the centre
// pixel of a 5 x 5 render; the one-pixel tracer, whose ray tree must also
// record the shadow ray as blocked or not), within 1e-5 per channel (the
// frame's output is float; measured: largest error 2.9e-8 over the 480
// answers of 40 cases per placement).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "core/ray_trace.h"
#include "core/scene.h"
#include "core/shading.h"
#include "registry/ray_trace_row.h"

namespace lockstep {
namespace {

enum class Where { kBeyond, kAt, kShort };
const char* where_name(Where w) {
  return w == Where::kBeyond ? "beyond" : w == Where::kAt ? "at" : "short";
}

struct Case {
  Where where;
  Vec3 p, n, light, eye, center;
  double dist = 0, radius = 0, gap = 0;  // gap: relative, of dist
  Scene scene;
  std::string text;
};

Vec3 unit_in(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  for (;;) {
    const Vec3 v{g(rng), g(rng), g(rng)};
    if (length(v) > 1e-3) return normalize(v);
  }
}

// A unit vector within 60 degrees of n.
Vec3 towards(std::mt19937_64& rng, const Vec3& n) {
  for (;;) {
    const Vec3 v = unit_in(rng);
    if (dot(v, n) >= 0.5) return v;
  }
}

// Does the segment a-b come within r of c?
bool segment_near(const Vec3& a, const Vec3& b, const Vec3& c, double r) {
  const Vec3 d = b - a;
  const double t = std::clamp(dot(c - a, d) / dot(d, d), 0.0, 1.0);
  return length(a + t * d - c) <= r;
}

Case make_case(std::mt19937_64& rng, Where where) {
  std::uniform_real_distribution<double> u(0, 1);
  auto in = [&](double lo, double hi) { return lo + (hi - lo) * u(rng); };
  auto log_in = [&](double lo, double hi) { return std::exp(in(std::log(lo), std::log(hi))); };
  Case c;
  c.where = where;
  c.p = {in(-4, 4), in(-4, 4), in(-4, 4)};
  c.n = unit_in(rng);
  c.dist = in(1, 8);
  const Vec3 l = towards(rng, c.n);
  c.light = c.p + c.dist * l;
  c.radius = c.dist * in(0.05, 0.3);
  double along = 0;  // the sphere's centre, as a distance from P along l
  if (where == Where::kBeyond) {
    c.gap = log_in(1e-3, 2);
    along = c.dist * (1 + c.gap) + c.radius;
  } else if (where == Where::kAt) {
    c.gap = log_in(1e-4, 1e-3);
    along = c.dist * (1 + c.gap) + c.radius;
  } else {
    c.gap = log_in(1e-3, 1e-1);
    along = c.dist * (1 - c.gap) - c.radius;
  }
  c.center = c.p + along * l;
  // The eye: within 60 degrees of n, 2..10 away, its view of P clear of the sphere.
  do {
    c.eye = c.p + in(2, 10) * towards(rng, c.n);
  } while (segment_near(c.eye, c.p, c.center, 1.05 * c.radius));

  Scene& s = c.scene;
  s.view.from = c.eye;
  s.view.at = c.p;
  s.view.up =
      std::abs(dot(normalize(c.p - c.eye), Vec3{0, 0, 1})) < 0.9 ? Vec3{0, 0, 1} : Vec3{1, 0, 0};
  s.view.angle = 30;
  s.view.hither = 1e-3;
  s.view.xres = s.view.yres = 5;
  s.background = {0, 0, 0};
  Light light;
  light.position = c.light;
  s.lights.push_back(light);
  Material floor;
  floor.color = {1, 1, 1};
  floor.kd = 0.8;
  floor.ks = 0;
  const uint32_t mf = add_material(s, floor);
  // The square's corners counter-clockwise about n (NFF's front side).
  const Vec3 a = normalize(cross(c.n, std::abs(c.n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
  const Vec3 b = cross(c.n, a);
  const double h = 4 * c.dist;
  const Vec3 quad[4] = {c.p - h * a - h * b, c.p + h * a - h * b, c.p + h * a + h * b,
                        c.p - h * a + h * b};
  add_polygon(s, quad, {}, mf);
  Material ball;
  ball.color = {0.3, 0.6, 0.9};
  ball.kd = 0.7;
  add_sphere(s, c.center, c.radius, add_material(s, ball));

  char buf[640];
  std::snprintf(
      buf, sizeof buf,
      "occluder %s the light (relative gap %.6g of dist %.17g): P (%a, %a, %a), n (%a, %a, %a), "
      "light (%a, %a, %a), eye (%a, %a, %a), sphere centre (%a, %a, %a) radius %a",
      where_name(where), c.gap, c.dist, c.p.x, c.p.y, c.p.z, c.n.x, c.n.y, c.n.z, c.light.x,
      c.light.y, c.light.z, c.eye.x, c.eye.y, c.eye.z, c.center.x, c.center.y, c.center.z,
      c.radius);
  c.text = buf;
  return c;
}

// The exact answer at P: ambient, plus the light's term when lit.
Vec3 expected(const Case& c) {
  const Material& m = c.scene.materials[0];
  Vec3 col = kAmbient * (m.kd * m.color);
  if (c.where != Where::kShort) {
    const LightSample ls = light_at(c.scene, c.scene.lights[0], c.p);
    col += phong_light(m, c.n, normalize(c.eye - c.p), ls);
  }
  return col;
}

double max_diff(const Vec3& a, const Vec3& b) {
  return std::max({std::abs(a.x - b.x), std::abs(a.y - b.y), std::abs(a.z - b.z)});
}

std::string str(const Vec3& v) {
  char buf[120];
  std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", v.x, v.y, v.z);
  return buf;
}

constexpr double kTol = 1e-5;
constexpr int kCasesPerKind = 40;

TEST(LightDistance, OccluderBeyondAtAndShortOfThePointLight) {
  const uint64_t seed = 0x5eed1a7e0ffULL;
  std::printf("[ lockstep ] LightDistance: seed %llu, %d cases per placement\n",
              (unsigned long long)seed, kCasesPerKind);
  std::mt19937_64 rng(seed);
  const KernelRow<TracerFns>& row = ray_trace_row();
  int checked = 0;
  double worst = 0;
  for (int q = 0; q < kCasesPerKind; ++q)
    for (const Where where : {Where::kBeyond, Where::kAt, Where::kShort}) {
      const Case c = make_case(rng, where);
      const Vec3 want = expected(c);
      const Vec3 dark = kAmbient * (c.scene.materials[0].kd * c.scene.materials[0].color);
      if (where != Where::kShort) {
        ASSERT_GE(max_diff(want, dark), 0.39) << c.text;  // lit and dark far apart
      }
      for (const auto& impl : row.impls) {
        const std::string who = std::string(impl.name);
        FrameOptions o;
        o.width = o.height = 5;
        o.threads = 1;
        const Image frame = impl.fn.render(c.scene, o, nullptr);
        const float* px = frame.pixel(2, 2);
        const Vec3 got_frame{px[0], px[1], px[2]};
        RayTree tree;
        const Vec3 got_pixel = impl.fn.pixel(c.scene, TraceSettings{}, 5, 5, 2, 2, &tree);
        for (const auto& [entry, got] :
             {std::pair{"trace_render", got_frame}, std::pair{"trace_pixel", got_pixel}}) {
          const double err = max_diff(got, want);
          worst = std::max(worst, err);
          EXPECT_LE(err, kTol) << "seed " << seed << " case " << q << ": " << who << " " << entry
                               << " "
                               << (where == Where::kShort ? "lights a point it must shadow"
                                                          : "shadows a point it must light")
                               << ": got " << str(got) << ", exact " << str(want)
                               << " (ambient alone " << str(dark) << "); error " << err << " > "
                               << kTol << "\n  " << c.text;
          ++checked;
        }
        // The ray tree says why: its one shadow ray, blocked exactly when short.
        int shadow_rays = 0;
        for (const RayNode& node : tree.nodes)
          if (node.kind == RayKind::kShadow) {
            ++shadow_rays;
            EXPECT_EQ(node.blocked, where == Where::kShort)
                << "seed " << seed << " case " << q << ": " << who << " trace_pixel's shadow ray "
                << (node.blocked ? "blocked" : "not blocked") << " (tmax " << node.tmax
                << ", blocker t " << node.hit.t << ")\n  " << c.text;
          }
        EXPECT_EQ(shadow_rays, 1) << who << ": " << c.text;
      }
    }
  std::printf("[ lockstep ] LightDistance: %d answers, largest error %.3g (bound %g)\n", checked,
              worst, kTol);
}

}  // namespace
}  // namespace lockstep
