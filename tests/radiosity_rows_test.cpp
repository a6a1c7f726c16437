// Radiosity's rows (reference/radiosity.h, optimized/radiosity_simd.h): the
// form factors each method computes, against the laws and closed forms of
// core/radiosity.h, and the simd row against the reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/radiosity.h"
#include "io/nff.h"
#include "optimized/radiosity_simd.h"
#include "reference/radiosity.h"

namespace lockstep {
namespace {

// The box [o, o + (a, b, c)] with every wall facing in; walls in the order
// floor (y = 0), ceiling, z = 0, z = c, x = 0, x = a.
Scene closed_box(const Vec3& o, double a, double b, double c) {
  Scene s;
  s.view.from = o + Vec3{a / 2, b / 2, c / 2};
  s.view.at = s.view.from + Vec3{0, 0, 1};
  Material m;
  m.color = {0.5, 0.5, 0.5};
  m.emission = {1, 1, 1};
  add_material(s, m);
  auto p = [&](double x, double y, double z) { return o + Vec3{x, y, z}; };
  const std::vector<std::vector<Vec3>> walls = {
      {p(0, 0, 0), p(a, 0, 0), p(a, 0, c), p(0, 0, c)},  // floor, facing +y
      {p(0, b, 0), p(0, b, c), p(a, b, c), p(a, b, 0)},  // ceiling, facing -y
      {p(0, 0, 0), p(0, b, 0), p(a, b, 0), p(a, 0, 0)},  // z = 0, facing +z
      {p(0, 0, c), p(a, 0, c), p(a, b, c), p(0, b, c)},  // z = c, facing -z
      {p(0, 0, 0), p(0, 0, c), p(0, b, c), p(0, b, 0)},  // x = 0, facing +x
      {p(a, 0, 0), p(a, b, 0), p(a, b, c), p(a, 0, c)},  // x = a, facing -x
  };
  for (const auto& w : walls) {
    const std::vector<Vec3> in(w.rbegin(), w.rend());  // listed facing out: reversed, they face in
    add_polygon(s, in, {}, 0);
  }
  return s;
}

double row_sum(const FormFactors& f, size_t n, size_t i) {
  double t = 0;
  for (size_t j = 0; j < n; ++j) t += f[i * n + j];
  return t;
}

double hemicube_total(int res) {
  const HemicubeWeights w = hemicube_weights(res);
  double top = 0, side = 0;
  for (double x : w.top) top += x;
  for (double x : w.side) side += x;
  return top + 4 * side;
}

// F from wall a to wall b: sum over a's patches of A_i sum_{j in b} F_ij, over A_a.
double wall_factor(const PatchMesh& m, const FormFactors& f, int a, int b) {
  const size_t n = m.patches.size();
  double num = 0, area = 0;
  for (size_t i = 0; i < n; ++i) {
    if (m.patches[i].polygon != a) continue;
    area += m.patches[i].area();
    for (size_t j = 0; j < n; ++j)
      if (m.patches[j].polygon == b) num += m.patches[i].area() * f[i * n + j];
  }
  return num / area;
}

struct Rows {
  FormFactors ref_rays, simd_rays, ref_cube, simd_cube, ref_exact, simd_exact;
};
Rows all_rows(const Scene& s, const PatchMesh& m, int k, int res) {
  const opt::embree::Device device = opt::embree::Device::create();
  const FormFactorMethod exact = FormFactorMethod::exact;
  return {ref::form_factors_rays(s, m, k),
          opt::simd::radiosity_form_factors_rays(s, m, k, 2, device),
          ref::form_factors_hemicube(m, res),
          opt::simd::radiosity_form_factors_hemicube(m, res, 2),
          ref::form_factors_rays(s, m, k, exact),
          opt::simd::radiosity_form_factors_rays(s, m, k, 2, device, {}, nullptr, exact)};
}

TEST(Hemicube, WeightsSumToOneAsTheResolutionGrows) {
  // The delta form factors are the midpoint rule of the hemisphere's
  // cosine-weighted measure: their total goes to 1 as 1/res^2.
  const double e16 = std::abs(hemicube_total(16) - 1), e64 = std::abs(hemicube_total(64) - 1),
               e256 = std::abs(hemicube_total(256) - 1);
  EXPECT_LT(e64, 1e-3);
  EXPECT_NEAR(e16 / e64, 16, 1.0);
  EXPECT_NEAR(e64 / e256, 16, 1.0);
}

// A closed box, moved far from the origin: from any patch's centre the other
// walls' patches cover the hemisphere, so a correct point-to-area method's
// rows sum to its total: 1 for Lambert's factors, W for the hemicube.
TEST(ClosedBox, RowsSumToOneByRaysAndToTheWeightsByHemicube) {
  for (const Vec3 o : {Vec3{0, 0, 0}, Vec3{1e4, -3e4, 2e4}}) {
    const Scene s = closed_box(o, 2, 3, 1.5);
    const PatchMesh m = mesh_scene(s, 0.2);
    const size_t n = m.patches.size();
    ASSERT_GT(n, 80u);
    const Rows r = all_rows(s, m, 2, 64);
    const double w = hemicube_total(64);
    double worst_rays = 0, worst_cube = 0, worst_exact = 0;
    for (size_t i = 0; i < n; ++i) {
      worst_rays = std::max({worst_rays, std::abs(row_sum(r.ref_rays, n, i) - 1), std::abs(row_sum(r.simd_rays, n, i) - 1)});
      worst_cube = std::max({worst_cube, std::abs(row_sum(r.ref_cube, n, i) - w), std::abs(row_sum(r.simd_cube, n, i) - w)});
      worst_exact =
          std::max({worst_exact, std::abs(row_sum(r.ref_exact, n, i) - 1), std::abs(row_sum(r.simd_exact, n, i) - 1)});
    }
    std::printf("offset %g: rows sum to 1 within %.3g (rays), %.3g (exact)\n", o.x, worst_rays, worst_exact);
    EXPECT_LT(worst_rays, 1e-12) << "offset " << o.x;
    EXPECT_LT(worst_cube, 1e-12) << "offset " << o.x;
    // Measured 1.4e-15; 3e4 away 5.2e-12: the corners themselves round there
    // (an ulp of 3e4 is 3.6e-12), so the patches tile the walls only so closely.
    EXPECT_LT(worst_exact, o.x == 0 ? 1e-14 : 1e-11) << "offset " << o.x;
    // The exact factors: the same scalar code in both rows, reciprocal.
    EXPECT_EQ(r.ref_exact, r.simd_exact);
    double gap = 0;
    for (size_t i = 0; i < n; ++i)
      for (size_t j = 0; j < n; ++j)
        gap = std::max(gap, std::abs(m.patches[i].area() * r.ref_exact[i * n + j] -
                                     m.patches[j].area() * r.ref_exact[j * n + i]));
    std::printf("offset %g: exact A_i F_ij - A_j F_ji at most %.3g\n", o.x, gap);
    EXPECT_LT(gap, 1e-15) << "offset " << o.x;  // measured 3.4e-17
    // No ray is blocked in an empty box: the simd row's factors are the
    // reference's but for its vector atan (3 ULP) and order of operations.
    double worst = 0;
    for (size_t k = 0; k < n * n; ++k)
      worst = std::max(worst, std::abs(r.ref_rays[k] - r.simd_rays[k]) / std::max(r.ref_rays[k], 1e-300));
    std::printf("offset %g: simd rays against the reference, largest relative difference %.3g\n", o.x, worst);
    EXPECT_LT(worst, 5e-14) << "offset " << o.x;  // measured 3.1e-14
    // The simd z-buffer draws the reference's item buffers (float depth): equal.
    EXPECT_EQ(r.ref_cube, r.simd_cube);
  }
}

// Wall to wall against Howell's closed forms (parallel and perpendicular
// rectangles): the error of a point-to-area method over patches of side h
// at distance d. Bounds are the measured errors with a margin of 1.5.
TEST(ClosedBox, WallFactorsAgainstClosedForms) {
  const double a = 2, b = 3, c = 1.5;
  const Scene s = closed_box({0, 0, 0}, a, b, c);
  const PatchMesh m = mesh_scene(s, 0.05);
  const Rows r = all_rows(s, m, 2, 64);
  const double floor_ceiling = parallel_rectangles_form_factor(a, c, b);
  // floor (a x c) to the wall z = 0 (a x b): common edge a, floor width c, wall height b.
  const double floor_wall = perpendicular_rectangles_form_factor(a, c, b);
  struct Got {
    const char* what;
    const FormFactors* f;
    double parallel_bound, perpendicular_bound, back_bound, gap_bound;
  };
  // Measured (patches of 0.05, k = 2, 64 pixels), floor to ceiling, floor
  // to wall, wall to floor, reciprocity gap: rays 1.07e-4, 3.2e-5, 9.0e-5,
  // 8.1e-4; hemicube (turned, hemicube_turn) 7.9e-5, 1.32e-4, 8.9e-5, 1.19e-3
  // (the same for both rows).
  // Exact: 2.4e-16, 2.0e-15, 1.4e-16, 8.9e-15.
  for (const Got& g : {Got{"reference exact", &r.ref_exact, 1e-15, 1e-14, 1e-15, 2e-14},
                       Got{"simd exact", &r.simd_exact, 1e-15, 1e-14, 1e-15, 2e-14},
                       Got{"reference rays", &r.ref_rays, 1.6e-4, 5e-5, 1.35e-4, 1.25e-3},
                       Got{"simd rays", &r.simd_rays, 1.6e-4, 5e-5, 1.35e-4, 1.25e-3},
                       Got{"reference hemicube", &r.ref_cube, 1.2e-4, 2e-4, 1.35e-4, 1.8e-3},
                       Got{"simd hemicube", &r.simd_cube, 1.2e-4, 2e-4, 1.35e-4, 1.8e-3}}) {
    const double fp = wall_factor(m, *g.f, 0, 1), fq = wall_factor(m, *g.f, 0, 2);
    std::printf("%-20s floor-ceiling %.6f (exact %.6f, error %.2e), floor-wall %.6f (exact %.6f, error %.2e)\n",
                g.what, fp, floor_ceiling, fp - floor_ceiling, fq, floor_wall, fq - floor_wall);
    EXPECT_NEAR(fp, floor_ceiling, g.parallel_bound) << g.what;
    EXPECT_NEAR(fq, floor_wall, g.perpendicular_bound) << g.what;
    // Back from the wall to the floor, and reciprocity of the walls' totals
    // (A_floor F_fw = A_wall F_wf holds for the exact factors).
    const double back = wall_factor(m, *g.f, 2, 0), back_exact = perpendicular_rectangles_form_factor(a, b, c);
    const double gap = (a * c * fq - a * b * back) / (a * c * floor_wall);
    std::printf("%-20s wall-floor %.6f (exact %.6f, error %.2e), reciprocity gap %.2e\n", g.what, back, back_exact,
                back - back_exact, gap);
    EXPECT_NEAR(back, back_exact, g.back_bound) << g.what;
    EXPECT_LT(std::abs(gap), g.gap_bound) << g.what;
  }
  // Patch by patch against the exact factors: the point-to-area methods'
  // own error, largest where patches meet at a corner (proximity).
  const size_t n = m.patches.size();
  auto row_error = [&](const FormFactors& f) {
    double worst = 0;
    for (size_t i = 0; i < n; ++i) {
      double e = 0;
      for (size_t j = 0; j < n; ++j) e += std::abs(f[i * n + j] - r.ref_exact[i * n + j]);
      worst = std::max(worst, e);
    }
    return worst;
  };
  const double rays = row_error(r.ref_rays), cube = row_error(r.ref_cube);
  std::printf("%zu patches: max_i sum_j |F_ij - exact|: rays %.3g, hemicube %.3g\n", n, rays, cube);
  EXPECT_LT(rays, 0.067);  // measured 0.0556
  EXPECT_LT(cube, 0.2);    // measured 0.166
}

}  // namespace
}  // namespace lockstep

namespace lockstep {
namespace {

// The Cornell box (its blocks occlude): the simd row's rays factors against
// the reference's. Both decide each segment by the same exact predicate
// (the simd row only where a shade says it may be hidden): equal but for
// rounding in the unoccluded factors.
TEST(CornellBox, SimdRaysAgreeWithTheReference) {
  const Scene s = read_nff(LOCKSTEP_CORPUS_DIR "/radiosity/cornell_box.nff");
  const PatchMesh m = mesh_scene(s, 0);
  const size_t n = m.patches.size();
  const FormFactors a = ref::form_factors_rays(s, m, 2);
  const FormFactors b =
      opt::simd::radiosity_form_factors_rays(s, m, 2, 2, opt::embree::Device::create());
  size_t visibility = 0, blocked = 0;
  double rounding = 0;
  for (size_t k = 0; k < n * n; ++k) {
    blocked += a[k] == 0 && b[k] == 0 && centre_form_factor(m, k / n, k % n) > 0;
    // A ray's share of a factor worth a pixel is far above 1e-12; rounding
    // is far below (absolute: the near-coplanar patches of the measured,
    // slightly warped walls have factors of 1e-9 and less, all cancellation).
    const double diff = std::abs(a[k] - b[k]);
    if (diff > 1e-12) ++visibility;
    else rounding = std::max(rounding, diff);
  }
  std::printf("%zu patches: %zu pairs wholly blocked; %zu factors differ by a ray (%.3g%%); rounding %.3g absolute\n", n,
              blocked, visibility, 100.0 * double(visibility) / double(n * n), rounding);
  EXPECT_GT(blocked, n * n / 20);  // the blocks do block
  EXPECT_EQ(visibility, 0u);
  EXPECT_LT(rounding, 1e-15);
}

// The side output --patches: made only when asked, the mesh_scene patches
// with the solution the image shows; the two rows' solutions agree.
TEST(CornellBox, PatchesSideOutputIsTheSolution) {
  const Scene s = read_nff(LOCKSTEP_CORPUS_DIR "/radiosity/cornell_box.nff");
  FrameOptions o;
  o.width = o.height = 16;
  o.params.set("patch_area", "8000");
  FrameStats plain;
  opt::simd::radiosity(s, o, &plain);
  EXPECT_TRUE(plain.sides.empty());
  o.sides = {"patches"};
  FrameStats rs, ss;
  ref::radiosity(s, o, &rs);
  opt::simd::radiosity(s, o, &ss);
  ASSERT_EQ(rs.sides.size(), 1u);
  ASSERT_EQ(ss.sides.size(), 1u);
  EXPECT_EQ(rs.sides[0].first, "patches");
  const PatchSolution& a = output_as<PatchSolution>(rs.sides[0].second);
  const PatchSolution& b = output_as<PatchSolution>(ss.sides[0].second);
  const PatchMesh m = mesh_scene(s, 8000);
  ASSERT_EQ(a.mesh.patches.size(), m.patches.size());
  ASSERT_EQ(a.b.size(), m.patches.size());
  ASSERT_EQ(b.b.size(), m.patches.size());
  EXPECT_EQ(a.vertex_b, vertex_radiosity(a.mesh, a.b));
  double worst = 0, brightest = 0;
  for (size_t k = 0; k < a.b.size(); ++k) {
    worst = std::max({worst, std::abs(a.b[k].x - b.b[k].x), std::abs(a.b[k].y - b.b[k].y),
                      std::abs(a.b[k].z - b.b[k].z)});
    brightest = std::max(brightest, a.b[k].x);
  }
  std::printf("%zu patches: simd against reference %.3g (largest B %.3g)\n", a.b.size(), worst, brightest);
  EXPECT_GT(brightest, 1.0);  // the light: its emission is pi x its radiance
  // Equal factors, the same Gauss-Seidel sweeps, but the simd row's sweeps
  // read the factors rounded to float (2^-24 relative each): measured 3.05e-8
  // (5.7e-10 of the brightest B); in double it was 6.7e-16. Sweeps in
  // another order (the simd row's Jacobi, tried) differ by 5.8e-3.
  EXPECT_LT(worst, 1e-9 * brightest);
}

// The simd row decides visibility by shadow polygons (each blocker's shade
// on a receiver's plane; the exact predicate near a shade's edge), the
// reference by testing every triangle: the same answers, pair by pair, in
// rooms cluttered with what the shades must handle: convex quads seen whole,
// triangles, a non-convex L, warped quads (shaded per triangle; as
// receivers, their targets projected), a plate a hair above the floor (the
// floor's patches too near its plane for shades: Embree decides those), at
// the origin, 1e4 and 1e8 away (where rounding's reach outgrows the shades:
// Embree decides), at two scales.
TEST(Clutter, SimdShadowsAgreeWithTheReference) {
  for (const double offset : {0.0, 1e4, 1e8})
    for (const double scale : {1.0, 300.0})
      for (uint64_t seed = 1; seed <= 3; ++seed) {
        const Vec3 o{offset, -offset / 2, offset / 3};
        Scene s = closed_box(o, 4 * scale, 3 * scale, 5 * scale);
        uint64_t state = seed * 0x9e3779b97f4a7c15ull;
        auto uniform = [&] {
          state = state * 6364136223846793005ull + 1442695040888963407ull;
          return double(state >> 11) / double(1ull << 53);
        };
        auto at = [&](double x, double y, double z) { return o + Vec3{x, y, z} * scale; };
        auto random_point = [&] { return at(0.5 + 3 * uniform(), 0.3 + 2.4 * uniform(), 0.5 + 4 * uniform()); };
        auto add = [&](const std::vector<Vec3>& v) { add_polygon(s, v, {}, 0); };
        for (int k = 0; k < 4; ++k) {  // convex planar quads in random orientations
          const Vec3 c = random_point();
          const Vec3 u = normalize(Vec3{uniform() - 0.5, uniform() - 0.5, uniform() - 0.5}) * (0.4 * scale);
          const Vec3 w = normalize(cross(u, Vec3{uniform() - 0.5, uniform() - 0.5, uniform() - 0.5})) * (0.3 * scale);
          add({c - u - w, c + u - w, c + u + w, c - u + w});
        }
        for (int k = 0; k < 3; ++k) {  // triangles
          const Vec3 c = random_point();
          auto jitter = [&] { return Vec3{uniform() - 0.5, uniform() - 0.5, uniform() - 0.5} * (0.8 * scale); };
          add({c + jitter(), c + jitter(), c + jitter()});
        }
        {  // a non-convex L, level
          const Vec3 c = random_point();
          auto p = [&](double x, double z) { return c + Vec3{x, 0, z} * scale; };
          add({p(0, 0), p(0, 0.6), p(0.2, 0.6), p(0.2, 0.2), p(0.6, 0.2), p(0.6, 0)});
        }
        for (int k = 0; k < 2; ++k) {  // warped quads: a corner lifted by 2% of the side
          const Vec3 c = random_point();
          add({c, c + Vec3{0.5, 0, 0} * scale, c + Vec3{0.5, 0.01, 0.5} * scale, c + Vec3{0, 0, 0.5} * scale});
        }
        add({at(1, 1e-7, 1), at(1, 1e-7, 2), at(2, 1e-7, 2), at(2, 1e-7, 1)});  // a plate just above the floor
        const PatchMesh m = mesh_scene(s, 0);
        const size_t n = m.patches.size();
        const FormFactors a = ref::form_factors_rays(s, m, 2);
        opt::simd::RayCounts counts;
        const FormFactors b =
            opt::simd::radiosity_form_factors_rays(s, m, 2, 2, opt::embree::Device::create(), {}, &counts);
        size_t differ = 0, blocked = 0;
        double rounding = 0;
        for (size_t k = 0; k < n * n; ++k) {
          const double diff = std::abs(a[k] - b[k]);
          blocked += a[k] < centre_form_factor(m, k / n, k % n);
          if (diff > 1e-12) {
            if (differ++ < 3)
              std::printf("  offset %g scale %g seed %llu: F[%zu][%zu] reference %.17g simd %.17g\n", offset, scale,
                          (unsigned long long)seed, k / n, k % n, a[k], b[k]);
          } else {
            rounding = std::max(rounding, diff);
          }
        }
        std::printf("offset %g scale %g seed %llu: %zu patches, %zu pairs partly blocked, %zu differ; %llu shade "
                    "tests, %llu segments by Embree\n",
                    offset, scale, (unsigned long long)seed, n, blocked, differ, (unsigned long long)counts.shaded,
                    (unsigned long long)counts.rays);
        EXPECT_GT(blocked, n * n / 50);  // the clutter does block
        // Up to 1e4 out the shades take the segments; at 1e8 rounding's reach
        // (1e-12 of 1e8 in height) outgrows the small room's slab and Embree
        // takes them all (centred, its float agrees here too); the large
        // room's are shared.
        if (offset <= 1e4) EXPECT_GT(counts.shaded, counts.rays);
        EXPECT_EQ(differ, 0u);
        EXPECT_LT(rounding, 1e-15);
      }
}

// --error E on the Cornell box ("model no more than a scene needs"): the
// refined mesh, started from 305 patches, puts its patches where the
// radiosity changes (shadow boundaries, the blocks' feet, the corners), so
// its image's largest error against a fine uniform solution (15,000-odd
// patches) is well below that of a uniform mesh with more patches, its rms
// error no worse; both rows cut the same patches.
TEST(CornellBox, RefinementBeatsUniformPatchesAtEqualCount) {
  const Scene s = read_nff(LOCKSTEP_CORPUS_DIR "/radiosity/cornell_box.nff");
  auto frame = [&](double area, const char* error, FrameStats* st, bool reference = false) {
    FrameOptions o;
    o.width = o.height = 96;
    o.params.set("patch_area", std::to_string(area));
    if (error) o.params.set("error", error);
    return reference ? ref::radiosity(s, o, st) : opt::simd::radiosity(s, o, st);
  };
  auto patches = [](const FrameStats& st) {
    for (const auto& [name, value] : st.counts)
      if (name == "patches") return value;
    return uint64_t(0);
  };
  FrameStats fs;
  const Image fine = frame(250, nullptr, &fs);
  struct Error {
    double max = 0, rms = 0;
  };
  auto error = [&](const Image& im) {
    Error e;
    for (size_t k = 0; k < im.rgba.size(); ++k) {
      const double d = double(im.rgba[k]) - double(fine.rgba[k]);
      e.max = std::max(e.max, std::abs(d)), e.rms += d * d;
    }
    e.rms = std::sqrt(e.rms / double(im.rgba.size()));
    return e;
  };
  FrameStats as, rs;
  const Image adaptive = frame(8000, "0.05", &as);
  frame(8000, "0.05", &rs, true);
  EXPECT_EQ(patches(as), patches(rs));  // the rows' solutions agree, so their cuts do
  const uint64_t n = patches(as);
  // Uniform meshes from 305 patches up, until one has at least n.
  Error uniform;
  uint64_t uniform_n = 0;
  for (double area = 8000; uniform_n < n; area /= 1.25) {
    FrameStats us;
    const Image u = frame(area, nullptr, &us);
    uniform_n = patches(us), uniform = error(u);
  }
  const Error refined = error(adaptive);
  std::printf("refined to %llu patches: image error max %.4g rms %.4g; uniform %llu patches: max %.4g rms %.4g "
              "(against %llu)\n",
              (unsigned long long)n, refined.max, refined.rms, (unsigned long long)uniform_n, uniform.max, uniform.rms,
              (unsigned long long)patches(fs));
  EXPECT_GT(n, 305u);
  EXPECT_LT(refined.max, 0.8 * uniform.max);
  EXPECT_LT(refined.rms, uniform.rms);
}

}  // namespace
}  // namespace lockstep
