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
#include <span>
#include <string>
#include <vector>

#include "core/math.h"

namespace lockstep {

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
SolveResult solve_radiosity(const std::vector<Patch>& patches, const std::vector<double>& f,
                            RadiositySolver solver, double tolerance, int max_iterations);

// max_i,c |B_i - E_i - rho_i sum_j F_ij B_j|.
double radiosity_residual(const std::vector<Patch>& patches, const std::vector<double>& f,
                          const std::vector<Vec3>& b);

}  // namespace lockstep
