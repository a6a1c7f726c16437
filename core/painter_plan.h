// lockstep core: the painter's plan, shared by every painter row (reference/painter.h,
// optimized/painter_simd.h): the painter's algorithm with the Newell-Newell-Sancha
// tests (Newell, Newell and Sancha 1972; Foley, van Dam, Feiner, Hughes,
// "Computer Graphics: Principles and Practice", 2nd ed., 15.5.1), and the exact
// predicates it decides with (Shewchuk 1997, "Adaptive precision floating-point
// arithmetic and fast robust geometric predicates").
//
// The geometry the painter reasons about is the one the z-buffer draws: each
// ScreenTri of ref::view_scene, with its snapped screen vertices (X, Y in
// 1/256 pixel) and the depth the z-buffer interpolates linearly on screen
// (1/z: the z-buffer always takes depth from the plane of 1/z). In that
// "screen space" S = (X, Y, W) the view is orthographic along W (larger W =
// nearer), triangles are exactly planar, and "Q hides P at sample s" is exactly
// "W_Q(s) > W_P(s)". Every test below is exact in S.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/raster.h"

namespace lockstep {

// ---------------------------------------------------------------- exact predicates
namespace exact {
// Exactness: the expansions are exact as long as no product's rounding error
// underflows (below 2^-1074) or overflows: every nonzero coordinate and
// coordinate difference within [2^-300, 2^300] suffices (eye and screen
// coordinates are far inside). Subnormal inputs can decide wrong
// (PainterExact labels such cases "underflow").
//
// Sign (+1, 0, -1) of (b - a) x (c - a): +1 when a, b, c turn counter-clockwise
// in a right-handed (x, y) frame.
int orient2d(double ax, double ay, double bx, double by, double cx, double cy);
// Sign of det[a - d; b - d; c - d]. With a, b, c
// counter-clockwise seen from above (+z), points above the plane give -1.
int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
// Whether the closed triangles t and u share a point; exact (orient3d and
// orient2d only). Degenerate (collinear) triangles are treated as segments.
bool triangles_intersect(const std::array<Vec3, 3>& t, const std::array<Vec3, 3>& u);
// Sign of a*b*c + d*e*f + ... : sum over the rows of the product of three
// doubles, exact. For the per-sample depth comparison.
int sign_of_triple_products(const double (*rows)[3], int n);
}  // namespace exact

// ---------------------------------------------------------------- the painter's plan

// One ScreenTri as the painter sees it.
struct PainterTri {
  std::array<int64_t, 3> x{}, y{};  // snapped screen position, 1/256 pixel
  std::array<Vec3, 3> s;            // (x, y, W = 1/z) in screen space S
  int64_t xmin = 0, xmax = 0, ymin = 0, ymax = 0;
  double zmin = 0, zmax = 0;  // eye depth range
  int64_t area = 0;           // twice the snapped area (> 0)
};
PainterTri painter_tri(const ScreenTri& t);

// How two triangles whose screen extents overlap must be drawn; p is the one
// the depth sort put first (farther).
enum class PairOrder : uint8_t {
  kNone,            // their projections share no interior point: any order
  kPFirst,          // p must be drawn before q
  kQFirst,          // q must be drawn before p (the sort was wrong for this pair)
  kInterpenetrate,  // they cross inside their common screen area: no order is right
  kCoplanar,        // the same plane over a common area: the z-buffer's tie rule decides
};
// Which test decided: 1 x extents, 2 y extents, 3 p behind q's plane, 4 q in
// front of p's plane, 5 projections disjoint, 6 q behind p's plane or p in
// front of q's plane (reversed 3/4), 7 exact intersection, 8 depth at a
// witness point of the common area, 0 depth ranges disjoint.
struct PairVerdict {
  PairOrder order = PairOrder::kNone;
  int test = 0;
};
PairVerdict classify_pair(const PainterTri& p, const PainterTri& q);
// Test 5 alone: the interiors of the two screen triangles are disjoint (exact).
// classify_pair(p, q) is then {kNone, 5} whenever the extents overlap.
bool projections_disjoint(const PainterTri& p, const PainterTri& q);

// Exact: is triangle a nearer than triangle b at the sample (sx, sy) (snapped
// units)? Equal depths: the lower index (the z-buffer keeps the first).
bool nearer_at(const PainterTri& a, uint32_t ia, const PainterTri& b, uint32_t ib, int64_t sx,
               int64_t sy);

struct PainterPlan {
  std::vector<uint32_t> sorted;  // triangle indices, farthest eye z first (ties: scene order)
  std::vector<uint32_t>
      order;  // the drawing order: components topologically, members in sorted order
  std::vector<uint32_t> group;  // per triangle: its component (cycles and interpenetrations merged)
  std::vector<uint32_t> group_size;  // per component: members
  std::vector<std::vector<uint32_t>>
      cycles;  // components of the must-draw-before graph with > 1 triangle
  std::vector<std::vector<uint32_t>>
      groups;  // components with > 1 triangle once interpenetrating pairs
               // are tied both ways: what no order draws right (in sort order)
  std::vector<std::array<uint32_t, 2>> interpenetrations;
  std::vector<std::array<uint32_t, 2>> coplanar;
  uint64_t pairs = 0;                    // pairs whose screen extents overlap
  std::array<uint64_t, 9> decided_by{};  // PairVerdict::test counts
  uint64_t edges = 0;
};
// The steps, separately (the optimized painter replaces the first two):
// the depth sort (farthest eye z first, ties in scene order);
std::vector<uint32_t> painter_sort(const std::vector<PainterTri>& tris);
// every pair whose screen extents overlap, classified (p: the one sorted first);
struct PairFinding {
  uint32_t p = 0, q = 0;
  PairVerdict v;
};
std::vector<PairFinding> painter_pairs(const std::vector<PainterTri>& tris,
                                       const std::vector<uint32_t>& sorted);
// the graph of those verdicts, its strongly connected components (Tarjan
// 1972) and a topological order of them (Kahn 1962). The result does not
// depend on the order of `pairs`.
PainterPlan painter_plan(const std::vector<PainterTri>& tris, std::vector<uint32_t> sorted,
                         const std::vector<PairFinding>& pairs);
// All three.
PainterPlan painter_plan(const std::vector<PainterTri>& tris);
// The notes a run reports: counts, then each group (every triangle that no
// order draws right), each interpenetrating and coplanar pair, with triangle
// and primitive indices ("tri N (prim P)").
std::vector<std::string> painter_notes(const ScreenMesh& mesh, const PainterPlan& plan, bool split);

// The fragment of triangle t at sample (sx, sy) in snapped units, with edge
// functions e (e[i] = E opposite vertex i) and twice the area.
Fragment painter_fragment(const ScreenMesh& mesh, uint32_t t, int64_t sx, int64_t sy,
                          const std::array<int64_t, 3>& e, int64_t area, bool perspective);
// Whether the top-left fill rule gives the sample to triangle t (e as above).
bool painter_covers(const ScreenTri& t, const std::array<int64_t, 3>& e);


}  // namespace lockstep
