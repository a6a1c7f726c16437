// lockstep props/raster: the interpolation lessons, measured (part
// "interpolation", on the scanline family; fixed tests with a fixed seed, each
// prints what it measured and fails when it is over its bound).
//
//   Interpolation.barycentric_weights   area-ratio barycentrics sum to 1 and
//       reproduce the vertices' values; so do the weights the scanline
//       interpolates (perspective-correct: divided by their sum, so 1 within a
//       few ulps; affine: within the drift).
//   Interpolation.span_drift   incremental 1/z and bilinear weights along spans
//       of 16..4096 pixels against direct evaluation (long double, from the exact
//       edge functions): the reference in double, and the simd's depth lanes in
//       float; a table span length -> max drift; bounds linear in the length.
//   Interpolation.quad_rotation   bilinear (scanline) interpolation over a quad
//       changes when the quad turns on screen; barycentric over a triangle does not.
//   Interpolation.perspective_oracle   the scanline's perspective-correct
//       weights equal the exact ones (the eye-space ray-plane intersection in long
//       double) for any depth ratio; affine weights do not, and their error grows
//       with z_far / z_near of the triangle (a table).
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <random>

#include "optimized/scanline_simd.h"
#include "props/raster/parts.h"
#include "reference/scanline.h"

namespace lockstep::props::raster {

namespace {

constexpr uint64_t kSeed = 0x5ca11e5;

using LD = long double;

// A mesh of the given triangles (snapped coordinates, 1/256 pixel; depths).
ScreenMesh mesh_of(int w, int h, const std::vector<std::array<ScreenVertex, 3>>& tris) {
  ScreenMesh m;
  m.width = w;
  m.height = h;
  m.near_z = 0.5;
  m.far_z = 1000;
  for (auto t : tris) {
    const int64_t a =
        int64_t(t[1].x - t[0].x) * (t[2].y - t[0].y) - int64_t(t[1].y - t[0].y) * (t[2].x - t[0].x);
    if (a == 0) continue;
    if (a < 0) std::swap(t[1], t[2]);
    ScreenTri st;
    st.v = t;
    m.tris.push_back(st);
  }
  return m;
}

ScreenVertex vtx(int64_t x, int64_t y, double z) {
  ScreenVertex v;
  v.x = int32_t(x);
  v.y = int32_t(y);
  v.z = z;
  return v;
}

// Sample index -> position in 1/256 pixel.
std::array<int64_t, 2> sample_position(const ScreenMesh& m, const RasterSettings& s, size_t index) {
  const auto offsets = sample_offsets(s);
  const size_t spp = offsets.size();
  const size_t k = index % spp, p = index / spp;
  const int64_t i = int64_t(p % size_t(m.width)), j = int64_t(p / size_t(m.width));
  return {i * kSubpixel + offsets[k][0], j * kSubpixel + offsets[k][1]};
}

// Direct evaluation: the screen barycentrics from the exact integer edge
// functions, 1/z, and the perspective-correct weights, in long double.
struct Direct {
  LD l[3], b[3], w;
};
Direct direct(const ScreenTri& t, int64_t px, int64_t py) {
  auto e = [&](const ScreenVertex& a, const ScreenVertex& b) {
    return LD(int64_t(b.x - a.x) * (py - a.y) - int64_t(b.y - a.y) * (px - a.x));
  };
  const LD area = LD(int64_t(t.v[1].x - t.v[0].x) * (t.v[2].y - t.v[0].y) -
                     int64_t(t.v[1].y - t.v[0].y) * (t.v[2].x - t.v[0].x));
  Direct d;
  d.l[0] = e(t.v[1], t.v[2]) / area;
  d.l[1] = e(t.v[2], t.v[0]) / area;
  d.l[2] = e(t.v[0], t.v[1]) / area;
  d.w = d.l[0] / LD(t.v[0].z) + d.l[1] / LD(t.v[1].z) + d.l[2] / LD(t.v[2].z);
  for (int k = 0; k < 3; ++k) d.b[k] = d.l[k] / LD(t.v[k].z) / d.w;
  return d;
}

// ---------------------------------------------------------------- barycentric weights

void barycentric_weights() {
  std::mt19937_64 rng(kSeed);
  std::uniform_real_distribution<double> U(-100, 100), V(-5, 5);
  // 1. Area ratios: sum to 1, reproduce vertex values (exactly at the vertices).
  // The sum's error is relative to the triangle's conditioning: each area is
  // a difference of products of coordinates, so its rounding is about
  // eps * (size of the coordinates)^2, divided by the triangle's area.
  double worst_sum = 0, worst_ratio = 0;
  for (int n = 0; n < 20000; ++n) {
    ref::ScreenValue a{U(rng), U(rng), V(rng)}, b{U(rng), U(rng), V(rng)},
        c{U(rng), U(rng), V(rng)};
    const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (area == 0) continue;
    const double size = std::max(
        {std::abs(a.x), std::abs(a.y), std::abs(b.x), std::abs(b.y), std::abs(c.x), std::abs(c.y)});
    const double kappa = size * size / std::abs(area);
    // A point inside: random convex weights.
    const double r1 = std::uniform_real_distribution<double>(0, 1)(rng),
                 r2 = std::uniform_real_distribution<double>(0, 1)(rng);
    const double s = std::sqrt(r1);
    const double px = (1 - s) * a.x + s * (1 - r2) * b.x + s * r2 * c.x,
                 py = (1 - s) * a.y + s * (1 - r2) * b.y + s * r2 * c.y;
    const auto w = ref::barycentric(a, b, c, px, py);
    const double err = std::abs(w[0] + w[1] + w[2] - 1);
    worst_sum = std::max(worst_sum, err);
    worst_ratio = std::max(worst_ratio, err / (DBL_EPSILON * kappa));
    ASSERT_LE(err, 8 * DBL_EPSILON * kappa) << "seed " << kSeed << " case " << n
                                            << ": |sum - 1| = " << err << " at condition " << kappa;
    const ref::ScreenValue* v[3] = {&a, &b, &c};
    for (int k = 0; k < 3; ++k) {
      const auto at = ref::barycentric(a, b, c, v[k]->x, v[k]->y);
      const double value = at[0] * a.value + at[1] * b.value + at[2] * c.value;
      ASSERT_EQ(value, v[k]->value)
          << "seed " << kSeed << " case " << n << ": vertex " << k << " of (" << a.x << "," << a.y
          << ") (" << b.x << "," << b.y << ") (" << c.x << "," << c.y << ")";
    }
  }
  std::printf(
      "[ lockstep ] area-ratio barycentrics: max |sum - 1| = %.3g over 20000 triangles, at most "
      "%.3g eps x "
      "(size^2 / area) (bound 8); vertex values reproduced exactly\n",
      worst_sum, worst_ratio);

  // 2. The scanline's weights on random meshes: perspective-correct weights
  // are divided by their sum (1 within a few ulps); affine weights are three
  // independent incremental sums (1 within their drift). Where a sample lies
  // exactly on a vertex the weights are that vertex's unit vector within the drift.
  for (bool perspective : {true, false}) {
    double sum_err = 0, vertex_err = 0;
    int vertex_samples = 0;
    for (int n = 0; n < 200; ++n) {
      std::uniform_int_distribution<int> C(
          -2, 34);  // half pixels: vertices on pixel centres half the time
      std::uniform_real_distribution<double> Z(1, 20);
      std::vector<std::array<ScreenVertex, 3>> tris;
      for (int t = 0; t < 6; ++t)
        tris.push_back({vtx(C(rng) * 128, C(rng) * 128, Z(rng)),
                        vtx(C(rng) * 128, C(rng) * 128, Z(rng)),
                        vtx(C(rng) * 128, C(rng) * 128, Z(rng))});
      const ScreenMesh m = mesh_of(16, 16, tris);
      RasterSettings s;
      s.perspective = perspective;
      ref::scanline_fragments(m, s, [&](size_t index, const Fragment& f) {
        sum_err = std::max(sum_err, std::abs(f.b[0] + f.b[1] + f.b[2] - 1));
        const auto p = sample_position(m, s, index);
        for (int k = 0; k < 3; ++k)
          if (m.tris[f.tri].v[k].x == p[0] && m.tris[f.tri].v[k].y == p[1]) {
            ++vertex_samples;
            for (int q = 0; q < 3; ++q)
              vertex_err = std::max(vertex_err, std::abs(f.b[q] - (q == k ? 1.0 : 0.0)));
          }
      });
    }
    const double sum_bound = perspective ? 4 * DBL_EPSILON : 1e-13;
    std::printf(
        "[ lockstep ] scanline %s weights: max |sum - 1| = %.3g (bound %.3g); at %d samples on a "
        "vertex, "
        "max |b - e_k| = %.3g (bound 1e-14)\n",
        perspective ? "perspective-correct" : "affine", sum_err, sum_bound, vertex_samples,
        vertex_err);
    EXPECT_LE(sum_err, sum_bound) << "seed " << kSeed;
    EXPECT_LE(vertex_err, 1e-14) << "seed " << kSeed;
    EXPECT_GT(vertex_samples, 100) << "the meshes must put vertices on samples";
  }
}

// ---------------------------------------------------------------- drift along long spans

void span_drift() {
  std::printf(
      "[ lockstep ] drift of incremental interpolation against direct evaluation, by span length\n"
      "  (simd: float lanes, error in units of 2^-24 max|d| over the triangle)\n"
      "  span px | ref |b - b_direct| | ref |z/z_direct - 1| | simd float window depth | simd "
      "reversed n/z\n");
  const int lengths[] = {16, 64, 256, 1024, 4096};
  for (int L : lengths) {
    // A tall, wide triangle: each of the 4 rows holds a span of about L pixels;
    // depth from 1 to 40 across it (the far vertex on the right).
    const ScreenMesh m =
        mesh_of(L, 4,
                {{vtx(-64, -256 * 2 * L, 1.0), vtx(int64_t(L) * 256 + 200, 512, 40.0),
                  vtx(-64, 256 * 2 * L, 3.0)}});
    RasterSettings s;
    double b_err = 0, z_err = 0;
    ref::scanline_fragments(m, s, [&](size_t index, const Fragment& f) {
      const auto p = sample_position(m, s, index);
      const Direct d = direct(m.tris[f.tri], p[0], p[1]);
      for (int k = 0; k < 3; ++k) b_err = std::max(b_err, double(std::abs(LD(f.b[k]) - d.b[k])));
      z_err = std::max(z_err, double(std::abs(LD(f.z) * d.w - 1)));
    });
    // The simd's depth lanes, in float, against the exact stored depth
    // (unrounded): in units of u * max |d| with u = 2^-24 and d over the
    // triangle's vertices (every value on a span lies between them), the
    // error an affine evaluation in float cannot avoid.
    double units[2] = {0, 0};
    for (int r = 0; r < 2; ++r) {
      RasterSettings sf;
      sf.depth = r ? DepthFormat::kReversed : DepthFormat::kFloat;
      const LD n = m.near_z, fz = m.far_z;
      auto stored = [&](LD w) { return r ? n * w : (1 / n - w) / (1 / n - 1 / fz); };
      LD scale = 0;
      for (const ScreenVertex& v : m.tris[0].v)
        scale = std::max(scale, std::abs(stored(1 / LD(v.z))));
      Visibility vis;
      opt::simd::scanline_visibility(m, sf, 1, vis);
      for (size_t x = 0; x < vis.tri.size(); ++x) {
        if (vis.tri[x] == Visibility::kNone) continue;
        const auto p = sample_position(m, sf, x);
        const Direct d = direct(m.tris[vis.tri[x]], p[0], p[1]);
        units[r] = std::max(units[r], double(std::abs(LD(vis.depth[x]) - stored(d.w)) /
                                             (scale * std::ldexp(LD(1), -24))));
      }
    }
    std::printf("  %7d | %18.3g | %21.3g | %23.3g | %19.3g\n", L, b_err, z_err, units[0], units[1]);
    // Bounds, linear in the span length: the reference's double sums drift by
    // a few ulps of the values they carry per step (measured: at most about 4 L u,
    // u = 2^-53); the simd's float lanes round by at most half a unit per
    // vector step of N lanes (N = 16 on AVX-512, 8 on AVX2), so L / 2N units.
    const double ref_bound = 8 * L * std::ldexp(1.0, -53);
    EXPECT_LE(b_err, ref_bound) << "span " << L << ": reference weights drift over " << ref_bound;
    EXPECT_LE(z_err, ref_bound) << "span " << L << ": reference 1/z drift over " << ref_bound;
    const double simd_bound = 2 + L / (2.0 * double(opt::simd::scanline_lanes()));
    EXPECT_LE(units[0], simd_bound)
        << "span " << L << ": simd float depth drift over " << simd_bound;
    EXPECT_LE(units[1], simd_bound)
        << "span " << L << ": simd reversed depth drift over " << simd_bound;
  }
}

// ---------------------------------------------------------------- quad rotation

void quad_rotation() {
  // A quad with values that are not on one plane (a bilinear patch), and the
  // triangle of its first three vertices. Both turn about the centre (0, 0),
  // with the point p where the value is read.
  const ref::ScreenValue quad[4] = {{-10, -6, 0}, {9, -8, 1}, {11, 7, 0}, {-8, 9, 3}};
  const double p0x = 1.5, p0y = 0.5;
  std::printf(
      "[ lockstep ] the value at a fixed point of the shape, as the shape turns on screen\n"
      "  angle deg | bilinear over the quad | barycentric over the triangle\n");
  double bl_lo = kInfinity, bl_hi = -kInfinity, ba_lo = kInfinity, ba_hi = -kInfinity;
  for (int deg = 0; deg < 360; deg += 15) {
    const double a = deg * 3.14159265358979323846 / 180, c = std::cos(a), s = std::sin(a);
    ref::ScreenValue q[4];
    for (int k = 0; k < 4; ++k)
      q[k] = {c * quad[k].x - s * quad[k].y, s * quad[k].x + c * quad[k].y, quad[k].value};
    const double px = c * p0x - s * p0y, py = s * p0x + c * p0y;
    const double bl = ref::bilinear_polygon(q, px, py);
    const auto w = ref::barycentric(q[0], q[1], q[2], px, py);
    const double ba = w[0] * q[0].value + w[1] * q[1].value + w[2] * q[2].value;
    // Over a triangle the scanline's bilinear interpolation is barycentric interpolation.
    const double bl_tri = ref::bilinear_polygon(std::span<const ref::ScreenValue>(q, 3), px, py);
    EXPECT_NEAR(bl_tri, ba, 1e-12)
        << "angle " << deg << ": bilinear over the triangle " << bl_tri << " != barycentric " << ba;
    std::printf("  %9d | %22.15f | %29.15f\n", deg, bl, ba);
    bl_lo = std::min(bl_lo, bl), bl_hi = std::max(bl_hi, bl);
    ba_lo = std::min(ba_lo, ba), ba_hi = std::max(ba_hi, ba);
  }
  std::printf("  spread: bilinear %.4g (must be > 0.1), barycentric %.3g (must be <= 1e-13)\n",
              bl_hi - bl_lo, ba_hi - ba_lo);
  EXPECT_GT(bl_hi - bl_lo, 0.1)
      << "bilinear interpolation of the quad did not depend on its orientation";
  EXPECT_LE(ba_hi - ba_lo, 1e-13) << "barycentric interpolation depended on the orientation";
}

// ---------------------------------------------------------------- perspective against the exact
// oracle

void perspective_oracle() {
  // A triangle in eye space seen through a pinhole (focal length 64 pixels,
  // centre (32, 32)): its vertices' screen positions (snapped) and depths z_k;
  // the eye-space vertices are P_k = ((x_k - 32) z_k / 64, (y_k - 32) z_k / 64, z_k).
  // Oracle: the ray through the sample meets the triangle's plane at Q; the
  // weights are the 3D area ratios of Q (long double).
  std::printf(
      "[ lockstep ] weights against the exact ray-plane oracle, by the triangle's depth ratio "
      "z_far/z_near\n"
      "  ratio | affine max |b - b_exact| | perspective max |b - b_exact|\n");
  const double ratios[] = {1, 1.25, 2, 4, 10, 100};
  double prev_affine = -1;
  for (double ratio : ratios) {
    const double z[3] = {1, ratio, std::sqrt(ratio)};
    const ScreenMesh m =
        mesh_of(64, 64,
                {{vtx(2 * 256 + 17, 3 * 256 + 5, z[0]), vtx(60 * 256 + 3, 10 * 256 + 200, z[1]),
                  vtx(20 * 256 + 99, 61 * 256 + 31, z[2])}});
    const ScreenTri& t = m.tris[0];
    LD P[3][3];
    for (int k = 0; k < 3; ++k) {
      P[k][0] = (LD(t.v[k].x) / 256 - 32) * LD(t.v[k].z) / 64;
      P[k][1] = (LD(t.v[k].y) / 256 - 32) * LD(t.v[k].z) / 64;
      P[k][2] = LD(t.v[k].z);
    }
    auto sub = [](const LD* a, const LD* b, LD* o) {
      for (int i = 0; i < 3; ++i) o[i] = a[i] - b[i];
    };
    auto crs = [](const LD* a, const LD* b, LD* o) {
      o[0] = a[1] * b[2] - a[2] * b[1];
      o[1] = a[2] * b[0] - a[0] * b[2];
      o[2] = a[0] * b[1] - a[1] * b[0];
    };
    auto dt = [](const LD* a, const LD* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    LD e1[3], e2[3], n[3];
    sub(P[1], P[0], e1);
    sub(P[2], P[0], e2);
    crs(e1, e2, n);
    double err[2] = {0, 0};
    for (int interp = 0; interp < 2; ++interp) {
      RasterSettings s;
      s.perspective = interp == 1;
      ref::scanline_fragments(m, s, [&](size_t index, const Fragment& f) {
        const auto p = sample_position(m, s, index);
        const LD d[3] = {(LD(p[0]) / 256 - 32) / 64, (LD(p[1]) / 256 - 32) / 64, 1};
        const LD tq = dt(n, P[0]) / dt(n, d);
        const LD Q[3] = {tq * d[0], tq * d[1], tq * d[2]};
        for (int k = 0; k < 3; ++k) {
          LD a[3], b[3], c[3];
          sub(P[(k + 1) % 3], Q, a);
          sub(P[(k + 2) % 3], Q, b);
          crs(a, b, c);
          const LD exact = dt(n, c) / dt(n, n);
          err[interp] = std::max(err[interp], double(std::abs(LD(f.b[k]) - exact)));
        }
      });
    }
    std::printf("  %5g | %25.3g | %30.3g\n", ratio, err[0], err[1]);
    EXPECT_LE(err[1], 1e-13) << "ratio " << ratio
                             << ": perspective-correct weights off the oracle by " << err[1];
    if (ratio == 1) {
      EXPECT_LE(err[0], 1e-13) << "equal depths: affine must equal perspective-correct";
    } else {
      EXPECT_GT(err[0], 0.01) << "ratio " << ratio
                              << ": affine weights should be visibly wrong, off by " << err[0];
      EXPECT_GE(err[0], prev_affine) << "affine error should grow with the depth ratio";
    }
    prev_affine = err[0];
  }
}

}  // namespace

void interpolation_part(const Family& family, FamilyProperties& out) {
  out.fixed.push_back({"Interpolation", "barycentric_weights", barycentric_weights});
  out.fixed.push_back({"Interpolation", "span_drift", span_drift});
  out.fixed.push_back({"Interpolation", "quad_rotation", quad_rotation});
  out.fixed.push_back({"Interpolation", "perspective_oracle", perspective_oracle});
}

}  // namespace lockstep::props::raster
