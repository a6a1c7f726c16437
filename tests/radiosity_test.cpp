// core/radiosity.h against its closed forms and laws (issue #33): the
// point-to-polygon form factor against the corner-aligned rectangle, the
// integrated patch form factor against parallel and perpendicular
// rectangles (converging as the rule refines), reciprocity, summation in a
// closed cube, and every solver reaching B = E / (1 - rho) in a closed
// enclosure of uniform emission and reflectance; a reflectance of 1 refused.
#include "core/radiosity.h"
#include "io/nff.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <cstdio>
#include <stdexcept>

namespace lockstep {
namespace {

Patch quad(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  Patch p;
  p.v[0] = a, p.v[1] = b, p.v[2] = c, p.v[3] = d;
  p.count = 4;
  return p;
}

// The unit cube [0, 1]^3 seen from inside (normals inward), each face cut
// into k x k patches, with reflectance rho and emission e everywhere.
std::vector<Patch> closed_cube(int k, double rho, double e) {
  const Vec3 c[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                     {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  // Corners counter-clockwise seen from inside.
  const int faces[6][4] = {{0, 1, 2, 3}, {4, 7, 6, 5}, {0, 4, 5, 1},
                           {3, 2, 6, 7}, {0, 3, 7, 4}, {1, 5, 6, 2}};
  std::vector<Patch> out;
  for (int f = 0; f < 6; ++f) {
    const Vec3 poly[4] = {c[faces[f][0]], c[faces[f][1]], c[faces[f][2]], c[faces[f][3]]};
    for (const Patch& p : mesh_polygon(poly, Vec3{rho, rho, rho}, Vec3{e, e, e}, 1.0 / (k * k), f))
      out.push_back(p);
  }
  return out;
}

// F_ij from each patch's centre (point-to-polygon, exact): in a closed
// convex enclosure each row sums to 1 (the centre's hemisphere sees
// nothing but the other faces).
FormFactors centre_form_factors(const std::vector<Patch>& p) {
  const size_t n = p.size();
  FormFactors f(n * n, 0.0);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j)
      if (i != j)
        f[i * n + j] = point_polygon_form_factor(p[i].centre(), p[i].normal(), p[j].corners());
  return f;
}

TEST(FormFactor, PointToRectangleCornerIsExact) {
  for (double a : {0.1, 1.0, 3.0})
    for (double b : {0.2, 1.0, 7.0})
      for (double c : {0.5, 1.0, 4.0}) {
        const Vec3 rect[4] = {{0, 0, c}, {a, 0, c}, {a, b, c}, {0, b, c}};
        const double got = point_polygon_form_factor({0, 0, 0}, {0, 0, 1}, rect);
        const double want = point_rectangle_corner_form_factor(a, b, c);
        EXPECT_NEAR(got, want, 1e-14) << "a " << a << " b " << b << " c " << c;
      }
  // The infinite quadrant's limit is a quarter.
  EXPECT_NEAR(point_rectangle_corner_form_factor(1e9, 1e9, 1), 0.25, 1e-8);
}

TEST(FormFactor, PolygonBehindTheTangentPlaneIsClipped) {
  // A unit square standing on the plane z = 0, half of it below: only the
  // upper half counts, which is a corner-aligned rectangle turned upright.
  const Vec3 wall[4] = {{0, 1, -1}, {1, 1, -1}, {1, 1, 1}, {0, 1, 1}};
  const double whole = point_polygon_form_factor({0, 0, 0}, {0, 0, 1}, wall);
  const Vec3 upper[4] = {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}};
  EXPECT_NEAR(whole, point_polygon_form_factor({0, 0, 0}, {0, 0, 1}, upper), 1e-15);
  const Vec3 below[4] = {{0, 1, -1}, {1, 1, -1}, {1, 1, -0.5}, {0, 1, -0.5}};
  EXPECT_EQ(point_polygon_form_factor({0, 0, 0}, {0, 0, 1}, below), 0.0);
}

TEST(FormFactor, ParallelRectanglesConvergeToTheClosedForm) {
  // 1 x 2 rectangles, one above the other at distance 0.5, facing.
  const Patch lower = quad({0, 0, 0}, {1, 0, 0}, {1, 2, 0}, {0, 2, 0});
  const Patch upper = quad({0, 0, 0.5}, {0, 2, 0.5}, {1, 2, 0.5}, {1, 0, 0.5});
  const double want = parallel_rectangles_form_factor(1, 2, 0.5);
  double last = 1;
  for (int n : {4, 16, 64}) {
    const double err = std::abs(patch_form_factor(lower, upper, n) - want);
    std::printf("parallel 1x2 at 0.5: n %d error %.3g (closed form %.9f)\n", n, err, want);
    EXPECT_LT(err, last / 8) << "n " << n;  // 1/n^2: x16 a step, 8 allowed
    last = err;
  }
  EXPECT_LT(last, 6e-5);  // measured 4.45e-5
  // The unit cube's opposite faces: 0.1998248 (Howell C-11).
  EXPECT_NEAR(parallel_rectangles_form_factor(1, 1, 1), 0.1998248, 1e-7);
}

TEST(FormFactor, PerpendicularRectanglesConvergeToTheClosedForm) {
  // Floor 2 (along the edge) x 1, wall 2 x 1.5, sharing the edge y = 0.
  const Patch floor = quad({0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0});
  const Patch wall = quad({0, 0, 0}, {0, 0, 1.5}, {2, 0, 1.5}, {2, 0, 0});
  const double want = perpendicular_rectangles_form_factor(2, 1, 1.5);
  const double e8 = std::abs(patch_form_factor(floor, wall, 8) - want);
  const double e64 = std::abs(patch_form_factor(floor, wall, 64) - want);
  std::printf("perpendicular: n 8 error %.3g, n 64 error %.3g (closed form %.9f)\n", e8, e64, want);
  // The edge the two share makes the integrand singular (log): slower than 1/n^2.
  EXPECT_LT(e64, e8 / 4);
  EXPECT_LT(e64, 2e-3);
  // The unit cube's adjacent faces: 0.2000437 (Howell C-14).
  EXPECT_NEAR(perpendicular_rectangles_form_factor(1, 1, 1), 0.2000437, 1e-7);
}

TEST(FormFactor, Reciprocity) {
  // Two patches at an angle, neither touching: A_i F_ij = A_j F_ji within the rule's error.
  const Patch a = quad({0, 0, 0}, {1, 0, 0}, {1, 0.5, 0}, {0, 0.5, 0});
  Patch b;
  b.count = 3;
  b.v[0] = {0.2, 1.5, 1.0}, b.v[1] = {1.4, 1.2, 0.3}, b.v[2] = {0.5, 0.6, 2.0};
  if (dot(b.normal(), a.centre() - b.centre()) < 0) std::swap(b.v[1], b.v[2]);
  // Both sides are midpoint rules: their difference falls as 1/n^2.
  auto gap = [&](int n) {
    return std::abs(a.area() * patch_form_factor(a, b, n) - b.area() * patch_form_factor(b, a, n));
  };
  const double ab = a.area() * patch_form_factor(a, b, 64), g16 = gap(16), g64 = gap(64);
  std::printf("reciprocity: A_a F_ab %.9f; |A_a F_ab - A_b F_ba| n 16 %.3g, n 64 %.3g\n", ab, g16,
              g64);
  EXPECT_GT(ab, 0.01);
  EXPECT_LT(g64, g16 / 8);
  EXPECT_LT(g64, 5e-5 * ab);  // measured 2.7e-5
}

// The exact area-to-area form (Sparrow's double contour integral) against
// Howell's closed forms: parallel (no shared points), perpendicular (a
// shared edge: ln r singular on it), and far apart with moved origins.
TEST(FormFactor, ContourIntegralIsExact) {
  const Patch lower = quad({0, 0, 0}, {1, 0, 0}, {1, 2, 0}, {0, 2, 0});
  const Patch upper = quad({0, 0, 0.5}, {0, 2, 0.5}, {1, 2, 0.5}, {1, 0, 0.5});
  const Patch floor = quad({0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0});
  const Patch wall = quad({0, 0, 0}, {0, 0, 1.5}, {2, 0, 1.5}, {2, 0, 0});
  double worst = 0;
  auto check = [&](const char* what, double got, double want, double bound) {
    const double err = std::abs(got - want);
    worst = std::max(worst, err / want);
    std::printf("%s: exact %.15f closed form %.15f, error %.3g\n", what, got, want, err);
    EXPECT_LT(err, bound) << what;
  };
  check("parallel 1x2 at 0.5", polygon_form_factor(lower.corners(), upper.corners()),
        parallel_rectangles_form_factor(1, 2, 0.5), 1e-13);
  check("perpendicular 2x1 to 2x1.5", polygon_form_factor(floor.corners(), wall.corners()),
        perpendicular_rectangles_form_factor(2, 1, 1.5), 1e-12);
  check("perpendicular, the other way", polygon_form_factor(wall.corners(), floor.corners()),
        perpendicular_rectangles_form_factor(2, 1.5, 1), 1e-12);
  // The winding is the front: turned away, or behind the other's plane, or
  // in it, a polygon exchanges nothing.
  const std::vector<Vec3> reversed(upper.corners().rbegin(), upper.corners().rend());
  EXPECT_EQ(polygon_form_factor(lower.corners(), reversed), 0.0);
  const Patch below = quad({0, 0, -1}, {0, 2, -1}, {1, 2, -1}, {1, 0, -1});
  EXPECT_EQ(polygon_form_factor(lower.corners(), below.corners()), 0.0);
  EXPECT_EQ(polygon_form_factor(lower.corners(), floor.corners()), 0.0);  // coplanar
  // 1e4 and 1e6 from the origin, and small plates far apart (1/10 at 10: F ~ 3e-5).
  for (double o : {1e4, 1e6}) {
    const Vec3 d{o, -o, o};
    Patch a = lower, b = upper;
    for (int k = 0; k < 4; ++k) a.v[k] = a.v[k] + d, b.v[k] = b.v[k] + d;
    check(o == 1e4 ? "parallel, 1e4 away" : "parallel, 1e6 away", polygon_form_factor(a.corners(), b.corners()),
          parallel_rectangles_form_factor(1, 2, 0.5), 1e-14);  // measured 1.2e-15, 1.3e-15
  }
  const Patch tiny_a = quad({0, 0, 0}, {0.1, 0, 0}, {0.1, 0.1, 0}, {0, 0.1, 0});
  const Patch tiny_b = quad({0, 0, 10}, {0, 0.1, 10}, {0.1, 0.1, 10}, {0.1, 0, 10});
  check("0.1 plates at 10", polygon_form_factor(tiny_a.corners(), tiny_b.corners()),
        parallel_rectangles_form_factor(0.1, 0.1, 10), 1e-15);  // measured 1.9e-16 of F 3.2e-5: the contour terms cancel (distance / size 100)
  std::printf("worst relative error %.3g\n", worst);
  // Reciprocity at an angle, neither touching: to rounding.
  const Patch p = quad({0, 0, 0}, {1, 0, 0}, {1, 0.5, 0}, {0, 0.5, 0});
  const Patch q = quad({0.9, 1, 0.3}, {0.9, 1.3, 1.1}, {0.2, 1.3, 1.1}, {0.2, 1, 0.3});
  EXPECT_NEAR(p.area() * polygon_form_factor(p.corners(), q.corners()),
              q.area() * polygon_form_factor(q.corners(), p.corners()), 1e-14);
  // A floor patch and a block's face whose bottom edge lies in the floor's
  // plane (the Cornell box's, patches 48 and 285): reciprocal to rounding.
  // (A quadrature that counted a panel twice gave 0 one way, 0.081 the other.)
  const Patch floor_patch = quad({392.89795918367349, 0, 479.31428571428575}, {314.31836734693877, 0, 479.31428571428569},
                                 {314.05714285714288, 0, 559.20000000000005}, {392.57142857142861, 0, 559.20000000000005});
  const Patch block_face = quad({393, 0, 431}, {393, 82.5, 431}, {314, 82.5, 456}, {314, 0, 456});
  const double fb = polygon_form_factor(floor_patch.corners(), block_face.corners());
  const double bf = polygon_form_factor(block_face.corners(), floor_patch.corners());
  std::printf("floor patch to block face %.15f, back %.15f\n", fb, bf);
  EXPECT_NEAR(floor_patch.area() * fb, block_face.area() * bf, 1e-12 * floor_patch.area() * fb);
  EXPECT_NEAR(fb, patch_form_factor(floor_patch, block_face, 256), 1e-5);
  // Against the midpoint rule of the point form (converging as 1/n^2): within its error.
  EXPECT_NEAR(polygon_form_factor(p.corners(), q.corners()), patch_form_factor(p, q, 256), 1e-6);
}

// Lambert's point-to-polygon factor against an independent closed form:
// the coaxial disk, approached by regular N-gons inscribed in it (area short
// by 1 - sin(2 pi/N) N / (2 pi), the factor by about as much).
TEST(FormFactor, PointToRegularPolygonApproachesTheDisk) {
  const double r = 0.7, h = 1.3, want = point_disk_form_factor(r, h);
  double last = 1;
  for (int n : {16, 64, 256, 1024}) {
    std::vector<Vec3> poly;
    for (int k = 0; k < n; ++k) {
      const double a = 2 * std::numbers::pi * k / n;
      poly.push_back({r * std::cos(a), r * std::sin(a), h});
    }
    const double err = want - point_polygon_form_factor({0, 0, 0}, {0, 0, 1}, poly);
    std::printf("disk r %.1f at %.1f: %d-gon short by %.3g\n", r, h, n, err);
    EXPECT_GT(err, 0);
    EXPECT_LT(err, last / 15);  // 1/N^2: x16 a step
    last = err;
  }
  EXPECT_LT(last, 3e-6);
}

TEST(Enclosure, CubeRowsSumToOne) {
  const std::vector<Patch> p = closed_cube(3, 0.5, 1);
  const FormFactors f = centre_form_factors(p);
  const size_t n = p.size();
  double worst = 0;
  for (size_t i = 0; i < n; ++i) {
    double s = 0;
    for (size_t j = 0; j < n; ++j) s += f[i * n + j];
    worst = std::max(worst, std::abs(s - 1));
  }
  std::printf("cube 6 x 3 x 3 patches: largest |sum_j F_ij - 1| %.3g\n", worst);
  EXPECT_LT(worst, 1e-13);
}

TEST(Enclosure, EverySolverGivesEOverOneMinusRho) {
  const double rho = 0.7, e = 0.3;
  const std::vector<Patch> p = closed_cube(2, rho, e);
  const FormFactors f = centre_form_factors(p);
  for (RadiositySolver s :
       {RadiositySolver::jacobi, RadiositySolver::gauss_seidel, RadiositySolver::progressive}) {
    const SolveResult r = solve_radiosity(p, f, s, 1e-12, 100000);
    double worst = 0;
    for (const Vec3& b : r.b) worst = std::max(worst, std::abs(b.x - e / (1 - rho)));
    std::printf("solver %d: %d iterations, residual %.3g, largest |B - E/(1-rho)| %.3g\n", int(s),
                r.iterations, r.residual, worst);
    EXPECT_LT(worst, 1e-10) << "solver " << int(s);
  }
}

TEST(Solve, GaussSeidelTakesFewerSweepsThanJacobi) {
  std::vector<Patch> p = closed_cube(2, 0.8, 0);
  p[0].emission = {1, 1, 1};  // one light
  const FormFactors f = centre_form_factors(p);
  const SolveResult j = solve_radiosity(p, f, RadiositySolver::jacobi, 1e-9, 10000);
  const SolveResult g = solve_radiosity(p, f, RadiositySolver::gauss_seidel, 1e-9, 10000);
  std::printf("one light, rho 0.8: Jacobi %d sweeps, Gauss-Seidel %d\n", j.iterations,
              g.iterations);
  EXPECT_LE(j.residual, 1e-9);
  EXPECT_LE(g.residual, 1e-9);
  EXPECT_LT(g.iterations, j.iterations);
}

TEST(Solve, ReflectanceOfOneIsRefused) {
  std::vector<Patch> p = closed_cube(1, 0.5, 1);
  p[3].rho.y = 1.0;
  EXPECT_THROW(solve_radiosity(p, centre_form_factors(p), RadiositySolver::jacobi, 1e-9, 100),
               std::invalid_argument);
  p[3].rho.y = 0.5;
  p[2].emission.x = std::nan("");
  EXPECT_THROW(solve_radiosity(p, centre_form_factors(p), RadiositySolver::progressive, 1e-9, 100),
               std::invalid_argument);
}

TEST(Meshing, PiecesCoverThePolygonWithinTheArea) {
  const Vec3 q[4] = {{0, 0, 0}, {3, 0, 0}, {3.5, 2, 0}, {0, 2, 0}};
  const std::vector<Patch> pieces = mesh_polygon(q, {0.5, 0.5, 0.5}, {0, 0, 0}, 0.1, 7);
  double total = 0;
  for (const Patch& p : pieces) {
    EXPECT_LE(p.area(), 0.1 + 1e-12);
    EXPECT_NEAR(dot(p.normal(), Vec3{0, 0, 1}), 1.0, 1e-12);
    EXPECT_EQ(p.polygon, 7);
    total += p.area();
  }
  EXPECT_NEAR(total, 6.5, 1e-12);
  const Vec3 t[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 1}};
  const std::vector<Patch> tris = mesh_polygon(t, {0.5, 0.5, 0.5}, {0, 0, 0}, 0.01, 0);
  double tt = 0;
  for (const Patch& p : tris) tt += p.area();
  EXPECT_EQ(tris.size(), 256u);  // area 0.707: four halvings to 0.0028
  EXPECT_NEAR(tt, 0.5 * std::sqrt(2.0), 1e-12);
}

// Refinement (--error): a unit square cut 4 x 4, lit on its left half: the
// jump is between the two middle columns, so those 8 patches are cut in
// four and nothing else; areas and the polygon kept; a constant radiosity
// has no jump; the smallest size holds a patch.
TEST(Refine, CutsWhereNeighboursJumpAndNowhereElse) {
  const Vec3 q[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  PatchMesh mesh;
  mesh.patches = mesh_polygon(q, {0.5, 0.5, 0.5}, {0, 0, 0}, 1.0 / 16, 3);
  mesh.max_area = mesh.cut_area = 1.0 / 16;
  index_vertices(mesh);
  ASSERT_EQ(mesh.patches.size(), 16u);
  EXPECT_EQ(mesh.vertex.size(), 25u);
  std::vector<Vec3> b;
  for (const Patch& p : mesh.patches) b.push_back(p.centre().x < 0.5 ? Vec3{1, 1, 1} : Vec3{0, 0, 0});
  const std::vector<double> jump = radiosity_jumps(mesh, b);
  for (size_t i = 0; i < 16; ++i) {
    const double x = mesh.patches[i].centre().x;
    EXPECT_EQ(jump[i], std::abs(x - 0.5) < 0.25 ? 1.0 : 0.0) << "patch at x = " << x;
  }
  EXPECT_EQ(radiosity_jumps(mesh, std::vector<Vec3>(16, Vec3{2, 2, 2}))[5], 0.0);
  PatchMesh held = mesh;
  const Refined none = refine_patches(held, b, 0.5, 1.0 / 32);  // a quarter would be 1/64 < 1/32
  EXPECT_EQ(none.cut, 0u);
  EXPECT_EQ(none.held, 8u);
  const Refined r = refine_patches(mesh, b, 0.5, 1.0 / 256);
  EXPECT_EQ(r.cut, 8u);
  EXPECT_EQ(r.held, 0u);
  ASSERT_EQ(mesh.patches.size(), 16u + 8 * 3);
  double total = 0;
  size_t small = 0;
  for (const Patch& p : mesh.patches) {
    total += p.area();
    small += std::abs(p.area() - 1.0 / 64) < 1e-15;
    EXPECT_EQ(p.polygon, 3);
    EXPECT_NEAR(dot(p.normal(), Vec3{0, 0, 1}), 1.0, 1e-15);
  }
  EXPECT_NEAR(total, 1.0, 1e-15);
  EXPECT_EQ(small, 32u);
  EXPECT_EQ(mesh.cut_area, 1.0 / 64);
  EXPECT_EQ(mesh.corner.size(), mesh.patches.size());
  // Two columns cut in four add their midpoints: 25 + 2 x (4 + 5) ... every
  // corner a vertex, shared where corners meet.
  for (size_t k = 0; k < mesh.patches.size(); ++k)
    for (int c = 0; c < mesh.patches[k].count; ++c) {
      const Vec3 d = mesh.vertex[mesh.corner[k][size_t(c)]] - mesh.patches[k].v[c];
      EXPECT_EQ(length(d), 0.0);
    }
}

TEST(CornellBox, ReadsWithItsEmitterAndEveryPolygonFacesTheRoom) {
  const Scene s = read_nff(LOCKSTEP_CORPUS_DIR "/radiosity/cornell_box.nff");
  ASSERT_EQ(s.poly_material.size(), 16u);  // light, 5 walls, 2 blocks of 5 faces
  int emitters = 0;
  for (size_t i = 0; i < s.poly_material.size(); ++i) {
    const Material& m = s.materials[s.poly_material[i]];
    Vec3 c{0, 0, 0};
    const uint32_t first = s.poly_first[i], last = s.poly_first[i + 1];
    for (uint32_t k = first; k < last; ++k) c = c + s.vertex[k];
    c = c / double(last - first);
    const Vec3 n = s.poly_plane[i].n;
    // The light and the walls face the room's middle; the blocks' faces face
    // away from their block's middle.
    const Vec3 towards = i < 6 ? Vec3{278, 274, 280} - c
                         : i < 11 ? c - Vec3{186, 82, 168}
                                  : c - Vec3{368, 165, 351};
    EXPECT_GT(dot(n, towards), 0) << "polygon " << i;
    if (m.emission.x > 0) {
      ++emitters;
      EXPECT_NEAR(m.emission.x, 17 * M_PI, 1e-3);  // radiance 17 12 4, times pi
      EXPECT_NEAR(m.emission.y, 12 * M_PI, 1e-3);
      EXPECT_NEAR(m.emission.z, 4 * M_PI, 1e-3);
      EXPECT_NEAR(n.y, -1, 1e-12);  // the light shines down
    }
    EXPECT_LT(std::max({m.color.x, m.color.y, m.color.z}) * m.kd, 1.0) << "polygon " << i;
  }
  EXPECT_EQ(emitters, 1);
}

}  // namespace
}  // namespace lockstep
