// lockstep props: the oracle, exact decisions and 113-bit t.
//
// The double inputs are exact rationals. Every hit/miss decision is taken in
// exact rational arithmetic (CGAL::Gmpq): the sign of the sphere's discriminant,
// where its roots lie against tmin/tmax, the plane's n.d, the exact hit point
// inside the polygon (CGAL::bounded_side_2 on the projection dropping the
// dominant axis of the normal; the boundary counts as inside). t itself comes
// from the exact quantities through a stable formula evaluated with MPFR at 256
// bits, and is returned as __float128 (113 bits, correctly rounded).
//
// Besides the answer, the oracle says how hard the query is. Three views:
//   local     the query seen from the ray origin (translation-invariant): what a
//             careful implementation working relative to the ray (the SIMD
//             frames, refine_hit) can be expected to get right;
//   world     the problem in world coordinates: perturbing each input component
//             by a relative epsilon. "Well-conditioned" (for agreement and
//             accuracy) is decided on this view;
//   textbook  world plus the amplification of the textbook formula itself (the
//             discriminant B^2 - 4AC cancels for far/small spheres).
// kappa is the relative condition number of t (relative error of t per unit of
// relative input perturbation); margin is the relative distance to the nearest
// decision boundary (hit/miss, root against tmin/tmax, facing, polygon edge) in
// the same units: an implementation with unit roundoff eps may flip a decision
// only when margin is below a small multiple of eps. The *_why strings name the
// dominating term: grazing, near_tmin, near_tmax, parallel, near_edge,
// translation, cancellation, separation, zero_area.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/scene.h"

namespace lockstep::props::ray_cast {

using f128 = __float128;

struct Conditioning {
  double kappa = 1;
  const char* kappa_why = "";
  double margin = kInfinity;
  const char* margin_why = "";
};

struct OracleHit {
  bool hit = false;
  f128 t = f128(kInfinity);  // in units of |d|; +inf on a miss
  int root = -1;             // spheres: 0 the near root, 1 the far root
  double t_decide = kInfinity;  // about where along the ray the decision sits (for trace relevance)
  Conditioning local, world, textbook;
  bool zero_area = false;  // polygon with exactly zero area (exact Newell normal is 0)
};

// Thresholds of "well-conditioned" (world view): kappa <= kWellKappa and margin >= kWellMargin.
inline constexpr double kWellKappa = 64;
inline constexpr double kWellMargin = 1e-4;
bool well_conditioned(const OracleHit& h);
// Short text: "hit t=... kappa_local=... margin_local=...(why)".
std::string describe(const OracleHit& h);

// Kernels (no culling, nearest root in (tmin, tmax)), as core/ray_cast.h.
OracleHit oracle_sphere(const Ray& ray, const Sphere& sphere);
OracleHit oracle_plane(const Ray& ray, const Plane& plane);
OracleHit oracle_polygon(const Ray& ray, const Scene& scene, uint32_t poly);
// NFF's open cone `cone` of the scene, either side (root 0 / 1: the quadric's
// near / far root). Decisions also cover the rim (near_rim), the apex
// (near_apex) and rays parallel to a side line (parallel).
OracleHit oracle_cone(const Ray& ray, const Scene& scene, uint32_t cone);

// Frames: the nearest visible hit over the whole scene (NFF sidedness).
struct OracleTrace {
  OracleHit best;            // conditioning: the best prim's, margin over every relevant decision
  uint32_t prim = Hit::kNoHit;
  std::vector<uint32_t> tied;  // prims whose visible hit is at best.t within 1e-12 (all acceptable)
  std::vector<OracleHit> per_prim;  // visible-hit answer for every prim
};
OracleTrace oracle_trace(const Scene& scene, const Ray& ray);

// Watertightness of closed meshes (polygons only): the first contact of the ray
// with any polygon, either side, the boundary included, and every polygon that
// contains that exact point. transversal: every such polygon faces the ray
// strictly (|d.n| >= 1e-6 |d|, n the stored plane normal) or is two-sided, so a
// closed surface is entered there and any implementation must report a hit.
struct OracleContact {
  bool contact = false;
  f128 t = f128(kInfinity);
  std::vector<uint32_t> touching;
  bool transversal = false;
};
OracleContact oracle_contact(const Scene& scene, const Ray& ray);

// Exact: the polygon's vertices have zero area (exact Newell normal is zero).
bool oracle_zero_area(const Scene& scene, uint32_t poly);

// 113-bit helpers.
double to_double(f128 x);
std::string hex128(f128 x);  // %Qa
// |a - b| / |b| in 113 bits (0 when both are equal, including infinities).
double rel_error(double a, f128 b);

}  // namespace lockstep::props::ray_cast
