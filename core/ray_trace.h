// lockstep core: the ray-tracing contract (Whitted 1980).
//
// Every ray-tracing implementation (ref: reference/ray_trace.cpp; opt::embree:
// optimized/ray_trace_embree.cpp) provides the two functions of the types at
// the end, and pairs/ray_trace.cpp lists them. The scene is the NFF scene of
// ray casting (core/scene.h); NFF's material `f r g b Kd Ks Shine T ior` now
// drives the secondary rays:
//
//   colour(ray) = local + kr colour(reflected) + kt colour(refracted)
//   local       = Phong (core/shading.h) with the ambient term, and each
//                 light's diffuse + specular term only when a shadow ray from
//                 the hit reaches that light (shadows=rays; shadows=none: every
//                 light, as ray casting does)
//   kr = min(1, Ks), kt = min(1, T): a ray never amplifies (NFF allows Ks or
//   T > 1; no SPD scene uses it). Colours are not filtered by the surface's
//   colour (Whitted's scalar coefficients).
//
// Geometry the rays see:
//   * spheres are solids: a ray meets the first root in range whatever side
//     it is on (a refracted ray inside a glass ball leaves through the far
//     wall); ray casting's NFF sidedness for spheres applies to rays from
//     outside only, which is where the eye is in every SPD scene;
//   * polygons keep NFF's sidedness: one-sided unless they transmit;
//   * shadow rays are blocked by anything between the hit and the light, both
//     sides of every surface, transparent or not (hard shadows, no caustics).
//
// Refraction: entering when d.n < 0 for the outward geometric normal n (a
// sphere's p - c, a polygon's plane normal), leaving otherwise; the outside
// is air (index 1), so eta = 1/ior entering and ior leaving (no nested media).
// Snell's law in Heckbert's vector form (refract() below); when it has no
// solution the ray is totally internally reflected: no refracted ray, and the
// ray-tree node says so (tir). Its weight kt is then lost: Whitted's model has
// fixed coefficients, no Fresnel terms, so the reflected ray keeps its kr.
//
// Depth: the primary ray is depth 1; a ray at depth k spawns reflected and
// refracted rays only when k < max_depth (max_depth 1: primary rays and their
// shadow rays only), and only when the child's accumulated weight (the
// product of kr and kt down the path) is at least `cutoff` (Hall and Greenberg
// 1983's adaptive tree-depth control; default 1/256: a ray that can change no
// 8-bit level of a pixel whose radiance is at most 1 is not traced).
//
// Self-intersection: a secondary or shadow ray starts from the hit point
// moved off the surface along the geometric normal, to the side the new ray
// leaves on, and then counts hits from t = 0:
//   fixed   by eps (world units), the textbook way;
//   robust  by Waechter and Binder's integer-ulp offset (offset_robust below),
//           counted in the ulps of the arithmetic the intersector works in
//           (embree: float, in the eye frame; the reference: double, world).
// The default is each implementation's own: the reference fixed with eps =
// 1e-6, embree robust.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/family.h"
#include "core/image.h"
#include "core/math.h"
#include "core/scene.h"

namespace lockstep {

enum class Offset : uint8_t { kOwn, kFixed, kRobust };

struct TraceSettings {
  int max_depth = 5;
  double cutoff = 1.0 / 256;
  bool shadows = true;
  Offset offset = Offset::kOwn;
  double eps = 1e-6;  // kFixed (and the reference's own)
};

inline constexpr double kDefaultEps = 1e-6;

// The settings of FrameOptions::params (depth=N, shadows=rays|none, eps=E,
// robust=1, cutoff=W); throws InputError(source, 0, ...) naming a bad one.
TraceSettings trace_settings(const Params& params, const std::string& source = "settings");
std::vector<ParamSpec> trace_params();

// ---------------------------------------------------------------- the ray tree
enum class RayKind : uint8_t { kPrimary, kShadow, kReflect, kRefract };
const char* ray_kind_name(RayKind k);

// Rays traced, by kind (FrameStats::counts: the benchmarks' primary_per_s ...).
struct RayCounts {
  uint64_t n[4] = {};
  void add(RayKind k) { ++n[int(k)]; }
  uint64_t total() const { return n[0] + n[1] + n[2] + n[3]; }
  RayCounts& operator+=(const RayCounts& o) {
    for (int k = 0; k < 4; ++k) n[k] += o.n[k];
    return *this;
  }
  // items = every ray; counts = each kind by name.
  void report(FrameStats* stats) const {
    if (!stats) return;
    stats->items = total();
    stats->counts = {{"primary", n[0]}, {"shadow", n[1]}, {"reflect", n[2]}, {"refract", n[3]}};
  }
};

// One ray of a pixel's tree, in the order they were traced (parents first).
struct RayNode {
  RayKind kind = RayKind::kPrimary;
  int parent = -1;          // index in RayTree::nodes; -1 for the primary ray
  int depth = 1;            // primary 1; a shadow ray has its parent's depth
  Vec3 origin, direction;   // world space; direction unit length
  double tmax = kInfinity;  // shadow rays: the distance to the light
  Hit hit;                  // nearest hit (shadow rays: the first blocker found, if any)
  double weight =
      1;       // accumulated kr / kt product: what this ray's colour is multiplied by in the pixel
  Vec3 color;  // what the ray returns (shadow: the light's diffuse + specular term, 0 when blocked)
  uint32_t light = 0;     // shadow rays: which light
  bool blocked = false;   // shadow rays: something lies between the hit and the light
  bool tir = false;       // refracted ray that total internal reflection turned away: not traced
  bool entering = false;  // refracted rays: into the surface's medium
};

struct RayTree {
  std::vector<RayNode> nodes;
};

// The node a refracted ray leaves in the tree when total internal reflection
// turns it away (not traced): from p along the incoming d, with its weight.
inline RayNode tir_node(int parent, int depth, const Vec3& p, const Vec3& d, double weight, bool entering) {
  RayNode n;
  n.kind = RayKind::kRefract;
  n.parent = parent;
  n.depth = depth;
  n.origin = p;
  n.direction = d;
  n.weight = weight;
  n.tir = true;
  n.entering = entering;
  return n;
}

// Appends node to *tree and returns its index; -1 (nothing kept) when tree is null.
inline int record(RayTree* tree, const RayNode& node) {
  if (!tree) return -1;
  tree->nodes.push_back(node);
  return int(tree->nodes.size()) - 1;
}

// The outward unit geometric normal at p on prim: a sphere's (p - c) / |p - c|
// (whatever the radius' sign: spheres are solids here), a polygon's plane
// normal (its front). It says which side a ray comes from (entering or
// leaving) and where rays that leave p start.
Vec3 outward_normal(const Scene& scene, uint32_t prim, const Vec3& p);

// ---------------------------------------------------------------- the laws
// Mirror reflection of unit d about unit n: r = d - 2 (d.n) n (unit, the same
// angle on the other side of n, in the plane of d and n).
inline Vec3 reflect(const Vec3& d, const Vec3& n) { return d - 2.0 * dot(d, n) * n; }

// Refraction of unit d at a surface with unit normal n facing against d
// (d.n <= 0), eta = n1 / n2 (Heckbert's form, Glassner ed., An Introduction
// to Ray Tracing, ch. 5): with c = -d.n and k = 1 - eta^2 (1 - c^2),
//   t = eta d + (eta c - sqrt(k)) n,
// and k < 0 is total internal reflection (returns false, t untouched).
inline bool refract(const Vec3& d, const Vec3& n, double eta, Vec3& t) {
  const double c = -dot(d, n);
  const double k = 1.0 - eta * eta * (1.0 - c * c);
  if (k < 0) return false;
  t = eta * d + (eta * c - std::sqrt(k)) * n;
  return true;
}

// Waechter and Binder, "A Fast and Robust Method for Avoiding
// Self-Intersection", Ray Tracing Gems (2019) ch. 6, in float as the chapter
// has it: each coordinate of the hit p moves along the unit normal n (pointing
// to the side the new ray leaves on) by 256 n_i ulps of that coordinate --
// an offset that scales with the coordinate's magnitude, as the rounding
// error of the hit point does -- except near the origin (|p_i| < 1/32), where
// ulps become tiny and a fixed n_i / 65536 is added instead. The integer add
// on the bit pattern steps away from zero for positive p_i and n_i; for a
// negative p_i the sign of the step is flipped so that it still moves along n.
inline Vec3f offset_robust(const Vec3f& p, const Vec3f& n) {
  constexpr float kOrigin = 1.0f / 32, kFloatScale = 1.0f / 65536, kIntScale = 256;
  Vec3f out;
  for (int a = 0; a < 3; ++a) {
    const int32_t step = int32_t(kIntScale * n[a]);
    const int32_t bits = std::bit_cast<int32_t>(p[a]) + (p[a] < 0 ? -step : step);
    out[a] = std::fabs(p[a]) < kOrigin ? p[a] + kFloatScale * n[a] : std::bit_cast<float>(bits);
  }
  return out;
}

// The same method in double, for an intersector that works in double in world
// coordinates (the reference): its hit points carry rounding errors of a few
// double ulps of each coordinate, so the step is 256 double ulps of the
// coordinate (int64 on the bit pattern), and near the origin (|p_i| < 1/32) a
// fixed n_i 2^-45: the chapter's 2^-16 scaled by the ratio of the two
// machine epsilons (2^-52 / 2^-23), as the ulp step is. The offset therefore
// stays below 1e-6 world units up to |p_i| = 2^25 (256 ulps of 2^24 is
// 2^-20), where the float method's is 0.016 already at |p_i| = 512 and 1 at
// 2^15: larger than the gaps a double scene out there can hold.
inline Vec3 offset_robust(const Vec3& p, const Vec3& n) {
  constexpr double kOrigin = 1.0 / 32, kFloatScale = 0x1p-45, kIntScale = 256;
  Vec3 out;
  for (int a = 0; a < 3; ++a) {
    const int64_t step = int64_t(kIntScale * n[a]);
    const int64_t bits = std::bit_cast<int64_t>(p[a]) + (p[a] < 0 ? -step : step);
    out[a] = std::fabs(p[a]) < kOrigin ? p[a] + kFloatScale * n[a] : std::bit_cast<double>(bits);
  }
  return out;
}

// Which arithmetic the intersector that will trace a ray works in, and so
// which ulps the robust offset counts: float (embree: Embree traverses the
// float coordinates of the eye frame) or double (the reference, world
// coordinates).
enum class Arith : uint8_t { kFloat, kDouble };

// Where a ray leaving the hit p in direction dir starts: p moved off the
// surface along the outward geometric normal ng, to dir's side, by eps
// (Offset::kFixed) or by offset_robust (Offset::kRobust) in the intersector's
// arithmetic (kFloat: p and ng rounded to float first, as the chapter works).
// The caller resolves Offset::kOwn.
inline Vec3 ray_start(const Vec3& p, const Vec3& ng, const Vec3& dir, const TraceSettings& s,
                      Arith arith) {
  const Vec3 side = dot(dir, ng) >= 0 ? ng : -ng;
  if (s.offset == Offset::kRobust)
    return arith == Arith::kFloat ? Vec3(offset_robust(Vec3f(p), Vec3f(side)))
                                  : offset_robust(p, side);
  return p + s.eps * side;
}

// ---------------------------------------------------------------- the entry points
// The whole frame (the scene's view at opts.width x opts.height, settings in
// opts.params); stats->items counts every ray: primary + shadow + secondary.
using TraceRenderFn = Image (*)(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
// One pixel's colour and, when tree is not null, its ray tree (the same
// computation the frame does for that pixel).
using TracePixelFn = Vec3 (*)(const Scene& scene, const TraceSettings& settings, int width,
                              int height, int x, int y, RayTree* tree);

}  // namespace lockstep
