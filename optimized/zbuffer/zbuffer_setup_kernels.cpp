// Z-buffer set-up kernels, Highway SIMD (declared in zbuffer_simd_kernels.h):
// the steps of opt::simd's set-up (zbuffer_setup.cpp and its parts) that run a
// vector of vertices, faces or triangles at a time, with the reference's
// double operations in the reference's order (no contraction: the build has
// -ffp-contract=off), so the same bits:
//   ball_entries       the hidden spheres' occluders, a row of corner rays;
//   grow_bounds        the scene's bounds;
//   sphere_faces,      the spheres' world face tests;
//   sphere_face_codes
//   project_vertices   the vertex step: eye space, clip test, snapped position;
//   triangle_step      the image's triangle step (degenerate, culled, empty, hidden);
//   set_up_forward,    the binner's TriSetups (and the shading's planes);
//   set_up_shaded
//   polygon_run        runs of one-triangle polygons, projected and set up.
#include "optimized/zbuffer/zbuffer_simd_kernels.h"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cmath>
#include <cstdlib>

// foreach_target.h first: it re-includes this file once per target.
// clang-format off
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "optimized/zbuffer/zbuffer_setup_kernels.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "optimized/zbuffer/zbuffer_simd_kernels-inl.h"
// clang-format on

HWY_BEFORE_NAMESPACE();
namespace lockstep::opt::zsimd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// ---------------------------------------------------------------- hidden spheres, bounds, faces

void BallEntries(const double ce[3], double rho2, bool inverted, double z_occ, double pitch,
                 double half_w, double dy, int cell, int a0, int n, double* out) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const int N = int(hn::Lanes(d));
  const V cx = hn::Set(d, ce[0]), zero = hn::Zero(d);
  const double c2 = ce[0] * ce[0] + ce[1] * ce[1] + ce[2] * ce[2];
  // dot(d, d) and dot(ce, d) without their x terms: the same along the row.
  const V yz2 = hn::Set(d, dy * dy + 1.0), cyz = hn::Set(d, ce[1] * dy + ce[2]);
  const V vc2 = hn::Set(d, c2), vrho2 = hn::Set(d, rho2), inf = hn::Set(d, HUGE_VAL);
  const V lane = hn::Iota(d, 0.0);
  for (int i = 0; i < n; i += N) {
    // The ray through corner a = a0 + i + lane: its distance to the centre.
    const V a = hn::Add(hn::Set(d, double(a0 + i)), lane);
    const V dx = hn::Mul(hn::Sub(hn::Mul(a, hn::Set(d, double(cell))), hn::Set(d, half_w)),
                         hn::Set(d, pitch));
    const V len2 = hn::MulAdd(dx, dx, yz2), t = hn::MulAdd(cx, dx, cyz);
    const V miss2 = hn::Sub(vc2, hn::Div(hn::Mul(t, t), len2));
    const auto meets = hn::And(hn::Gt(t, zero), hn::Lt(miss2, vrho2));
    // Entry at t / |d| - sqrt(rho^2 - miss^2) along the unit ray; eye depth that / |d|.
    const V len = hn::Sqrt(len2);
    const V entry =
        inverted ? hn::Set(d, z_occ)
                 : hn::Div(hn::Sub(hn::Div(t, len), hn::Sqrt(hn::Max(zero, hn::Sub(vrho2, miss2)))),
                           len);
    const V v = hn::IfThenElse(meets, entry, inf);
    if (i + N <= n) {
      hn::StoreU(v, d, out + i);
    } else {
      HWY_ALIGN double tmp[16];
      hn::Store(v, d, tmp);
      for (int k = 0; i + k < n; ++k) out[i + k] = tmp[k];
    }
  }
}

void GrowBounds(const Vec3* points, size_t n, Vec3& lo, Vec3& hi) {
  const hn::ScalableTag<double> d;
  const size_t N = hn::Lanes(d);
  size_t i = 0;
  if (n >= N) {
    hn::Vec<decltype(d)> l[3], h[3];
    for (int c = 0; c < 3; ++c) l[c] = hn::Set(d, lo[c]), h[c] = hn::Set(d, hi[c]);
    for (; i + N <= n; i += N) {
      hn::Vec<decltype(d)> p[3];
      hn::LoadInterleaved3(d, &points[i].x, p[0], p[1], p[2]);
      for (int c = 0; c < 3; ++c) {  // std::min(l, p) = p < l ? p : l, and the like
        l[c] = hn::IfThenElse(hn::Lt(p[c], l[c]), p[c], l[c]);
        h[c] = hn::IfThenElse(hn::Lt(h[c], p[c]), p[c], h[c]);
      }
    }
    HWY_ALIGN double bl[3][16], bh[3][16];
    for (int c = 0; c < 3; ++c) hn::Store(l[c], d, bl[c]), hn::Store(h[c], d, bh[c]);
    for (size_t k = 0; k < N; ++k)
      for (int c = 0; c < 3; ++c)
        lo[c] = std::min(lo[c], bl[c][k]), hi[c] = std::max(hi[c], bh[c][k]);
  }
  for (; i < n; ++i)
    for (int c = 0; c < 3; ++c)
      lo[c] = std::min(lo[c], points[i][c]), hi[c] = std::max(hi[c], points[i][c]);
}

void SphereFaces(const Vec3* world, const std::array<uint32_t, 3>* tri, size_t n, bool flip,
                 const Vec3& eye, double* face, uint8_t* flags) {
  const hn::ScalableTag<double> d;
  const hn::RebindToSigned<decltype(d)> di;
  using V = hn::Vec<decltype(d)>;
  const size_t N = hn::Lanes(d);
  const double* base = &world[0].x;
  const V ex = hn::Set(d, eye.x), ey = hn::Set(d, eye.y), ez = hn::Set(d, eye.z);
  const V zero = hn::Zero(d);
  HWY_ALIGN int64_t at[3][8];
  HWY_ALIGN double out[4][8];
  const int b = flip ? 2 : 1, c = flip ? 1 : 2;
  for (size_t i = 0; i < n; i += N) {
    const size_t m = std::min(N, n - i);
    for (size_t k = 0; k < N; ++k) {  // the tail repeats the last triangle
      const auto& t = tri[i + std::min(k, m - 1)];
      at[0][k] = 3 * int64_t(t[0]), at[1][k] = 3 * int64_t(t[b]), at[2][k] = 3 * int64_t(t[c]);
    }
    V w[3][3];  // vertex, coordinate
    for (int v = 0; v < 3; ++v) {
      const auto idx = hn::Load(di, at[v]);
      for (int x = 0; x < 3; ++x) w[v][x] = hn::GatherIndex(d, base + x, idx);
    }
    // cross(w1 - w0, w2 - w0), its length, the unit normal: core/math.h's operations.
    V e1[3], e2[3];
    for (int x = 0; x < 3; ++x)
      e1[x] = hn::Sub(w[1][x], w[0][x]), e2[x] = hn::Sub(w[2][x], w[0][x]);
    const V fn[3] = {hn::Sub(hn::Mul(e1[1], e2[2]), hn::Mul(e1[2], e2[1])),
                     hn::Sub(hn::Mul(e1[2], e2[0]), hn::Mul(e1[0], e2[2])),
                     hn::Sub(hn::Mul(e1[0], e2[1]), hn::Mul(e1[1], e2[0]))};
    const V len = hn::Sqrt(
        hn::Add(hn::Add(hn::Mul(fn[0], fn[0]), hn::Mul(fn[1], fn[1])), hn::Mul(fn[2], fn[2])));
    const V un[3] = {hn::Div(fn[0], len), hn::Div(fn[1], len), hn::Div(fn[2], len)};
    const V to_eye[3] = {hn::Sub(ex, w[0][0]), hn::Sub(ey, w[0][1]), hn::Sub(ez, w[0][2])};
    const V facing = hn::Add(hn::Add(hn::Mul(un[0], to_eye[0]), hn::Mul(un[1], to_eye[1])),
                             hn::Mul(un[2], to_eye[2]));
    for (int x = 0; x < 3; ++x) hn::Store(un[x], d, out[x]);
    hn::Store(hn::IfThenElse(hn::Eq(len, zero), hn::Set(d, double(kNoFace)),
                             hn::IfThenElseZero(hn::Gt(facing, zero), hn::Set(d, double(kFront)))),
              d, out[3]);
    for (size_t k = 0; k < m; ++k) {
      for (int x = 0; x < 3; ++x) face[3 * (i + k) + size_t(x)] = out[x][k];
      flags[i + k] = uint8_t(out[3][k]);
    }
  }
}

// ---------------------------------------------------------------- the set-up's vertex step
//
// core/viewing.cpp's eye_from_world, inside_all and to_screen on N
// vertices at once, with the very same double operations in the same order
// (no fused multiply-add: the build has -ffp-contract=off), so the same bits;
// llround as trunc plus a correction (exact: x - trunc(x) is exact). The tail
// (fewer than N vertices) runs the same lanes on a padded copy.
// One vector of vertices (world coordinates wx, wy, wz): eye depth ez, the
// snapped x and y (0 where not inside), inside, and with depth w = 1/z and the
// stored depth q.
template <class D, class V = hn::Vec<D>>
struct ProjectLanes {
  D d;
  V eye[3], rt[3], up[3], fw[3];
  V near_z, g, zero, half_w, half_h, pitch, sub, half, one;
  V dm_near, dm_inv_near, dm_range;
  bool reversed = false;
  ProjectLanes(D d_, const Projection& p, const DepthMap* depth) : d(d_) {
    for (int c = 0; c < 3; ++c) {
      eye[c] = hn::Set(d, p.eye[c]), rt[c] = hn::Set(d, p.right[c]);
      up[c] = hn::Set(d, p.up[c]), fw[c] = hn::Set(d, p.forward[c]);
    }
    near_z = hn::Set(d, p.near_z), g = hn::Set(d, p.g), zero = hn::Zero(d);
    half_w = hn::Set(d, p.half_w), half_h = hn::Set(d, p.half_h), pitch = hn::Set(d, p.pitch);
    sub = hn::Set(d, double(kSubpixel)), half = hn::Set(d, 0.5), one = hn::Set(d, 1.0);
    dm_near = hn::Set(d, depth ? depth->near_z : 1.0);
    dm_inv_near = hn::Set(d, depth ? depth->inv_near : 1.0);
    dm_range = hn::Set(d, depth ? depth->range : 1.0);
    reversed = depth && depth->reversed;
  }
  static V dot(const V a[3], const V b[3]) {  // (a.x b.x + a.y b.y) + a.z b.z, as Vec3's dot
    return hn::Add(hn::Add(hn::Mul(a[0], b[0]), hn::Mul(a[1], b[1])), hn::Mul(a[2], b[2]));
  }
  V round_half_away(V x) const {
    const V t = hn::Trunc(x);
    const V f = hn::Sub(x, t);
    return hn::Sub(hn::Add(t, hn::IfThenElseZero(hn::Ge(f, half), one)),
                   hn::IfThenElseZero(hn::Le(f, hn::Neg(half)), one));
  }
  // The eye depth, snapped position and clip test of the vertices w.
  HWY_INLINE void position(const V w[3], V& ez, V& x, V& y, hn::Mask<D>& inside) const {
    const V dv[3] = {hn::Sub(w[0], eye[0]), hn::Sub(w[1], eye[1]), hn::Sub(w[2], eye[2])};
    const V ex = dot(dv, rt), ey = dot(dv, up);
    ez = dot(dv, fw);
    const V gz = hn::Mul(g, ez);
    inside = hn::And(hn::And(hn::Ge(hn::Sub(ez, near_z), zero), hn::Ge(hn::Sub(gz, ex), zero)),
                     hn::And(hn::And(hn::Ge(hn::Add(gz, ex), zero), hn::Ge(hn::Sub(gz, ey), zero)),
                             hn::Ge(hn::Add(gz, ey), zero)));
    const V den = hn::Mul(ez, pitch);
    const V sx = hn::Add(half_w, hn::Div(ex, den));
    const V sy = hn::Sub(half_h, hn::Div(ey, den));
    x = round_half_away(hn::IfThenElseZero(inside, hn::Mul(sx, sub)));
    y = round_half_away(hn::IfThenElseZero(inside, hn::Mul(sy, sub)));
  }
  // DepthMap: w = 1/z, then (1/n - w) / range or n / z.
  HWY_INLINE void depth(V ez, V& w, V& q) const {
    w = hn::Div(one, ez);
    q = reversed ? hn::Div(dm_near, ez) : hn::Div(hn::Sub(dm_inv_near, w), dm_range);
  }
};

void ProjectVertices(const Projection& p, const Vec3* world, size_t n, ProjectedVertex* out,
                     const DepthMap* depth, VertexDepth* depth_out) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const size_t N = hn::Lanes(d);
  const ProjectLanes<decltype(d)> proj(d, p, depth);
  const V one = hn::Set(d, 1.0);
  HWY_ALIGN double zs[16], xs[16], ys[16], ins[16], ws[16], qs[16];
  HWY_ALIGN double pad[3 * 16];
  for (size_t i = 0; i < n; i += N) {
    const size_t m = std::min(N, n - i);
    const double* src = &world[i].x;
    if (m < N) {  // the tail: a copy padded with the last vertex
      for (size_t k = 0; k < N; ++k)
        for (int c = 0; c < 3; ++c) pad[3 * k + c] = world[i + std::min(k, m - 1)][c];
      src = pad;
    }
    V w[3];
    hn::LoadInterleaved3(d, src, w[0], w[1], w[2]);
    V ez, x, y;
    hn::Mask<decltype(d)> inside;
    proj.position(w, ez, x, y, inside);
    hn::Store(ez, d, zs);
    hn::Store(x, d, xs);
    hn::Store(y, d, ys);
    hn::Store(hn::IfThenElseZero(inside, one), d, ins);
    if (depth) {
      V wv, q;
      proj.depth(ez, wv, q);
      hn::Store(wv, d, ws);
      hn::Store(q, d, qs);
      for (size_t k = 0; k < m; ++k) depth_out[i + k] = {ws[k], qs[k]};
    }
    for (size_t k = 0; k < m; ++k) {
      ProjectedVertex& o = out[i + k];
      o.z = zs[k];
      o.x = int32_t(int64_t(xs[k]));
      o.y = int32_t(int64_t(ys[k]));
      o.inside = ins[k] != 0;
    }
  }
}

// SampleGrid::pixels for a vector of triangles of vertices (x[k], y[k]) (the
// floor and ceiling of / 256 are shifts): triangle_step's and set_up_forward's.
template <class DI, class VI = hn::Vec<DI>>
HWY_INLINE void PixelBox(DI di, const SampleGrid& grid, const VI x[3], const VI y[3], VI& i0,
                         VI& i1, VI& j0, VI& j1) {
  static_assert(kSubpixel == 256);
  const VI zero = hn::Zero(di), round = hn::Set(di, kSubpixel - 1);
  const VI xmin = hn::Min(hn::Min(x[0], x[1]), x[2]), xmax = hn::Max(hn::Max(x[0], x[1]), x[2]);
  const VI ymin = hn::Min(hn::Min(y[0], y[1]), y[2]), ymax = hn::Max(hn::Max(y[0], y[1]), y[2]);
  i0 = hn::Max(zero, hn::ShiftRight<8>(hn::Add(hn::Sub(xmin, hn::Set(di, grid.ox1)), round)));
  i1 = hn::Min(hn::Set(di, grid.width - 1), hn::ShiftRight<8>(hn::Sub(xmax, hn::Set(di, grid.ox0))));
  j0 = hn::Max(zero, hn::ShiftRight<8>(hn::Add(hn::Sub(ymin, hn::Set(di, grid.oy1)), round)));
  j1 = hn::Min(hn::Set(di, grid.height - 1), hn::ShiftRight<8>(hn::Sub(ymax, hn::Set(di, grid.oy0))));
}

// One sample per pixel (grid.ox0 == ox1, oy0 == oy1): the triangles of a
// vector (vertices x[k], y[k] in the raster's order, box i0..j1 from PixelBox)
// that are small (vertices within 16 px of each other both ways, a box of at
// most 3 x 3 samples) and cover none of their box's samples: E_k >= bias_k
// for no sample and every edge k, the raster's own test (set_up_forward's
// edges). Such a triangle draws nothing. (Edge values there are below 2^25:
// int32.) 3 x 3: on balls-3 (AVX2, callgrind) 2 x 2 catches too few, 4 x 4
// costs more than the triangles it sorts out save.
// The raster's edges of a vector of triangles (vertices x[k], y[k] in its
// order): edge k from vertex a = k + 1 to b = k + 2, E_k = ex (X - x_a) +
// ey (Y - y_a), a sample covered where E_k >= bias_k (0 on a top or left
// edge, else 1): set_up_forward's and CoversNothing's.
template <class DI, class VI = hn::Vec<DI>>
HWY_INLINE void Edges(DI di, const VI x[3], const VI y[3], VI ex[3], VI ey[3], VI bias[3]) {
  const VI zero = hn::Zero(di);
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    const VI dx = hn::Sub(x[b], x[a]), dy = hn::Sub(y[b], y[a]);
    ex[k] = hn::Neg(dy), ey[k] = dx;
    const auto top_left = hn::Or(hn::And(hn::Eq(dy, zero), hn::Gt(dx, zero)), hn::Lt(dy, zero));
    bias[k] = hn::IfThenZeroElse(top_left, hn::Set(di, 1));
  }
}

template <class DI, class VI = hn::Vec<DI>>
HWY_INLINE hn::Mask<DI> CoversNothing(DI di, const SampleGrid& grid, const VI x[3], const VI y[3],
                                      const VI edge_x[3], const VI edge_y[3], const VI bias[3],
                                      VI i0, VI i1, VI j0, VI j1) {
  static_assert(kSubpixel == 256);
  constexpr int kSide = 3;
  const VI zero = hn::Zero(di), side = hn::Set(di, kSide);
  const VI limit = hn::Set(di, 16 * kSubpixel);
  const VI xmin = hn::Min(hn::Min(x[0], x[1]), x[2]), xmax = hn::Max(hn::Max(x[0], x[1]), x[2]);
  const VI ymin = hn::Min(hn::Min(y[0], y[1]), y[2]), ymax = hn::Max(hn::Max(y[0], y[1]), y[2]);
  const auto small =
      hn::And(hn::And(hn::Lt(hn::Sub(xmax, xmin), limit), hn::Lt(hn::Sub(ymax, ymin), limit)),
              hn::And(hn::Lt(hn::Sub(i1, i0), side), hn::Lt(hn::Sub(j1, j0), side)));
  if (hn::AllFalse(di, small)) return small;
  // Covered where E_k >= bias_k, i.e. E_k > bias_k - 1.
  VI ex[3], ey[3], floor_e[3];
  for (int k = 0; k < 3; ++k)
    ex[k] = edge_x[k], ey[k] = edge_y[k], floor_e[k] = hn::Sub(bias[k], hn::Set(di, 1));
  // The edges at the box's first sample, then stepped: 256 ex a column, 256 ey a row.
  const VI sx0 = hn::Add(hn::ShiftLeft<8>(i0), hn::Set(di, grid.ox0));
  const VI sy0 = hn::Add(hn::ShiftLeft<8>(j0), hn::Set(di, grid.oy0));
  VI row_e[3];
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3;
    row_e[k] = hn::Add(hn::Mul(ex[k], hn::Sub(sx0, x[a])), hn::Mul(ey[k], hn::Sub(sy0, y[a])));
    ex[k] = hn::ShiftLeft<8>(ex[k]), ey[k] = hn::ShiftLeft<8>(ey[k]);
  }
  // Columns and rows past the box's own: never covered.
  const VI cols = hn::Sub(i1, i0), rows = hn::Sub(j1, j0);
  auto covered = hn::Not(hn::Eq(zero, zero));
  for (int r = 0; r < kSide; ++r) {
    const auto row_in = hn::Gt(rows, hn::Set(di, r - 1));
    VI e[3] = {row_e[0], row_e[1], row_e[2]};
    for (int c = 0; c < kSide; ++c) {
      auto in = hn::And(row_in, hn::Gt(cols, hn::Set(di, c - 1)));
      for (int k = 0; k < 3; ++k) {
        in = hn::And(in, hn::Gt(e[k], floor_e[k]));
        e[k] = hn::Add(e[k], ex[k]);
      }
      covered = hn::Or(covered, in);
    }
    if (hn::AllTrue(di, hn::Or(covered, hn::Not(small)))) break;
    for (int k = 0; k < 3; ++k) row_e[k] = hn::Add(row_e[k], ey[k]);
  }
  return hn::AndNot(covered, small);
}

// triangle_step: the vertices' first 16 bytes a lane (ProjectedVertex: z at
// double 0, x and y at int32 2 and 3 of its 24 bytes), LoadPairs, not gathers;
// the area exact in double as in int64. The kept triangles are compressed to
// the front of the arrays as they are found (at most as far as the vector
// just read).
// Whether everything at eye depth >= z_min with its samples in pixels
// [i0, i1] x [j0, j1] loses to the occluders, from the coarse cells
// (zbuffer_setup's OcclusionMap::hidden, the same test).
bool CoarseHidden(const OcclusionCells& occ, int i0, int i1, int j0, int j1, double z_min) {
  static_assert(kOcclusionCell == 4);
  double beyond = -HUGE_VAL;
  const double* coarse = occ.beyond + occ.coarse;
  for (int b = j0 / 8; b <= j1 / 8; ++b)
    for (int a = i0 / 8; a <= i1 / 8; ++a)
      beyond = std::max(beyond, coarse[size_t(b) * size_t(occ.coarse_nx) + size_t(a)]);
  return z_min > beyond;
}

size_t TriangleStep(const ProjectedVertex* pv, uint32_t* a, uint32_t* b, uint32_t* c,
                    uint32_t* tag, size_t n, const SampleGrid& grid, bool cull_projection,
                    const OcclusionCells* occ, TriangleCounts& counts) {
  static_assert(sizeof(ProjectedVertex) == 24 && offsetof(ProjectedVertex, x) == 8 &&
                offsetof(ProjectedVertex, y) == 12 && offsetof(ProjectedVertex, z) == 0);
  const hn::CappedTag<double, 8> dd;
  const hn::Rebind<int32_t, decltype(dd)> di;
  const hn::Rebind<uint32_t, decltype(dd)> du;
  using VD = hn::Vec<decltype(dd)>;
  using VI = hn::Vec<decltype(di)>;
  const size_t N = hn::Lanes(dd);
  const hn::Rebind<uint64_t, decltype(dd)> d64;
  const double* zs = reinterpret_cast<const double*>(pv);
  const VI two = hn::Set(di, 2);
  const VI zero_i = hn::Zero(di);
  const VI lane = hn::Iota(di, 0);
  const VD zero = hn::Zero(dd);
  const bool one_sample = grid.ox0 == grid.ox1 && grid.oy0 == grid.oy1;
  size_t kept = 0;
  for (size_t i = 0; i < n; i += N) {
    const auto ib = hn::LoadU(du, b + i), ic = hn::LoadU(du, c + i);
    VI x[3], y[3];
    VD z[3];
    const uint32_t* const index[3] = {a + i, b + i, c + i};
    for (int k = 0; k < 3; ++k) {
      // Word 0 of the vertex's three 8-byte words: z; word 1: x (low half) and y.
      VD xyd;
      LoadPairs(dd, [&](int l) { return zs + 3 * size_t(index[k][l]); }, z[k], xyd);
      const auto xy = hn::BitCast(d64, xyd);
      x[k] = hn::BitCast(di, hn::TruncateTo(du, xy));
      y[k] = hn::BitCast(di, hn::TruncateTo(du, hn::ShiftRight<32>(xy)));
    }
    // (p1.x - p0.x)(p2.y - p0.y) - (p1.y - p0.y)(p2.x - p0.x), exactly.
    const VD area =
        hn::Sub(hn::Mul(hn::PromoteTo(dd, hn::Sub(x[1], x[0])), hn::PromoteTo(dd, hn::Sub(y[2], y[0]))),
                hn::Mul(hn::PromoteTo(dd, hn::Sub(y[1], y[0])), hn::PromoteTo(dd, hn::Sub(x[2], x[0]))));
    VI i0, i1, j0, j1;
    PixelBox(di, grid, x, y, i0, i1, j0, j1);
    const VD zlo = hn::Min(hn::Min(z[0], z[1]), z[2]);
    // The area's sign in int32 lanes.
    const VI sign = hn::DemoteTo(
        di, hn::IfThenElse(hn::Gt(area, zero), hn::Set(dd, 1.0),
                           hn::IfThenElseZero(hn::Lt(area, zero), hn::Set(dd, -1.0))));
    // Negative area: b and c swapped (the raster's order).
    const auto swap = hn::Lt(sign, zero_i);
    // What drops a triangle, most specific first: degenerate (zero area),
    // culled (positive area, projection culling), no sample (uncounted).
    const auto in_range = hn::Lt(lane, hn::Set(di, int32_t(std::min(N, n - i))));
    const auto degenerate = hn::And(in_range, hn::Eq(sign, zero_i));
    auto left = hn::AndNot(degenerate, in_range);  // (not yet dropped)
    if (cull_projection) {
      const auto culled = hn::And(left, hn::Gt(sign, zero_i));
      counts.culled += hn::CountTrue(di, culled);
      left = hn::AndNot(culled, left);
    }
    counts.degenerate += hn::CountTrue(di, degenerate);
    auto none = hn::Or(hn::Gt(i0, i1), hn::Gt(j0, j1));
    if (one_sample) {  // (or a small triangle that covers no sample in it)
      const VI xs[3] = {x[0], hn::IfThenElse(swap, x[2], x[1]), hn::IfThenElse(swap, x[1], x[2])};
      const VI ys[3] = {y[0], hn::IfThenElse(swap, y[2], y[1]), hn::IfThenElse(swap, y[1], y[2])};
      VI ex[3], ey[3], bias[3];
      Edges(di, xs, ys, ex, ey, bias);
      none = hn::Or(none, CoversNothing(di, grid, xs, ys, ex, ey, bias, i0, i1, j0, j1));
    }
    auto keep = hn::AndNot(none, left);
    if (occ && !hn::AllFalse(di, keep)) {
      // The cells of the box's corners (a box within 2 x 2 cells has no others):
      // fine ones, else coarse ones.
      static_assert(kOcclusionCell == 4);
      VI a0 = hn::ShiftRight<2>(i0), a1 = hn::ShiftRight<2>(i1);
      VI b0 = hn::ShiftRight<2>(j0), b1 = hn::ShiftRight<2>(j1);
      const auto fine = hn::And(hn::Lt(hn::Sub(a1, a0), two), hn::Lt(hn::Sub(b1, b0), two));
      const VI ca0 = hn::ShiftRight<3>(i0), ca1 = hn::ShiftRight<3>(i1);
      const VI cb0 = hn::ShiftRight<3>(j0), cb1 = hn::ShiftRight<3>(j1);
      const auto coarse = hn::And(hn::Lt(hn::Sub(ca1, ca0), two), hn::Lt(hn::Sub(cb1, cb0), two));
      const auto near = hn::And(keep, hn::Or(fine, coarse));
      auto hidden = hn::FirstN(di, 0);
      if (!hn::AllFalse(di, near)) {
        a0 = hn::IfThenElse(fine, a0, ca0), a1 = hn::IfThenElse(fine, a1, ca1);
        b0 = hn::IfThenElse(fine, b0, cb0), b1 = hn::IfThenElse(fine, b1, cb1);
        const VI nx = hn::IfThenElse(fine, hn::Set(di, occ->nx), hn::Set(di, occ->coarse_nx));
        const VI at = hn::IfThenElseZero(hn::Not(fine), hn::Set(di, occ->coarse));
        const VI row0 = hn::Add(at, hn::Mul(b0, nx)), row1 = hn::Add(at, hn::Mul(b1, nx));
        // Cells a0 and a0 + 1 of both rows, two at a time (LoadPairs; a1 is
        // a0 or a0 + 1: where it is a0, cell a0 + 1 is read and ignored: the
        // map has a cell of slack at its end). (Lanes not tested read cell 0.)
        HWY_ALIGN int32_t cell[2][8];
        hn::Store(hn::IfThenElseZero(near, hn::Add(row0, a0)), di, cell[0]);
        hn::Store(hn::IfThenElseZero(near, hn::Add(row1, a0)), di, cell[1]);
        const auto one_column = CastMask(dd, di, hn::Eq(a1, a0));
        VD beyond = hn::Set(dd, -HUGE_VAL);
        for (int r = 0; r < 2; ++r) {
          VD left_cell, right_cell;
          LoadPairs(dd, [&](int l) { return occ->beyond + cell[r][l]; }, left_cell, right_cell);
          beyond = hn::Max(beyond, hn::Max(left_cell, hn::IfThenElse(one_column, left_cell, right_cell)));
        }
        hidden = hn::And(near, CastMask(di, dd, hn::Gt(zlo, beyond)));
      }
      // Wider boxes: the coarse cells one triangle at a time (few: the large triangles).
      const auto wide = hn::AndNot(hn::Or(fine, coarse), keep);
      if (!hn::AllFalse(di, wide)) {
        HWY_ALIGN int32_t bx[4][8];
        HWY_ALIGN double zl[8];
        hn::Store(i0, di, bx[0]), hn::Store(i1, di, bx[1]);
        hn::Store(j0, di, bx[2]), hn::Store(j1, di, bx[3]);
        hn::Store(zlo, dd, zl);
        HWY_ALIGN int32_t wide_hidden[8];
        hn::Store(hn::VecFromMask(di, wide), di, wide_hidden);
        for (size_t l = 0; l < N; ++l)
          if (wide_hidden[l])
            wide_hidden[l] = CoarseHidden(*occ, bx[0][l], bx[1][l], bx[2][l], bx[3][l], zl[l]) ? -1 : 0;
        hidden = hn::Or(hidden, hn::Gt(zero_i, hn::Load(di, wide_hidden)));
      }
      counts.hidden += hn::CountTrue(di, hidden);
      keep = hn::AndNot(hidden, keep);
    }
    // The kept ones to the front (kept <= i: everything from kept on that the
    // stores may write has been read).
    const auto keep_u = hn::RebindMask(du, keep);
    const auto swap_u = hn::RebindMask(du, swap);
    hn::CompressStore(hn::LoadU(du, a + i), keep_u, du, a + kept);
    hn::CompressStore(hn::IfThenElse(swap_u, ic, ib), keep_u, du, b + kept);
    hn::CompressStore(hn::IfThenElse(swap_u, ib, ic), keep_u, du, c + kept);
    kept += hn::CompressStore(hn::LoadU(du, tag + i), keep_u, du, tag + kept);
  }
  return kept;
}

#if HWY_TARGET <= HWY_AVX3
// AVX-512: eight TriSetups written from their fields' lanes by an 8 x 8
// transpose of 8-byte words in registers (instead of a scalar loop over the
// fields, which was ~45% of set_up_forward). Triangle j's words: int32 fields
// in pairs for its first cache line (ax, ay, ex, ey, the box as int16s, the
// biases as bytes, then zeros), doubles for the second (q0, qx, qy, w0, wx, wy,
// then the flat colour 0 and the padding). Writes the first m.
HWY_INLINE void Transpose8x8(__m512i r[8]) {
  __m512i a[8];
  for (int k = 0; k < 4; ++k) {
    a[2 * k] = _mm512_unpacklo_epi64(r[2 * k], r[2 * k + 1]);  // words 2b of rows 2k, 2k + 1
    a[2 * k + 1] = _mm512_unpackhi_epi64(r[2 * k], r[2 * k + 1]);
  }
  // Column 2b + p (p = 0, 1) is the 16-byte block b of a[p], a[2 + p], a[4 + p], a[6 + p].
  for (int p = 0; p < 2; ++p) {
    const __m512i b0 = _mm512_shuffle_i64x2(a[p], a[2 + p], 0x44);      // blocks 0 1 | 0 1
    const __m512i b1 = _mm512_shuffle_i64x2(a[p], a[2 + p], 0xEE);      // 2 3 | 2 3
    const __m512i b2 = _mm512_shuffle_i64x2(a[4 + p], a[6 + p], 0x44);
    const __m512i b3 = _mm512_shuffle_i64x2(a[4 + p], a[6 + p], 0xEE);
    r[p] = _mm512_shuffle_i64x2(b0, b2, 0x88);      // blocks 0 of all four
    r[2 + p] = _mm512_shuffle_i64x2(b0, b2, 0xDD);  // blocks 1
    r[4 + p] = _mm512_shuffle_i64x2(b1, b3, 0x88);  // blocks 2
    r[6 + p] = _mm512_shuffle_i64x2(b1, b3, 0xDD);  // blocks 3
  }
}

HWY_INLINE void WriteSetUps(const int32_t (*x)[8], const int32_t (*y)[8], const int32_t (*ex)[8],
                            const int32_t (*ey)[8], const int32_t (*bias)[8],
                            const int32_t (*box)[8], const double* q0, const double* qx,
                            const double* qy, const double* w0, const double* wx,
                            const double* wy, size_t m, TriSetup* out) {
  static_assert(offsetof(TriSetup, ax) == 0 && offsetof(TriSetup, ay) == 12 &&
                offsetof(TriSetup, ex) == 24 && offsetof(TriSetup, ey) == 36 &&
                offsetof(TriSetup, i0) == 48 && offsetof(TriSetup, j0) == 52 &&
                offsetof(TriSetup, bias) == 56 && offsetof(TriSetup, q0) == 64 &&
                offsetof(TriSetup, fwd.w0) == 88 && offsetof(TriSetup, fwd.flat) == 112);
  auto lanes = [](const int32_t* v) { return _mm256_load_si256(reinterpret_cast<const __m256i*>(v)); };
  // Two int32 fields as the words (lo | hi << 32).
  auto pair = [](__m256i lo, __m256i hi) {
    return _mm512_or_si512(_mm512_cvtepu32_epi64(lo), _mm512_slli_epi64(_mm512_cvtepu32_epi64(hi), 32));
  };
  // set_box's clamping, then two int16s in an int32: (lo & 0xffff) | hi << 16.
  const __m256i cap = _mm256_set1_epi32(1 << 14), none = _mm256_set1_epi32(-1);
  auto box16 = [&](int a, int b) {
    const __m256i lo = _mm256_min_epi32(lanes(box[a]), cap), hi = _mm256_max_epi32(lanes(box[b]), none);
    return _mm256_or_si256(_mm256_and_si256(lo, _mm256_set1_epi32(0xffff)), _mm256_slli_epi32(hi, 16));
  };
  const __m256i biases = _mm256_or_si256(
      lanes(bias[0]), _mm256_or_si256(_mm256_slli_epi32(lanes(bias[1]), 8), _mm256_slli_epi32(lanes(bias[2]), 16)));
  // ax[k] = x[(k + 1) % 3], as ay.
  __m512i lo[8] = {pair(lanes(x[1]), lanes(x[2])), pair(lanes(x[0]), lanes(y[1])),
                   pair(lanes(y[2]), lanes(y[0])), pair(lanes(ex[0]), lanes(ex[1])),
                   pair(lanes(ex[2]), lanes(ey[0])), pair(lanes(ey[1]), lanes(ey[2])),
                   pair(box16(0, 1), box16(2, 3)), pair(biases, _mm256_setzero_si256())};
  auto words = [](const double* v) { return _mm512_castpd_si512(_mm512_load_pd(v)); };
  __m512i hi[8] = {words(q0), words(qx), words(qy), words(w0), words(wx), words(wy),
                   _mm512_setzero_si512(), _mm512_setzero_si512()};
  Transpose8x8(lo);
  Transpose8x8(hi);
  for (size_t j = 0; j < m; ++j) {
    char* t = reinterpret_cast<char*>(out + j);
    _mm512_storeu_si512(t, lo[j]);
    _mm512_storeu_si512(t + 64, hi[j]);
  }
}
#endif

// set_up_forward: a vector of triangles at a time, their vertices' fields
// fetched into lanes on the stack (Fetch: fetch(i, x, y, w, q) fills vertex
// k's x[k][0 .. N), ... for triangles i ..) and written back per triangle. The
// area is exact in double as in int64 (snapped coordinates stay below 2^25 in
// magnitude inside the guard band: products below 2^52).
// Extra: extra(i, m, exd, eyd, inv_area, w, x, y, box) after the planes, for
// the shading's planes (SetUpShaded; box: i0, i1, j0, j1 as the TriSetup's);
// a no-op for the forward set-up.
struct NoExtra {
  template <class... A>
  void operator()(const A&...) const {}
};
template <class Fetch, class Extra = NoExtra>
HWY_INLINE void SetUpForwardT(const Fetch& fetch, size_t n, const SampleGrid& grid, TriSetup* out,
                              bool tested, const Extra& extra = Extra()) {
  const hn::CappedTag<double, 8> dd;
  const hn::Rebind<int32_t, decltype(dd)> di;
  using VD = hn::Vec<decltype(dd)>;
  using VI = hn::Vec<decltype(di)>;
  const size_t N = hn::Lanes(dd);
  HWY_ALIGN int32_t x_in[3][8], y_in[3][8], box[4][8], ex[3][8], ey[3][8], bias[3][8];
  HWY_ALIGN double w_in[3][8], q_in[3][8], qx[8], qy[8], wx[8], wy[8];
  const VI one_i = hn::Set(di, 1);
  const VD one = hn::Set(dd, 1.0);
  const bool test = !tested && grid.ox0 == grid.ox1 && grid.oy0 == grid.oy1;
  static_assert(kSubpixel == 256);
  for (size_t i = 0; i < n; i += N) {
    const size_t m = std::min(N, n - i);
    fetch(i, x_in, y_in, w_in, q_in);
    VI x[3], y[3];
    for (int k = 0; k < 3; ++k) x[k] = hn::Load(di, x_in[k]), y[k] = hn::Load(di, y_in[k]);
    VI i0, i1, j0, j1;
    PixelBox(di, grid, x, y, i0, i1, j0, j1);
    // Edge k from vertex a = k + 1 to b = k + 2: E_k = ex (X - x_a) + ey (Y - y_a).
    VD exd[3], eyd[3];
    VI exi[3], eyi[3], bi[3];
    Edges(di, x, y, exi, eyi, bi);
    for (int k = 0; k < 3; ++k) {
      hn::Store(exi[k], di, ex[k]);
      hn::Store(eyi[k], di, ey[k]);
      hn::Store(bi[k], di, bias[k]);
      exd[k] = hn::PromoteTo(dd, exi[k]);
      eyd[k] = hn::PromoteTo(dd, eyi[k]);
    }
    // One sample per pixel: a small triangle that covers none of its box's
    // samples would draw nothing: its box is left empty, so it is never binned.
    VI hi = i1;
    if (test)
      hi = hn::IfThenElse(CoversNothing(di, grid, x, y, exi, eyi, bi, i0, i1, j0, j1),
                          hn::Sub(i0, one_i), i1);
    hn::Store(i0, di, box[0]);
    hn::Store(hi, di, box[1]);
    hn::Store(j0, di, box[2]);
    hn::Store(j1, di, box[3]);
    // Twice the area, E_2 at vertex 2, and the planes of q and w.
    const VD area = hn::Add(hn::Mul(exd[2], hn::PromoteTo(dd, hn::Sub(x[2], x[0]))),
                            hn::Mul(eyd[2], hn::PromoteTo(dd, hn::Sub(y[2], y[0]))));
    const VD inv_area = hn::Div(one, area);
    auto gradient = [&](const double (*v)[8], const VD e[3]) {
      const VD v0 = hn::Load(dd, v[0]);
      return hn::Add(hn::Mul(hn::Sub(hn::Load(dd, v[1]), v0), e[1]),
                     hn::Mul(hn::Sub(hn::Load(dd, v[2]), v0), e[2]));
    };
    hn::Store(hn::Div(gradient(q_in, exd), area), dd, qx);
    hn::Store(hn::Div(gradient(q_in, eyd), area), dd, qy);
    hn::Store(hn::Mul(gradient(w_in, exd), inv_area), dd, wx);
    hn::Store(hn::Mul(gradient(w_in, eyd), inv_area), dd, wy);
    extra(i, m, exd, eyd, inv_area, w_in, x_in, y_in, box);
#if HWY_TARGET <= HWY_AVX3
    if constexpr (hn::MaxLanes(dd) == 8) {
      WriteSetUps(x_in, y_in, ex, ey, bias, box, q_in[0], qx, qy, w_in[0], wx, wy, m, out + i);
      continue;
    }
#endif
    for (size_t j = 0; j < m; ++j) {
      TriSetup& t = out[i + j];
      for (int k = 0; k < 3; ++k) {
        const int a = (k + 1) % 3;
        t.ax[k] = x_in[a][j], t.ay[k] = y_in[a][j];
        t.ex[k] = ex[k][j], t.ey[k] = ey[k][j], t.bias[k] = uint8_t(bias[k][j]);
      }
      t.set_box(box[0][j], box[1][j], box[2][j], box[3][j]);
      t.q0 = q_in[0][j], t.qx = qx[j], t.qy = qy[j];
      t.fwd.w0 = w_in[0][j], t.fwd.wx = wx[j], t.fwd.wy = wy[j];
      t.fwd.flat[0] = t.fwd.flat[1] = t.fwd.flat[2] = 0;
    }
  }
}

// From IndexedTris: the vertices' fields fetched from their arrays (no copy of
// the triangles first), 16 bytes at a time (LoadPairs): z and the 8-byte word
// of x and y, then w and the stored depth. (Spare lanes: valid indices, not
// written out.)
// IndexedTris' fetch for SetUpForwardT (set_up_forward, set_up_shaded).
struct FetchIndexed {
  const IndexedTris& tris;
  void operator()(size_t i, int32_t (*x)[8], int32_t (*y)[8], double (*w)[8], double (*q)[8]) const {
    const hn::CappedTag<double, 8> dd;
    const hn::Rebind<int32_t, decltype(dd)> di;
    const hn::Rebind<uint32_t, decltype(dd)> du;
    const hn::Rebind<uint64_t, decltype(dd)> d64;
    static_assert(sizeof(ProjectedVertex) == 24 && offsetof(ProjectedVertex, x) == 8 &&
                  offsetof(ProjectedVertex, y) == 12 && sizeof(VertexDepth) == 16 &&
                  offsetof(VertexDepth, q) == 8);
    const double* pvd = reinterpret_cast<const double*>(tris.pv);
    const double* vd = reinterpret_cast<const double*>(tris.vd);
    const uint32_t* const index[3] = {tris.a, tris.b, tris.c};
    for (int k = 0; k < 3; ++k) {
      const uint32_t* const v = index[k] + i;
      hn::Vec<decltype(dd)> z, xyd, wk, qk;
      LoadPairs(dd, [&](int l) { return pvd + 3 * size_t(v[l]); }, z, xyd);
      const auto xy = hn::BitCast(d64, xyd);
      hn::Store(hn::BitCast(di, hn::TruncateTo(du, xy)), di, x[k]);
      hn::Store(hn::BitCast(di, hn::TruncateTo(du, hn::ShiftRight<32>(xy))), di, y[k]);
      LoadPairs(dd, [&](int l) { return vd + 2 * size_t(v[l]); }, wk, qk);
      hn::Store(wk, dd, w[k]);
      hn::Store(qk, dd, q[k]);
    }
  }
};

void SetUpForward(const IndexedTris& tris, size_t n, const SampleGrid& grid, TriSetup* out,
                  bool tested) {
  SetUpForwardT(FetchIndexed{tris}, n, grid, out, tested);
}

// set_up_shaded: set_up_forward's set-ups from IndexedTris, and per triangle
// the shading's four planes (w, then the normal times w under perspective, the
// normal itself under affine interpolation) from the vertex normals, with
// opt::simd's set_up_shading operations (no contraction): the same bits; moved
// to the triangle's tile where it meets one only, with shade_one_tile's.
void SetUpShaded(const IndexedTris& tris, size_t n, const SampleGrid& grid, TriSetup* out,
                 const Vec3* normal, bool negate, bool perspective, const ShadedPlanes& to) {
  const hn::CappedTag<double, 8> dd;
  const hn::Rebind<int32_t, decltype(dd)> di;
  const hn::Rebind<float, decltype(dd)> df;
  using VD = hn::Vec<decltype(dd)>;
  using VI = hn::Vec<decltype(di)>;
  const double* nd = &normal[0].x;
  const uint32_t* const index[3] = {tris.a, tris.b, tris.c};
  const int tw_log2 = to.tw_log2, th_log2 = to.th_log2;
  const size_t N = hn::Lanes(dd);
  HWY_ALIGN double c[4][3][8];
  HWY_ALIGN float local[4][3][8];
  HWY_ALIGN int32_t one_tile[8];
  auto shading = [&](size_t i, size_t m, const VD exd[3], const VD eyd[3], VD inv_area,
                     const double (*w)[8], const int32_t (*x)[8], const int32_t (*y)[8],
                     const int32_t (*box)[8]) {
    // The vertices' values per row: w; the normal (x, y | y, z a 16-byte load each).
    VD a[4][3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t* const v = index[k] + i;
      VD nx, ny, ny2, nz;
      LoadPairs(dd, [&](int l) { return nd + 3 * size_t(v[l]); }, nx, ny);
      LoadPairs(dd, [&](int l) { return nd + 3 * size_t(v[l]) + 1; }, ny2, nz);
      const VD wk = hn::Load(dd, w[k]);
      const VD value[3] = {negate ? hn::Neg(nx) : nx, negate ? hn::Neg(ny) : ny,
                           negate ? hn::Neg(nz) : nz};
      a[0][k] = wk;
      for (int r = 1; r < 4; ++r) a[r][k] = perspective ? hn::Mul(value[r - 1], wk) : value[r - 1];
    }
    // The tile of the box's top-left pixel, whether the box stays in it, and
    // its top-left corner from vertex 0 in 1/256 px (shade_one_tile's cx - x0).
    const VI i0 = hn::Load(di, box[0]), i1 = hn::Load(di, box[1]);
    const VI j0 = hn::Load(di, box[2]), j1 = hn::Load(di, box[3]);
    const VI tx = hn::ShiftRightSame(i0, tw_log2), ty = hn::ShiftRightSame(j0, th_log2);
    const auto one = hn::And(hn::Eq(tx, hn::ShiftRightSame(i1, tw_log2)),
                             hn::Eq(ty, hn::ShiftRightSame(j1, th_log2)));
    hn::Store(hn::VecFromMask(di, one), di, one_tile);
    const VD dx = hn::PromoteTo(dd, hn::Sub(hn::ShiftLeft<8>(hn::ShiftLeftSame(tx, tw_log2)),
                                            hn::Load(di, x[0])));
    const VD dy = hn::PromoteTo(dd, hn::Sub(hn::ShiftLeft<8>(hn::ShiftLeftSame(ty, th_log2)),
                                            hn::Load(di, y[0])));
    static_assert(kSubpixel == 256);
    const VD subpixel = hn::Set(dd, double(kSubpixel));
    for (int r = 0; r < 4; ++r) {
      const VD d1 = hn::Sub(a[r][1], a[r][0]), d2 = hn::Sub(a[r][2], a[r][0]);
      const VD a0 = a[r][0];
      const VD ax = hn::Mul(hn::Add(hn::Mul(d1, exd[1]), hn::Mul(d2, exd[2])), inv_area);
      const VD ay = hn::Mul(hn::Add(hn::Mul(d1, eyd[1]), hn::Mul(d2, eyd[2])), inv_area);
      hn::Store(a0, dd, c[r][0]);
      hn::Store(ax, dd, c[r][1]);
      hn::Store(ay, dd, c[r][2]);
      hn::Store(hn::DemoteTo(df, hn::Add(hn::Add(a0, hn::Mul(ax, dx)), hn::Mul(ay, dy))), df,
                local[r][0]);
      hn::Store(hn::DemoteTo(df, hn::Mul(ax, subpixel)), df, local[r][1]);
      hn::Store(hn::DemoteTo(df, hn::Mul(ay, subpixel)), df, local[r][2]);
    }
    // The set-ups and TilePlanes four vectors ahead, for writing: the stores
    // are what this loop waits on where the arrays are out of the caches (each
    // line is fetched before it is written; the hardware's prefetch starts
    // late). (Not in the flat set-up: there it costs more than it saves.)
    for (size_t j = i + 4 * N; j < std::min(n, i + 5 * N); ++j) {
      __builtin_prefetch(&out[j], 1);
      __builtin_prefetch(reinterpret_cast<const char*>(&out[j]) + 64, 1);
      __builtin_prefetch(&to.local[j], 1);
    }
    // (The moved planes for every triangle -- unread where not in one tile --
    // the double ones for those only: rare, a branch that predicts well.)
    for (size_t j = 0; j < m; ++j) {
      float* const p = &to.local[i + j].p[0][0];
      for (int r = 0; r < 4; ++r)
        for (int k = 0; k < 3; ++k) p[3 * r + k] = local[r][k][j];
      to.ready[i + j] = one_tile[j] != 0;
      if (!one_tile[j]) {
        double* const d = to.planes + (i + j) * 12;
        for (int r = 0; r < 4; ++r)
          for (int k = 0; k < 3; ++k) d[3 * r + k] = c[r][k][j];
      }
    }
  };
  SetUpForwardT(FetchIndexed{tris}, n, grid, out, true, shading);
}

// From TriVertices: loads.
void SetUpForwardArrays(const TriVertices& tris, size_t n, const SampleGrid& grid, TriSetup* out,
                        bool tested) {
  const hn::CappedTag<double, 8> dd;
  const hn::Rebind<int32_t, decltype(dd)> di;
  auto load = [&](size_t i, int32_t (*x)[8], int32_t (*y)[8], double (*w)[8], double (*q)[8]) {
    for (int k = 0; k < 3; ++k) {
      hn::Store(hn::LoadU(di, tris.x[k] + i), di, x[k]);
      hn::Store(hn::LoadU(di, tris.y[k] + i), di, y[k]);
      hn::Store(hn::LoadU(dd, tris.w[k] + i), dd, w[k]);
      hn::Store(hn::LoadU(dd, tris.q[k] + i), dd, q[k]);
    }
  };
  SetUpForwardT(load, n, grid, out, tested);
}

// ---------------------------------------------------------------- sphere_face_codes
size_t SphereFaceCodes(const double* nx, const double* ny, const double* nz, const double* h,
                       size_t n, const double e[3], double r, double sign, double margin,
                       bool mark_sure, uint32_t* cand, FaceVertices* verts) {
  const hn::CappedTag<double, 8> dd;
  const hn::Rebind<uint32_t, decltype(dd)> du;
  using VD = hn::Vec<decltype(dd)>;
  const size_t N = hn::Lanes(dd);
  const VD ex = hn::Set(dd, e[0]), ey = hn::Set(dd, e[1]), ez = hn::Set(dd, e[2]);
  const VD rv = hn::Set(dd, r), sg = hn::Set(dd, sign);
  const VD lo = hn::Set(dd, -margin), hi = hn::Set(dd, margin);
  const uint32_t sure_bit = mark_sure ? kSureFace : 0;
  const auto iota = hn::Iota(du, 0);
  size_t m = 0, t = 0;
  for (; t + N <= n; t += N) {
    const VD sd = hn::Mul(
        sg, hn::Sub(hn::Add(hn::Add(hn::Mul(hn::LoadU(dd, nx + t), ex), hn::Mul(hn::LoadU(dd, ny + t), ey)),
                            hn::Mul(hn::LoadU(dd, nz + t), ez)),
                    hn::Mul(hn::LoadU(dd, h + t), rv)));
    auto idx = hn::Add(iota, hn::Set(du, uint32_t(t)));
    const auto sure = CastMask(du, dd, hn::Gt(sd, hi)), written = CastMask(du, dd, hn::Ge(sd, lo));
    idx = hn::IfThenElse(sure, hn::Or(idx, hn::Set(du, sure_bit)), idx);
    if (verts) {
      for (int k = 0; k < 3; ++k)
        hn::CompressStore(hn::LoadU(du, verts->in[k] + t), written, du, verts->out[k] + m);
      verts->unsure += hn::CountTrue(du, hn::AndNot(sure, written));
    }
    m += hn::CompressStore(idx, written, du, cand + m);
  }
  for (; t < n; ++t) {  // (the same operations, one face)
    const double sd = sign * (nx[t] * e[0] + ny[t] * e[1] + nz[t] * e[2] - r * h[t]);
    cand[m] = uint32_t(t) | (sd > margin ? sure_bit : 0);
    if (verts && sd >= -margin) {
      for (int k = 0; k < 3; ++k) verts->out[k][m] = verts->in[k][t];
      verts->unsure += !(sd > margin);
    }
    m += sd >= -margin;
  }
  return m;
}

// ---------------------------------------------------------------- polygon_run
//
// Vertex k of each of a vector's N triangles, from one field of its 3N
// vertices (in order: v[0] holds vertices 0 .. N-1, v[1] the next N, v[2] the
// last): every third value, from the third starting at k.
template <class D, class V = hn::Vec<D>>
HWY_INLINE void PerTriangle(D d, const V v[3], V out[3]) {
  HWY_ALIGN hn::TFromD<D> buf[3 * hn::MaxLanes(D())];
  const size_t N = hn::Lanes(d);
  for (size_t j = 0; j < 3; ++j) hn::Store(v[j], d, buf + j * N);
  hn::LoadInterleaved3(d, buf, out[0], out[1], out[2]);
}

// The scalar loop's steps (view_scene_chunks) on N polygons at a time: the
// vertices' fields read a vector of vertices at a time (LoadInterleaved over
// their records), then regrouped per triangle (PerTriangle); the kept
// triangles compressed into out.
size_t PolygonRunStep(const PolygonRun& r, const SampleGrid& grid, PolygonRunOut& out) {
  const hn::CappedTag<double, 8> dd;
  const hn::Rebind<int32_t, decltype(dd)> di;
  using VD = hn::Vec<decltype(dd)>;
  using VI = hn::Vec<decltype(di)>;
  const size_t N = hn::Lanes(dd);
  static_assert(sizeof(Vec3) == 24);
  const double* world = &r.world[0].x;
  const ProjectLanes<decltype(dd)> proj(dd, *r.proj, r.depth);
  const VD zero = hn::Zero(dd), one = hn::Set(dd, 1.0), three = hn::Set(dd, 3.0);
  const VD eye[3] = {hn::Set(dd, r.proj->eye[0]), hn::Set(dd, r.proj->eye[1]),
                     hn::Set(dd, r.proj->eye[2])};
  const VI zero_i = hn::Zero(di);
  auto dot3 = [](VD ax, VD ay, VD az, VD bx, VD by, VD bz) {  // as Vec3's dot
    return hn::Add(hn::Add(hn::Mul(ax, bx), hn::Mul(ay, by)), hn::Mul(az, bz));
  };
  size_t i = 0;
  for (; i + N <= r.n; i += N) {
    VD face[4];  // (n.x, n.y, n.z, d)
    hn::LoadInterleaved4(dd, r.plane + 4 * i, face[0], face[1], face[2], face[3]);
    // A zero face normal: the caller's too (view_polygons counts it when only
    // range lost the normal: nothing is dropped silently).
    auto alive =
        hn::Not(hn::Eq(dot3(face[0], face[1], face[2], face[0], face[1], face[2]), zero));
    // The vertices, a vector of them at a time (c[coordinate][j]: vertices
    // j N .. j N + N - 1), projected (project_vertices' operations), then
    // regrouped per triangle (wv[coordinate][vertex k], ...).
    VD c[3][3], ez_v[3], x_v[3], y_v[3], in_v[3];
    for (size_t j = 0; j < 3; ++j) {
      hn::LoadInterleaved3(dd, world + 3 * (3 * i + j * N), c[0][j], c[1][j], c[2][j]);
      const VD w[3] = {c[0][j], c[1][j], c[2][j]};
      hn::Mask<decltype(dd)> inside;
      proj.position(w, ez_v[j], x_v[j], y_v[j], inside);
      in_v[j] = hn::IfThenElseZero(inside, one);
    }
    VD in[3];
    PerTriangle(dd, in_v, in);
    const auto inside = hn::Gt(hn::Min(hn::Min(in[0], in[1]), in[2]), zero);
    // A polygon that may need clipping, or without a normal: the caller's (view_polygons).
    if (!hn::AllTrue(dd, hn::And(inside, alive))) break;
    out.scene_tris += hn::CountTrue(dd, alive);
    VD wv[3][3];
    for (int k = 0; k < 3; ++k) PerTriangle(dd, c[k], wv[k]);
    // World-space culling: dot(face, eye - w0) > 0 for a front face.
    if (r.cull_world) {
      const VD facing = dot3(face[0], face[1], face[2], hn::Sub(eye[0], wv[0][0]),
                             hn::Sub(eye[1], wv[1][0]), hn::Sub(eye[2], wv[2][0]));
      const auto culled = hn::AndNot(hn::Gt(facing, zero), alive);
      out.culled += hn::CountTrue(dd, culled);
      alive = hn::AndNot(culled, alive);
    }
    if (hn::AllFalse(dd, alive)) continue;
    // The snapped area, exact in double as in int64: degenerate at 0, culled in
    // projection space when positive (a front face is counter-clockwise as
    // seen, y down), and b and c swapped when negative (the raster's order).
    VD xd[3], yd[3];
    PerTriangle(dd, x_v, xd);
    PerTriangle(dd, y_v, yd);
    VI x[3], y[3];
    for (int k = 0; k < 3; ++k) x[k] = hn::DemoteTo(di, xd[k]), y[k] = hn::DemoteTo(di, yd[k]);
    const VD area = hn::Sub(
        hn::Mul(hn::PromoteTo(dd, hn::Sub(x[1], x[0])), hn::PromoteTo(dd, hn::Sub(y[2], y[0]))),
        hn::Mul(hn::PromoteTo(dd, hn::Sub(y[1], y[0])), hn::PromoteTo(dd, hn::Sub(x[2], x[0]))));
    const auto degenerate = hn::And(hn::Eq(area, zero), alive);
    out.degenerate += hn::CountTrue(dd, degenerate);
    alive = hn::AndNot(degenerate, alive);
    if (r.cull_projection) {
      const auto culled = hn::And(hn::Gt(area, zero), alive);
      out.culled += hn::CountTrue(dd, culled);
      alive = hn::AndNot(culled, alive);
    }
    // No sample of the grid in the box: left out.
    VI i0, i1, j0, j1;
    PixelBox(di, grid, x, y, i0, i1, j0, j1);
    const auto none = CastMask(dd, di, hn::Or(hn::Gt(i0, i1), hn::Gt(j0, j1)));
    const auto kept = hn::AndNot(none, alive);
    if (hn::AllFalse(dd, kept)) continue;
    const auto kept_i = CastMask(di, dd, kept);
    const auto swap = hn::Lt(area, zero);
    const auto swap_i = hn::Gt(hn::DemoteTo(di, hn::IfThenElseZero(swap, one)), zero_i);
    // The kept triangles' vertices in the raster's order, w and the stored depth.
    VD w[3], q[3];
    {
      VD w_v[3], q_v[3];
      for (size_t j = 0; j < 3; ++j) proj.depth(ez_v[j], w_v[j], q_v[j]);
      PerTriangle(dd, w_v, w);
      PerTriangle(dd, q_v, q);
    }
    const size_t at = out.kept;
    for (int k = 0; k < 3; ++k) {
      const int from = k == 0 ? 0 : k == 1 ? 2 : 1;  // where swapped
      hn::CompressStore(hn::IfThenElse(swap_i, x[from], x[k]), kept_i, di, out.x[k] + at);
      hn::CompressStore(hn::IfThenElse(swap_i, y[from], y[k]), kept_i, di, out.y[k] + at);
      hn::CompressStore(hn::IfThenElse(swap, w[from], w[k]), kept, dd, out.w[k] + at);
      hn::CompressStore(hn::IfThenElse(swap, q[from], q[k]), kept, dd, out.q[k] + at);
    }
    // The flat colour's inputs: the centroid ((0 + v0 + v1 + v2) / 3, as the
    // scalar loop sums it) and the face normal.
    for (int k = 0; k < 3; ++k) {
      const VD centroid =
          hn::Div(hn::Add(hn::Add(hn::Add(zero, wv[k][0]), wv[k][1]), wv[k][2]), three);
      hn::CompressStore(centroid, kept, dd, out.centroid[k] + at);
      hn::CompressStore(face[k], kept, dd, out.face[k] + at);
    }
    out.kept += hn::CountTrue(dd, kept);
  }
  return i;
}


}  // namespace HWY_NAMESPACE
}  // namespace lockstep::opt::zsimd
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace lockstep::opt::zsimd {

HWY_EXPORT(BallEntries);
HWY_EXPORT(GrowBounds);
HWY_EXPORT(SphereFaces);
HWY_EXPORT(SphereFaceCodes);
HWY_EXPORT(ProjectVertices);
HWY_EXPORT(TriangleStep);
HWY_EXPORT(SetUpForward);
HWY_EXPORT(SetUpForwardArrays);
HWY_EXPORT(SetUpShaded);
HWY_EXPORT(PolygonRunStep);

void ball_entries(const double ce[3], double rho2, bool inverted, double z_occ, double pitch,
                  double half_w, double dy, int cell, int a0, int n, double* out) {
  HWY_DYNAMIC_DISPATCH(BallEntries)(ce, rho2, inverted, z_occ, pitch, half_w, dy, cell, a0, n, out);
}

void grow_bounds(const Vec3* points, size_t n, Vec3& lo, Vec3& hi) {
  HWY_DYNAMIC_DISPATCH(GrowBounds)(points, n, lo, hi);
}

void sphere_faces(const Vec3* world, const std::array<uint32_t, 3>* tri, size_t n, bool flip,
                  const Vec3& eye, double* face, uint8_t* flags) {
  HWY_DYNAMIC_DISPATCH(SphereFaces)(world, tri, n, flip, eye, face, flags);
}

size_t sphere_face_codes(const double* nx, const double* ny, const double* nz, const double* h,
                         size_t n, const double e[3], double r, double sign, double margin,
                         bool mark_sure, uint32_t* cand, FaceVertices* verts) {
  return HWY_DYNAMIC_DISPATCH(SphereFaceCodes)(nx, ny, nz, h, n, e, r, sign, margin, mark_sure,
                                               cand, verts);
}

void project_vertices(const Projection& p, const Vec3* world, size_t n, ProjectedVertex* out,
                      const DepthMap* depth, VertexDepth* depth_out) {
  HWY_DYNAMIC_DISPATCH(ProjectVertices)(p, world, n, out, depth, depth_out);
}

size_t triangle_step(const ProjectedVertex* pv, uint32_t* a, uint32_t* b, uint32_t* c,
                     uint32_t* tag, size_t n, const SampleGrid& grid, bool cull_projection,
                     const OcclusionCells* occ, TriangleCounts& counts) {
  return HWY_DYNAMIC_DISPATCH(TriangleStep)(pv, a, b, c, tag, n, grid, cull_projection, occ, counts);
}

void set_up_forward(const IndexedTris& tris, size_t n, const SampleGrid& grid, TriSetup* out,
                    bool tested) {
  HWY_DYNAMIC_DISPATCH(SetUpForward)(tris, n, grid, out, tested);
}
void set_up_forward(const TriVertices& tris, size_t n, const SampleGrid& grid, TriSetup* out,
                    bool tested) {
  HWY_DYNAMIC_DISPATCH(SetUpForwardArrays)(tris, n, grid, out, tested);
}
void set_up_shaded(const IndexedTris& tris, size_t n, const SampleGrid& grid, TriSetup* out,
                   const Vec3* normal, bool negate, bool perspective, const ShadedPlanes& to) {
  HWY_DYNAMIC_DISPATCH(SetUpShaded)(tris, n, grid, out, normal, negate, perspective, to);
}

size_t polygon_run(const PolygonRun& run, const SampleGrid& grid, PolygonRunOut& out) {
  return HWY_DYNAMIC_DISPATCH(PolygonRunStep)(run, grid, out);
}

}  // namespace lockstep::opt::zsimd
#endif  // HWY_ONCE
