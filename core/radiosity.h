// lockstep core: radiosity (issue #33), the contract every row shares.
//
// The scene is cut into patches: planar convex polygons (3 or 4 vertices,
// counter-clockwise seen from the side the normal points to), each with a
// reflectance rho and an emitted radiosity E per channel (RGB). The form
// factor F_ij is the fraction of the energy leaving patch i (diffusely) that
// arrives at patch j (Cohen and Wallace, "Radiosity and Realistic Image
// Synthesis", ch. 4):
//
//   F_ij = 1/A_i  Int_{A_i} Int_{A_j}  cos(t_i) cos(t_j) / (pi r^2)  V  dA_j dA_i
//
// with V the visibility between the two points. Two laws hold for any
// correct form factors: reciprocity A_i F_ij = A_j F_ji, and in a closed
// enclosure the summation rule sum_j F_ij = 1. The radiosities solve
//
//   B_i = E_i + rho_i sum_j F_ij B_j          (per channel)
//
// which converges (Jacobi, Gauss-Seidel, progressive refinement) when every
// reflectance is below 1: a scene with rho >= 1 is refused, not iterated.
//
// The closed forms here are the exact oracles the rows are measured with.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "core/family.h"
#include "core/large_buffer.h"
#include "core/math.h"
#include "core/raster.h"
#include "core/scene.h"

namespace lockstep {

// The dense form-factor matrix, row-major (F_ij at i * n + j): n^2 doubles,
// 136 MB at 4,119 patches, on huge pages where the kernel allows
// (core/large_buffer.h: its first touch was most of a one-shot call's extra
// cost). Constructed without a value it is not initialized: a row writes
// every entry of its own, or the maker fills it.
using FormFactors = UninitVector<double>;

struct Patch {
  Vec3 v[4];         // the corners, counter-clockwise about the normal
  int count = 4;     // 3 or 4
  Vec3 rho;          // reflectance per channel, each in [0, 1)
  Vec3 emission;     // emitted radiosity per channel, >= 0
  int polygon = -1;  // the scene polygon it was cut from

  std::span<const Vec3> corners() const { return {v, size_t(count)}; }
  Vec3 normal() const;  // unit, from the corners' winding
  double area() const;
  Vec3 centre() const;  // the centroid of the area
};

// ------------------------------------------------------------ form factors

// F from a differential area at x with unit normal n to a polygon (any
// winding), unoccluded: Lambert's contour integral (Cohen and Wallace eq.
// 4.18), the polygon first clipped to the half-space in front of x (the
// part behind the tangent plane sends nothing). Exact up to rounding.
double point_polygon_form_factor(const Vec3& x, const Vec3& n, std::span<const Vec3> polygon);

// F_ij between two patches, unoccluded, by an n x n midpoint rule over
// patch i of the point-to-polygon form factor (exact in j): converges as
// 1/n^2 for patches that do not touch.
double patch_form_factor(const Patch& from, const Patch& to, int n);

// F from polygon `from` to polygon `to` (planar, convex, each facing the
// side from which its corners run counter-clockwise, as a Patch does),
// unoccluded, area to area and exact: Stokes turns the double area integral
// into a double contour integral (Sparrow 1963; Cohen and Wallace eq. 4.16),
//   F = 1/(2 pi A_from) sum_p sum_q (e_p . e_q) Int_0^1 Int_0^1 ln r dt_q dt_p,
// e_p and e_q the edges; the inner integral in closed form, the outer by
// adaptive Gauss-Kronrod (1e-14 per edge pair, or rounding's floor, at
// most 200 panels). Each
// polygon is first clipped to the half-space in front of the other's plane
// (the cosines clamp at 0). Polygons that share an edge or a corner are
// fine: ln r is integrable. The oracle for form_factors=exact and for the
// other methods' error; reciprocity holds to rounding.
double polygon_form_factor(std::span<const Vec3> from, std::span<const Vec3> to);

// From a differential area to a coaxial parallel disk of radius r at
// distance h: r^2 / (h^2 + r^2) (Howell B-13).
inline double point_disk_form_factor(double r, double h) { return r * r / (h * h + r * r); }

// Closed forms (Howell's catalogue of configuration factors, C-11, C-14,
// B-3), the oracles the rows' form factors are measured against.
// Two directly opposed parallel rectangles a x b at distance c.
double parallel_rectangles_form_factor(double a, double b, double c);
// From a rectangle (width w, along the common edge of length l) to a
// perpendicular one (height h) sharing that edge.
double perpendicular_rectangles_form_factor(double l, double w, double h);
// From a differential area to a parallel rectangle a x b whose corner lies
// on the area's normal at distance c.
double point_rectangle_corner_form_factor(double a, double b, double c);

// ------------------------------------------------------------------- meshing

// Cuts a convex planar quad or triangle into patches of at most max_area: a
// quad into nu x nv quads on its bilinear grid (planar, so every piece is
// planar and convex), a triangle into 4^k triangles by its edge midpoints.
std::vector<Patch> mesh_polygon(std::span<const Vec3> polygon, const Vec3& rho,
                                const Vec3& emission, double max_area, int polygon_index);

// ------------------------------------------------------------------- solving

enum class RadiositySolver { jacobi, gauss_seidel, progressive };

struct SolveResult {
  std::vector<Vec3> b;  // radiosity per patch
  int iterations = 0;   // sweeps (Jacobi, Gauss-Seidel) or shots (progressive)
  double residual = 0;  // max_i,c |B - E - rho F B|
};

// Solves B = E + rho F B for the dense row-major form factor matrix f
// (f[i * n + j] = F_ij) until the residual is at most tolerance (relative to
// the largest emission) or max_iterations. Progressive refinement shoots
// the patch with the most unshot energy (unshot radiosity times area) until
// what is left unshot is at most tolerance of what was emitted. Throws
// std::invalid_argument when a reflectance is outside [0, 1) or an emission
// is negative or not finite.
SolveResult solve_radiosity(const std::vector<Patch>& patches, const FormFactors& f,
                            RadiositySolver solver, double tolerance, int max_iterations);

// What solve_radiosity checks first (every solver's precondition): f is n x
// n, every reflectance in [0, 1), every emission finite and >= 0; throws
// std::invalid_argument naming the value. Returns the largest emission.
double radiosity_system_check(const std::vector<Patch>& patches, const FormFactors& f);

// max_i,c |B_i - E_i - rho_i sum_j F_ij B_j|.
double radiosity_residual(const std::vector<Patch>& patches, const FormFactors& f,
                          const std::vector<Vec3>& b);

// ------------------------------------------------------------- the family
//
// The radiosity family (registry/radiosity_row.cpp) reads an NFF scene whose
// emitters carry '#lockstep emit' (io/nff.h), cuts its polygons into patches
// (mesh_scene), computes the form factors by one of two methods, solves, and
// displays the solution through the z-buffer: every row runs these steps,
// and they share the ones below.
//
// Form factors (settings form_factors=...):
//   rays      F_ij = F(c_i -> j) V_ij: Lambert's exact point-to-polygon
//             factor from i's centre c_i (point_polygon_form_factor), times
//             the fraction V_ij of k x k points of j (the midpoints of its
//             grid) that a segment from c_i reaches unblocked by any scene
//             polygon. 0 when j faces away from c_i.
//   hemicube  Cohen and Greenberg (1985): the scene seen from c_i through the
//             five faces of a unit half-cube (res x res on the top, the upper
//             halves of four sides), each pixel's visible patch getting the
//             pixel's delta form factor (hemicube_weights). A pixel whose
//             nearest polygon faces away from c_i gives its share to no one.
//   exact     F_ij = F(i -> j) V_ij: the area-to-area factor (exact_form_factor,
//             polygon_form_factor) times V_ij as for rays. Exact where
//             nothing occludes; the oracle of the other two.
// rays and hemicube are point-to-area: exact in j, one point of i. Their
// error against the area-to-area factor is the method's (docs/radiosity.md).

enum class FormFactorMethod { rays, hemicube, exact };

struct RadiositySettings {
  FormFactorMethod method = FormFactorMethod::rays;
  int rays = 2;                    // rays: k x k points on each patch j
  int hemicube = 64;               // hemicube: pixels a side of the top face (even)
  RadiositySolver solver = RadiositySolver::gauss_seidel;
  double patch_area = 0;           // the largest patch area; 0: the scene's polygon area / 256
  double error = 0;                // > 0: refine until no weighted jump between neighbours passes it (refine_patches)
  double tolerance = 1e-4;         // the solve's residual, relative to the largest emission
  int max_iterations = 10000;      // sweeps or shots
};

// Reads a family's Params (form_factors, rays, hemicube, solver, patch_area,
// tolerance). Throws InputError(source, 0, ...) naming the setting.
RadiositySettings radiosity_settings(const Params& params, const std::string& source);
std::vector<ParamSpec> radiosity_params();

// The scene cut into patches, with the vertices the display interpolates.
struct PatchMesh {
  std::vector<Patch> patches;
  // Display vertices: patch corners, shared by the patches of one scene
  // polygon that meet there (not across polygons: a crease keeps both sides).
  std::vector<Vec3> vertex;
  std::vector<std::array<uint32_t, 4>> corner;  // per patch: its corners' display vertices
  uint64_t spheres_and_cones = 0;               // left out: not polygons (FrameStats::dropped)
  uint64_t no_area = 0;                         // polygons without area, left out (FrameStats::dropped)
  double max_area = 0;                          // the patch area it was cut at
  double cut_area = 0;                          // the smallest area refinement cut to (max_area when none)
};

// Cuts every polygon of the scene into patches of at most max_area (0: the
// scene's total polygon area / 256): convex quads on their grid, other
// polygons through their triangulation. Reflectance is the material's
// colour x Kd, emission its '#lockstep emit'. Throws InputError naming the
// scene (and the material's line) when a reflectance is 1 or more, or when
// the patch count would pass 20000 (a dense matrix of 3.2 GB).
PatchMesh mesh_scene(const Scene& scene, double max_area);

// The display vertices of mesh's patches again (after they changed): each
// corner one vertex per scene polygon and position, as mesh_scene makes them.
void index_vertices(PatchMesh& mesh);

// ------------------------------------------------------- adaptive refinement
//
// --error E, "model no more than a scene needs": the uniform mesh is a
// start; after each solve every patch whose radiosity differs from a
// neighbour's (a patch of the same scene polygon whose box touches its own)
// by a jump J, relative to the scene's largest reflected radiosity (B - E,
// per channel: the emitters' own emission left out), with J sqrt(A / A0) > E
// (A its area, A0 the start's patch area: a jump counts by the width it
// spans, so a step that no cut removes, a shadow's edge or a block's foot,
// stops being cut once its patches are narrow) is cut in four (a quad at its
// edges' midpoints on its bilinear grid, a triangle at its edges'
// midpoints), and the scene solved again: the patches gather where the
// radiosity changes. Until no patch passes E, or none may be cut: none
// smaller than A0 / 4^kRefineLevels, and the mesh at most kMaxPatches. Cut
// neighbours leave T-junctions: the coarse patch's edge holds the fine
// ones' corners, which its display vertices do not (the display's colour
// steps there; docs/radiosity.md).
inline constexpr int kRefineLevels = 4;
inline constexpr size_t kMaxPatches = 20000;

// Each patch's largest jump to a neighbour, relative to the largest
// reflected radiosity B - E (0 when nothing is lit).
std::vector<double> radiosity_jumps(const PatchMesh& mesh, const std::vector<Vec3>& b);

struct Refined {
  size_t cut = 0;          // patches cut in four
  size_t held = 0;         // patches over E left whole: at the smallest size, or the cap reached
};
// Cuts the patches whose jump, times sqrt(area / mesh.max_area), passes e
// (largest first while the cap allows), no patch below min_area; the
// display vertices rebuilt.
Refined refine_patches(PatchMesh& mesh, const std::vector<Vec3>& b, double e, double min_area);

// solve_radiosity (or a row's own solve) with the row's settings; a refused
// system (reflectance, emission) is an InputError naming source.
using RadiositySolve =
    std::function<SolveResult(const std::vector<Patch>&, const FormFactors&, RadiositySolver, double, int)>;
SolveResult solve_patches(const PatchMesh& mesh, const FormFactors& f, const RadiositySettings& s,
                          const std::string& source, const RadiositySolve& solve = {});
// A scene's solution: its (refined) patches, their form factors and
// radiosities.
struct RadiositySolution {
  PatchMesh mesh;
  FormFactors f;
  SolveResult solved;
  int rounds = 0;      // solves after the first (refinements)
  double jump = 0;     // the largest weighted jump left (refine_patches), when refining
  size_t held = 0;     // patches over E left whole on the last round
};
// Every row's steps 1-3: mesh_scene at s.patch_area, the row's form factors
// (given the mesh and the storage of the last round's), its solve; with
// s.error > 0 refined and solved again until refine_patches cuts nothing.
using FormFactorsOf = std::function<FormFactors(const PatchMesh&, FormFactors storage)>;
RadiositySolution solve_scene(const Scene& scene, const RadiositySettings& s, const FormFactorsOf& form_factors,
                              const RadiositySolve& solve = {});

// The patches as a scene of polygons (polygon p = patch p, one material): the
// z-buffer's item buffer names patches by the polygons it draws.
Scene patch_scene(const PatchMesh& mesh, const View& view);

// The delta form factors of a hemicube of res x res pixels on the top face
// (res even): top[j * res + i] for pixel (i, j) of the top face, side[j * res
// + i] for pixel (i, j) of a side face's upper half (rows j < res / 2, the
// row nearest the top face first). Pixel (i, j) of a face seen through a
// camera with pitch 2 / res (Camera: centres at sx(i), sy(j)): top 1 / (pi
// (x^2 + y^2 + 1)^2) dA, side z / (pi (x^2 + z^2 + 1)^2) dA, dA = (2/res)^2.
struct HemicubeWeights {
  int res = 0;
  std::vector<double> top, side;
};
HemicubeWeights hemicube_weights(int res);
// The camera of face f (0: top, along n; 1-4: sides, along u, -u, v, -v with
// n up) of a hemicube at c with unit normal n, res pixels a side of the full
// face, hither at near: a View for view_scene. u is turned by `turn`
// radians about n from a fixed perpendicular.
View hemicube_view(const Vec3& c, const Vec3& n, int face, int res, double near, double turn);
// Patch i's hemicube turn, in [0, pi/2): the golden-ratio sequence. A
// hemicube square to the room lines its pixel centres up with the room's
// edges (every sample of a column on the edge where two walls meet, each
// z-buffer's rounding then deciding which wall it sees); turned, such a
// sample has probability 0, and the aliasing of regular edges spreads out
// (Cohen and Wallace, 5.8: rotating the hemicube about the normal).
double hemicube_turn(size_t patch);
// Adds face f's pixels to row i of the form factors (f_row[j] = F_ij): each
// pixel of the face (the upper half of a side) its delta form factor to the
// patch the item buffer vis shows there (screen: the face's view of
// patch_scene(mesh)); nothing for patch i itself or a patch seen from behind
// (the pixel's share is lost).
void add_hemicube_face(const PatchMesh& mesh, const Scene& items, const ScreenMesh& screen, const Visibility& vis,
                       const HemicubeWeights& w, size_t i, int face, double* f_row);

// F(c_i -> j): the unoccluded point-to-polygon factor from patch i's centre
// to patch j; 0 when j == i or c_i is not in front of j (j sends nothing to
// a point behind it, nor to one in its plane: within 1e-9 rad of it). The rays method scales it by j's visible fraction.
double centre_form_factor(const PatchMesh& mesh, size_t i, size_t j);
// F_ij area to area, unoccluded (polygon_form_factor); 0 between patches of
// one scene polygon (planar: they exchange nothing). The exact method scales
// it by j's visible fraction from i's centre.
double exact_form_factor(const PatchMesh& mesh, size_t i, size_t j);
// The k x k points of patch p its rays aim at (grid midpoints; triangles:
// the centroids of k^2 congruent pieces).
std::vector<Vec3> patch_targets(const Patch& p, int k);
// Moller and Trumbore (1997): does the segment a + t d, t in (lo, hi),
// cross triangle (p0, p1, p2), from either side? (Its edges count; a
// segment in the triangle's plane does not.) The rays method's visibility
// predicate, in double, in both rows.
inline bool segment_meets_triangle(const Vec3& a, const Vec3& d, double lo, double hi, const Vec3& p0,
                                   const Vec3& p1, const Vec3& p2) {
  const Vec3 e1 = p1 - p0, e2 = p2 - p0;
  const Vec3 pv = cross(d, e2);
  const double det = dot(e1, pv);
  if (det == 0) return false;  // the segment is parallel to the plane
  const Vec3 s = a - p0;
  const double u = dot(s, pv) / det;
  if (u < 0 || u > 1) return false;
  const Vec3 q = cross(s, e1);
  const double v = dot(d, q) / det;
  if (v < 0 || u + v > 1) return false;
  const double t = dot(e2, q) / det;
  return t > lo && t < hi;
}

// Rays stop this fraction of their length short of each end: a polygon
// that touches the patch at the end (a corner of the room) does not block.
// The two patches' own polygons are never tested (reference/radiosity.h).
inline constexpr double kSegmentMargin = 1e-6;

// The z-buffer settings every row draws item buffers with (hemicube faces
// and the display): visibility only, back faces drawn (a back face hides what
// is behind it too), float depth (the simd z-buffer breaks exact depth ties
// at edges shared by two polygons as the reference does in float; with
// depth=double it kept other triangles there, whole hemicube pixels).
RasterSettings radiosity_item_buffer();
// A hemicube's hither: a hundredth of the side patches were cut to (another
// patch is at least half a side from a patch's centre).
double hemicube_near(const PatchMesh& mesh);

// What a run tells its user: the stats' items (n^2 form factors) and counts
// (patches, solver iterations, refinements with error), its notes and
// dropped: spheres and cones left out, no emitter (a black image), a solve
// stopped by max_iterations, patches refinement left over E.
void radiosity_notes(const RadiositySolution& sol, const RadiositySettings& s, FrameStats& stats);

// Vertex radiosities by area-weighted averaging of the patches that share
// each display vertex.
std::vector<Vec3> vertex_radiosity(const PatchMesh& mesh, const std::vector<Vec3>& b);

// The patches and their solution: the family's side output "patches"
// (`lockstep radiosity --patches OUT.ply`, registry/radiosity_row.cpp).
struct PatchSolution {
  PatchMesh mesh;
  std::vector<Vec3> b;         // per patch
  std::vector<Vec3> vertex_b;  // per display vertex (vertex_radiosity)
};
// Adds the side outputs opts asks for (FrameOptions::sides) to stats.
void radiosity_sides(const PatchMesh& mesh, const std::vector<Vec3>& b, const std::vector<Vec3>& vertex_b,
                     const FrameOptions& opts, FrameStats* stats);

// The display (Gouraud through the z-buffer): each pixel shows the vertex
// radiosities of its visible triangle (vis over the patch scene's screen
// mesh), interpolated with the perspective-correct barycentrics of the
// point where the pixel's centre ray meets the triangle's plane; background
// where nothing is visible. Depth is that point's eye distance along the
// view axis.
Image radiosity_image(const Scene& patches, const PatchMesh& mesh, const std::vector<Vec3>& vertex_b,
                      const ScreenMesh& screen, const Visibility& vis, const Vec3& background);

}  // namespace lockstep
