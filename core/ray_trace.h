// lockstep core: the ray-tracing contract (Whitted 1980).
//
// Every ray-tracing implementation (ref: reference/ray_trace.cpp; opt::embree:
// optimized/ray_trace_embree.cpp) provides the two functions of the types at
// the end, and registry/ray_trace_row.cpp lists them. The scene is the NFF scene of
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
//   robust  by the hit's error bounds (robust_offset below): ulps of the
//           primitive's coordinates in the arithmetic and frame of the
//           intersector (embree: float, in a frame centred on the scene; the
//           reference: double, world), from a hit point re-projected onto
//           its surface (surface_point): right at any eye distance.
// The default is each implementation's own: the reference fixed with eps =
// 1e-6, embree robust.
#pragma once

#include <algorithm>
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

// ---------------------------------------------------------------- leaving a surface
// A hit point moved onto the surface it was found on, in object space, and a
// bound on how far it can still be from that surface (world units). The hit
// o + t d carries the error of t, which grows with the distance from the ray's
// origin: a textbook sphere seen from 1e5 away is hit ~1e-6 off its surface.
// Re-projected (a sphere: c + |r| (p - c) / |p - c|; a polygon: onto its
// plane), the error is a few ulps of the surface's own coordinates, whatever
// the eye's distance. Cones are not re-projected: their careful roots (reference/
// ray_cone.h) are already good to a few ulps of |o| + t, and err says so.
struct SurfacePoint {
  Vec3 p;
  double err = 0;
};
SurfacePoint surface_point(const Scene& scene, uint32_t prim, const Ray& ray, double t);

// The largest |coordinate| an intersector holds for prim, in the frame it
// works in (frame_origin subtracted; the frames here only translate): a
// sphere's centre plus its radius, a polygon's vertices and plane offset, a
// cone's end centres plus its larger radius. It scales both how well the
// intersector knows where the surface is (its coordinates' rounding) and how
// well it can tell a ray's origin from it.
double prim_magnitude(const Scene& scene, uint32_t prim, const Vec3& frame_origin);

// Which arithmetic the intersector that will trace a ray works in: float
// (embree: Embree traverses float coordinates of its frame, which the row
// centres on the scene, optimized/ray_trace_embree.cpp) or double (the
// reference, world coordinates).
enum class Arith : uint8_t { kFloat, kDouble };

// The robust offset: how far along the geometric normal a ray leaving a
// surface starts, from the bounds of every error that could put that surface,
// as the next intersector sees it, on the new ray's side of its origin
// (Pharr, Jakob and Humphreys, Physically Based Rendering 3rd ed. 3.9: offset
// by the hit's error bound; Waechter and Binder, Ray Tracing Gems ch. 6, for
// counting it in ulps of the coordinates involved):
//   kRobustUlps unit roundoffs of the arithmetic times the primitive's
//   magnitude in the intersector's frame (its coordinates' rounding, the
//   intersection test's own error for an origin that close: a few ulps; the
//   rounding of the new origin to float: half an ulp), plus
//   kRobustErr times the hit point's own bound (SurfacePoint::err).
// Nothing in it depends on the distance the hit was seen from: only on the
// size of the primitive's coordinates in the frame (the scene's scale, and
// for double rows its distance from the world origin). 32: measured, the
// failure map (bench/studies/ray_trace_study.cpp) and the property Far find acne in
// embree with 1 and none with 4 or more; 32 keeps 8x over that, and a
// smaller offset leaks less and moves shadow rays less off the reference's
// (256 gave 18 pixels over 1/255 on corpus rt-pov-tree-11, whose ground's
// vertices are 50 away; 32 gives 3).
inline constexpr double kRobustUlps = 32, kRobustErr = 4;
inline double robust_offset(double magnitude, double err, Arith arith) {
  const double unit = arith == Arith::kFloat ? 0x1p-24 : 0x1p-53;
  return std::max(kRobustUlps * unit * magnitude + kRobustErr * err, 0x1p-1022);
}

// Where a ray leaving the surface point sp (in the caller's frame: sp.p there)
// in direction dir starts: moved off the surface along the outward geometric
// normal ng, to dir's side, by eps (Offset::kFixed) or by robust_offset
// (Offset::kRobust; magnitude from prim_magnitude in the intersector's frame).
// The caller resolves Offset::kOwn.
inline Vec3 ray_start(const Vec3& p, double err, double magnitude, const Vec3& ng, const Vec3& dir,
                      const TraceSettings& s, Arith arith) {
  const Vec3 side = dot(dir, ng) >= 0 ? ng : -ng;
  if (s.offset == Offset::kRobust) return p + robust_offset(magnitude, err, arith) * side;
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
