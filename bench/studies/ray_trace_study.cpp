// lockstep_ray_trace_study: the ray-tracing family's failure map for
// BENCHMARKS.md (issue #22): shadow acne and light leaking, the fraction of
// wrong shadow-ray answers, against the self-intersection offset and the
// scene's distance from the origin and the eye's distance from the scene
// (issue #30). It prints CSV on stdout and checks the
// claims BENCHMARKS.md makes of it (exit 1 and a message on stderr when one
// does not hold), so the ctest ray_trace_study.quick keeps them true;
// bench/scripts/ray_trace_chart.py draws the chart and writes the table.
//
// The scene (local coordinates, turned so that no surface is axis-aligned,
// then moved by D (1,1,1)/sqrt(3), so that every coordinate grows with D): a
// lit ground square z = 0 (facing up, seen by an eye 3 above it), a ball of
// radius 0.3 above it, and a thin square occluder at height h = 0.01 facing
// down (one-sided, NFF: invisible to the eye, but it blocks shadow rays from
// either side, core/ray_trace.h), under a point light low at one side so that
// both shadows are in view. Each pixel is one sample: its primary ray
// (core/camera.h, the ray both implementations trace) meets the ground or the
// ball at a point p, and the shadow-ray answer is read off the frame at depth
// 1: lit when the pixel is bit for bit the frame rendered with shadows=none
// (the same operations on the same values), shadowed otherwise.
//
// The oracle, in long double, in local coordinates (the scene's doubles are
// the local scene to within their rounding, below 1e-8 at D = 1e7): p is the
// exact hit of that double primary ray for embree (double-refined hits), and
// for the reference the point it shades: its own textbook hit moved onto the
// surface (core/ray_trace.h surface_point); where its primary ray found
// another surface than the exact one (the textbook sphere's cancellation from
// 1e7 away) the pixel is counted as coverage, not as a shadow answer. On the ground, p is in shadow
// when the segment p -> light meets the ball (distance from its centre below r) or crosses the
// occluder's plane inside the square. On the ball, a point whose normal faces the light (n.l > m)
// is lit (the light is above everything: no other surface can shadow it); the dark side has no
// shadow ray and is not a sample. A sample is left out (ambiguous, never counted) when the primary
// ray passes within m = 1e-4 of the ball's silhouette, n.l is within m of 0, or the segment passes
// within m of the ball's surface or of the square's edges: the hit points of both implementations
// are double accurate (embree refines its t in double, optimized/refine.h), so nothing further than
// m from a boundary can be decided either way by rounding. Every counted answer then is right, acne
// (a lit point reported shadowed: the ray met its own surface, or any other wrong "shadowed") or a
// leak (a shadowed point reported lit: the offset pushed the ray's origin past the occluder).
//
// Rows: impl (reference: double, world coordinates; embree: float, in a frame
// at the eye moved to the nearest primitive, optimized/ray_trace_embree.cpp) x offset (fixed eps =
// 1e-14 .. 1e-1, and robust: the hit's error bound, core/ray_trace.h
// robust_offset) x D = 1 .. 1e7, with the eye 3 above the ground; then, with
// the eye 1e1 .. 1e7 away (the view angle narrowed to frame the same), the
// robust offset, eps 1e-6 and 1e-4. Claims (full and quick):
//   * the robust offset, in each implementation (embree: its default;
//     reference: robust=1): zero acne and zero leaks at every D and every
//     eye distance;
//   * a mid-range eps (1e-4) is right on every sample at every D and eye
//     distance in both implementations (the oracle checked against both);
//   * the reference's default eps (1e-6) is right at every D and eye distance;
//   * embree's primary rays find the exact surface (no coverage error);
//   * some fixed eps fails at every D, in each implementation (the map has a
//     failure to show), and in double a fixed eps that is right at D = 1 fails
//     further out;
//   * --mutant: the robust row is replaced by a fixed offset of 1e-300 (no
//     offset at all: 0 ulps) and the first claim must fail (ctest
//     ray_trace_study.mutant, WILL_FAIL): the check can catch a bad offset.
//
// --scene D N writes the study's scene at distance D as NFF (N x N) on stdout
// and exits: the corpus case rt-acne-1e5 (corpus/scenes/acne-1e5.nff) is it.
//
// usage: lockstep_ray_trace_study [--quick] [--mutant] | --scene D N
#include "bench/studies/study.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "core/camera.h"
#include "io/nff.h"
#include "core/ray_trace.h"
#include "core/scene.h"
#include "optimized/ray_trace_embree.h"
#include "reference/ray_cast.h"
#include "reference/ray_trace.h"

namespace lockstep {
namespace {

using LD = long double;

constexpr double kHeight = 0.01;  // the thin occluder above the ground
constexpr double kMargin = 1e-4;  // samples this close to a boundary are not counted

struct Options {
  bool quick = false;
  bool mutant = false;
  study::Claims claims{"lockstep_ray_trace_study"};
};

std::string num(double x) {
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

// The scene's frame: local coordinates turned by a fixed rotation (about
// (1, 2, 3) by 0.7 rad, so that no surface is axis-aligned: an axis-aligned
// plane hides double's rounding, the hit's coordinate across it being exact)
// and moved by d (1, 1, 1) / sqrt(3).
struct Frame {
  LD r[3][3];
  LD t;
  explicit Frame(double d) : t(LD(d) / std::sqrt(3.0L)) {
    const LD n = std::sqrt(14.0L), ax = 1 / n, ay = 2 / n, az = 3 / n, a = 0.7L;
    const LD c = std::cos(a), s = std::sin(a), k = 1 - c;
    const LD m[3][3] = {{c + ax * ax * k, ax * ay * k - az * s, ax * az * k + ay * s},
                        {ay * ax * k + az * s, c + ay * ay * k, ay * az * k - ax * s},
                        {az * ax * k - ay * s, az * ay * k + ax * s, c + az * az * k}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r[i][j] = m[i][j];
  }
  // World (rounded to double, as a file holds it) of a local point.
  Vec3 world(LD x, LD y, LD z) const {
    Vec3 w;
    for (int i = 0; i < 3; ++i) w[i] = double(t + r[i][0] * x + r[i][1] * y + r[i][2] * z);
    return w;
  }
  // Local of a world point or (direction: no translation) vector, in long double.
  void local(const Vec3& w, bool point, LD out[3]) const {
    const LD v[3] = {w.x - (point ? t : 0), w.y - (point ? t : 0), w.z - (point ? t : 0)};
    for (int i = 0; i < 3; ++i) out[i] = r[0][i] * v[0] + r[1][i] * v[1] + r[2][i] * v[2];
  }
};

// The local scene (see the header).
constexpr LD kEye[3] = {0, 0, 3}, kLight[3] = {-3, -2, 3}, kBall[3] = {0.2L, 0.3L, 0.5L};
constexpr LD kRadius = 0.3L;
constexpr LD kOcc[4] = {-0.9L, -0.1L, -0.9L, -0.1L};  // x0, x1, y0, y1 at z = kHeight

// The scene at distance d from the origin, as NFF text (parsed by the NFF
// reader the CLI uses, so the implementations see what a file would give).
std::string scene_text(const Frame& fr, int size, double eye = 3) {
  auto xyz = [&](LD x, LD y, LD z) {
    const Vec3 w = fr.world(x, y, z);
    return num(w.x) + " " + num(w.y) + " " + num(w.z);
  };
  auto p = [&](LD x, LD y, LD z) { return xyz(x, y, z) + "\n"; };
  Vec3 up;
  for (int i = 0; i < 3; ++i) up[i] = double(fr.r[i][1]);
  std::string t;
  // The eye `eye` above the ground's centre, the view angle narrowed so that
  // the frame shows what it shows from 3 (a telephoto view from far away).
  const LD angle = 2 * std::atan(std::tan(LD(M_PI) / 8) * kEye[2] / LD(eye)) * 180 / LD(M_PI);
  t += "v\nfrom " + p(0, 0, eye) + "at " + p(0, 0, 0) + "up " + num(up.x) + " " + num(up.y) + " " +
       num(up.z) + "\nangle " + num(double(angle)) + "\nhither 0.001\n";
  t += "resolution " + std::to_string(size) + " " + std::to_string(size) + "\n";
  t += "b 0 0 0\nl " + p(kLight[0], kLight[1], kLight[2]);
  t += "f 0.8 0.8 0.8 1 0 1 0 1\n";
  // The ground, counter-clockwise from above: facing up.
  t += "p 4\n" + p(-2, -2, 0) + p(2, -2, 0) + p(2, 2, 0) + p(-2, 2, 0);
  // The occluder, clockwise from above: facing down, culled for the eye.
  t += "p 4\n" + p(kOcc[0], kOcc[2], kHeight) + p(kOcc[0], kOcc[3], kHeight) +
       p(kOcc[1], kOcc[3], kHeight) + p(kOcc[1], kOcc[2], kHeight);
  t += "s " + xyz(kBall[0], kBall[1], kBall[2]) + " " + num(double(kRadius)) + "\n";
  return t;
}

LD dot3(const LD* a, const LD* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// kBallLit: a point on the ball's lit side (n.l > 0), which no other surface
// shadows (the light is above everything): a sample for acne on a curved
// surface, where the rounding of the hit falls inside the ball half the time.
// kCoverage: the row's primary ray found another surface than the exact one
// (the textbook sphere test's cancellation seen from far away, ray casting's
// documented failure): not a shadow answer, counted apart.
enum Truth : int8_t { kAmbiguous, kLit, kShadow, kOff, kBallLit, kCoverage };

// Which surface a primary ray meets first, exactly (local coordinates).
enum class Surface : int8_t { kNone, kBall, kGround, kUnsure };

// The first surface the primary ray (o, dir) meets (the ball, the ground, or
// none), kUnsure within m of the ball's silhouette or the ground's edge; p:
// the exact hit.
Surface first_surface(const LD* o, const LD* dir, LD* p) {
  // The distance of the line from the ball's centre.
  const LD oc[3] = {kBall[0] - o[0], kBall[1] - o[1], kBall[2] - o[2]};
  const LD tc = dot3(oc, dir) / dot3(dir, dir);
  const LD near[3] = {oc[0] - tc * dir[0], oc[1] - tc * dir[1], oc[2] - tc * dir[2]};
  const LD miss = std::sqrt(dot3(near, near));
  if (miss < kRadius - kMargin) {
    const LD th = tc - std::sqrt(kRadius * kRadius - miss * miss) / std::sqrt(dot3(dir, dir));
    for (int a = 0; a < 3; ++a) p[a] = o[a] + th * dir[a];
    return Surface::kBall;
  }
  if (miss < kRadius + kMargin) return Surface::kUnsure;
  if (!(dir[2] < 0)) return Surface::kNone;
  const LD t = -o[2] / dir[2];
  p[0] = o[0] + t * dir[0], p[1] = o[1] + t * dir[1], p[2] = 0;
  if (std::fabs(std::fabs(p[0]) - 2) < kMargin || std::fabs(std::fabs(p[1]) - 2) < kMargin)
    return Surface::kUnsure;
  if (std::fabs(p[0]) > 2 || std::fabs(p[1]) > 2) return Surface::kNone;
  return Surface::kGround;
}

// Whether the light reaches the point p of surface s (local coordinates).
Truth judge(Surface s, const LD* p) {
  if (s == Surface::kBall) {
    // The cosine of the light at p; the terminator band |n.l| < m is left
    // out, the dark side has no shadow ray to test.
    const LD n[3] = {(p[0] - kBall[0]) / kRadius, (p[1] - kBall[1]) / kRadius,
                     (p[2] - kBall[2]) / kRadius};
    const LD l[3] = {kLight[0] - p[0], kLight[1] - p[1], kLight[2] - p[2]};
    const LD cosine = dot3(n, l) / std::sqrt(dot3(l, l));
    return cosine > kMargin ? kBallLit : cosine < -kMargin ? kOff : kAmbiguous;
  }
  if (s != Surface::kGround) return kOff;
  const LD pl[3] = {kLight[0] - p[0], kLight[1] - p[1], kLight[2] - p[2]};
  // The ball: the nearest point of the segment to the centre.
  const LD pc[3] = {kBall[0] - p[0], kBall[1] - p[1], kBall[2] - p[2]};
  LD u = dot3(pc, pl) / dot3(pl, pl);
  u = u < 0 ? 0 : u > 1 ? 1 : u;
  const LD q[3] = {pc[0] - u * pl[0], pc[1] - u * pl[1], pc[2] - u * pl[2]};
  const LD dist = std::sqrt(dot3(q, q));
  if (std::fabs(dist - kRadius) < kMargin) return kAmbiguous;
  // The occluder: where the segment crosses its plane, against the square.
  const LD w = (kHeight - p[2]) / pl[2];
  const LD cx = p[0] + w * pl[0], cy = p[1] + w * pl[1];
  const LD edge = std::min({std::fabs(cx - kOcc[0]), std::fabs(cx - kOcc[1]),
                            std::fabs(cy - kOcc[2]), std::fabs(cy - kOcc[3])});
  if (edge < kMargin) return kAmbiguous;
  const bool shadow =
      dist < kRadius || (cx > kOcc[0] && cx < kOcc[1] && cy > kOcc[2] && cy < kOcc[3]);
  return shadow ? kShadow : kLit;
}

// The exact answer for pixel (i, j) (see the header), in local coordinates:
// the scene's doubles differ from the local scene by rounding (below 1e-8 at
// D = 1e7), far below the margin. For a row whose primary hits are double
// accurate (embree refines its t in double, optimized/refine.h), the answer
// at the exact hit. For the reference (row_hit given: its own nearest hit,
// the textbook sphere test), the answer at the point it shades (its hit moved
// onto the surface, core/ray_trace.h surface_point), or kCoverage where it
// found another surface than the exact one.
Truth oracle(const Frame& fr, const Scene& sc, const Camera& cam, int i, int j,
             const Hit* row_hit) {
  const Ray r = cam.primary(i, j);
  LD o[3], dir[3], p[3];
  fr.local(r.o, true, o);
  fr.local(r.d, false, dir);
  const Surface s = first_surface(o, dir, p);
  if (s == Surface::kUnsure) return kAmbiguous;
  if (!row_hit) return judge(s, p);
  // prim 0 is the ball, 1 the ground (the occluder, 2, is culled for the eye).
  const Surface seen = !row_hit->hit()      ? Surface::kNone
                       : row_hit->prim == 0 ? Surface::kBall
                       : row_hit->prim == 1 ? Surface::kGround
                                            : Surface::kUnsure;
  if (seen != s) return kCoverage;
  if (s == Surface::kNone) return kOff;
  fr.local(surface_point(sc, row_hit->prim, r, row_hit->t).p, true, p);
  return judge(s, p);
}

struct Count {
  int samples = 0, acne = 0, leak = 0, shadowed = 0;
  int coverage = 0;             // primary rays that found another surface (not samples)
  int ball = 0, ball_acne = 0;  // of which on the ball
  int wrong() const { return acne + leak; }
};

using RenderFn = Image (*)(const Scene&, const FrameOptions&, FrameStats*);

Image frame(RenderFn fn, const Scene& sc, int size, const Params& p) {
  FrameOptions o;
  o.width = o.height = size;
  o.threads = 1;
  o.params = p;
  Params q = p;
  q.set("depth", "1");
  o.params = q;
  return fn(sc, o, nullptr);
}

Count classify(const Scene& sc, const Image& lit, const Image& shad,
               const std::vector<Truth>& truth, int size) {
  Count c;
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const Truth t = truth[size_t(j) * size + i];
      c.coverage += t == kCoverage;
      if (t != kLit && t != kShadow && t != kBallLit) continue;
      // Lit, the frame computes exactly what it does with shadows=none (the
      // same operations on the same values): any difference is a shadow.
      const float* a = lit.pixel(i, j);
      const float* b = shad.pixel(i, j);
      const bool dark = a[0] != b[0] || a[1] != b[1] || a[2] != b[2];
      ++c.samples;
      c.shadowed += t == kShadow;
      c.ball += t == kBallLit;
      if (dark && t != kShadow) ++c.acne;
      if (dark && t == kBallLit) ++c.ball_acne;
      if (!dark && t == kShadow) ++c.leak;
    }
  (void)sc;
  return c;
}

int run(Options& o) {
  const int size = o.quick ? 48 : 160;
  std::vector<double> distances = {1, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7};
  std::vector<double> eyes = {3, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7};
  if (o.quick) distances = {1, 1e3, 1e5, 1e7}, eyes = {3, 1e3, 1e5, 1e7};
  std::vector<double> eps;
  for (int e = -14; e <= -1; ++e) eps.push_back(std::pow(10.0, e));
  if (o.quick) eps = {1e-14, 1e-12, 1e-8, 1e-4, 1e-1};
  // From further away (eye > 3), only the offsets a user gets: robust, the
  // reference's default eps and the oracle's check eps.
  const std::vector<double> far_eps = {kDefaultEps, 1e-4};
  struct ImplRow {
    const char* name;
    RenderFn fn;
    bool own_hits;  // the oracle judges the row's own primary hits (see oracle())
  };
  const ImplRow impls[] = {{"reference", ref::trace_render, true},
                           {"embree", opt::embree::trace_render, false}};

  // The reference's fixed eps: right at D = 1, wrong at some larger D.
  std::map<double, bool> near_ok, far_bad;
  std::printf(
      "impl,offset,eps,distance,eye,samples,shadowed,acne,leak,wrong_fraction,ball_samples,ball_"
      "acne,coverage\n");
  for (const double eye : eyes)
    for (const double d : distances) {
      const Frame fr(d);
      const Scene sc = parse_nff(scene_text(fr, size, eye), "acne-" + num(d));
      const Camera cam = Camera::from_view(sc.view, size, size);
      const std::string where = " at D = " + num(d) + ", eye " + num(eye);
      for (const ImplRow& im : impls) {
        std::vector<Truth> truth(size_t(size) * size);
        for (int j = 0; j < size; ++j)
          for (int i = 0; i < size; ++i) {
            Hit own;
            if (im.own_hits)
              own = ref::nearest_hit(sc, cam.primary(i, j), ref::SphereSides::kSolid);
            truth[size_t(j) * size + i] = oracle(fr, sc, cam, i, j, im.own_hits ? &own : nullptr);
          }
        Params none;
        none.set("shadows", "none");
        const Image lit = frame(im.fn, sc, size, none);
        bool fixed_fails = false;
        auto emit = [&](const char* offset, double e, const Count& c) {
          std::printf("%s,%s,%s,%s,%s,%d,%d,%d,%d,%.6g,%d,%d,%d\n", im.name, offset,
                      e > 0 ? num(e).c_str() : "", num(d).c_str(), num(eye).c_str(), c.samples,
                      c.shadowed, c.acne, c.leak, c.samples ? double(c.wrong()) / c.samples : 0.0,
                      c.ball, c.ball_acne, c.coverage);
        };
        for (const double e : eye == 3 ? eps : far_eps) {
          Params p;
          p.set("eps", num(e));
          const Count c = classify(sc, lit, frame(im.fn, sc, size, p), truth, size);
          emit("fixed", e, c);
          if (eye == 3 && std::strcmp(im.name, "reference") == 0) {
            if (d == 1)
              near_ok[e] = c.wrong() == 0;
            else if (c.wrong() > 0)
              far_bad[e] = true;
          }
          fixed_fails = fixed_fails || c.wrong() > 0;
          // The oracle's own check: a mid-range offset, above every rounding and
          // far below the gap, agrees with it everywhere in both implementations
          // (a wrong oracle would show here, not only in the failing rows).
          if (e == 1e-4)
            o.claims.check(c.wrong() == 0, std::string(im.name) +
                                               " with eps = 1e-4 disagrees with the oracle" +
                                               where + ": " + std::to_string(c.acne) + " acne, " +
                                               std::to_string(c.leak) + " leaks");
          // The reference's default, from its hit moved onto the surface: no
          // acne from far away (the textbook hit alone, 1e-6 off a sphere
          // seen from 1e5, gave it on 2.8% of a ball).
          if (e == kDefaultEps && std::strcmp(im.name, "reference") == 0)
            o.claims.check(c.wrong() == 0, "the reference's default eps 1e-6" + where + ": " +
                                               std::to_string(c.acne) + " acne, " +
                                               std::to_string(c.leak) + " leaks");
          o.claims.check(c.samples > size * size / 2 && c.shadowed > c.samples / 20,
                         std::string(im.name) + where + ": too few samples or shadowed samples");
        }
        if (eye == 3)
          o.claims.check(fixed_fails,
                         std::string(im.name) + ": no fixed eps fails at D = " + num(d));
        Params p;
        if (o.mutant)
          p.set("eps", "1e-300");  // a deliberately bad "robust" offset: none at all
        else
          p.set("robust", "1");
        const Count c = classify(sc, lit, frame(im.fn, sc, size, p), truth, size);
        emit("robust", 0, c);
        // Both implementations: the robust offset, from the hit's error bounds
        // in each one's arithmetic and frame (core/ray_trace.h), needs no
        // tuning at any D or eye distance.
        o.claims.check(c.wrong() == 0, std::string(im.name) +
                                           "'s robust offset: " + std::to_string(c.acne) +
                                           " acne, " + std::to_string(c.leak) + " leaks of " +
                                           std::to_string(c.samples) + where);
        // Only the reference's textbook sphere test loses primary rays from
        // far away; embree's are double-refined.
        if (!im.own_hits)
          o.claims.check(c.coverage == 0, std::string(im.name) + ": coverage errors" + where);
      }
      std::fflush(stdout);
    }
  bool scale_bites = false;
  for (const auto& [e, ok] : near_ok) scale_bites = scale_bites || (ok && far_bad[e]);
  o.claims.check(scale_bites,
                 "no fixed eps of the reference (double) is right at D = 1 and wrong further out");
  return o.claims.exit_code();
}

}  // namespace
}  // namespace lockstep

int main(int argc, char** argv) {
  lockstep::Options o;
  for (int a = 1; a < argc; ++a) {
    if (std::strcmp(argv[a], "--quick") == 0)
      o.quick = true;
    else if (std::strcmp(argv[a], "--mutant") == 0)
      o.mutant = true;
    else if (std::strcmp(argv[a], "--scene") == 0 && a + 2 < argc) {
      const double d = std::atof(argv[a + 1]);
      const int n = std::atoi(argv[a + 2]);
      if (!(d > 0) || n < 1 || n > 16384) {
        std::fprintf(stderr, "lockstep_ray_trace_study: --scene D N: D > 0, N in 1..16384\n");
        return 2;
      }
      std::fputs(lockstep::scene_text(lockstep::Frame(d), n).c_str(), stdout);
      return 0;
    } else {
      std::fprintf(stderr, "usage: lockstep_ray_trace_study [--quick] [--mutant] | --scene D N\n");
      return 2;
    }
  }
  try {
    return lockstep::run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lockstep_ray_trace_study: %s\n", e.what());
    return 2;
  }
}
