// lockstep optimized: the scanline z-buffer with Highway span fills and TBB bands.
//
// The algorithm is the reference's (reference/scanline.cpp): per sample-row
// pass an edge table, an active edge list in scene order, the exact integer
// edge walk (so coverage is the z-buffer's, sample for sample), one span per
// triangle per row. What differs:
//   - the span fill is a vector loop: the stored depth (window depth, n/z or 1/z
//     based: all affine in 1/z, so in screen space) at the span's first sample
//     comes from the triangle's plane in double, then N lanes at a time
//     (8 floats on AVX2, 16 on AVX-512) d, d + dd, ... are compared with the
//     row's z-buffer and written where nearer, with the triangle's id;
//     float depth formats (float, reversed) run in float lanes, fixed24 and
//     double in double lanes;
//   - the frame is cut into bands of rows, each with its own edge table and
//     active edge lists (edges enter a band at its first row, their walk
//     initialised there exactly), on TBB (optimized/tiling.h);
//   - visibility first, shading after: each visible sample is shaded once, by
//     the z-buffer's SIMD shading (opt::simd::shade_visibility: float, SoA,
//     every Shading mode), within the simd z-buffer's 1/255 of the reference;
//   - the set-up is opt::simd::view_scene (view_scene's mesh, bit for bit).
#ifndef LOCKSTEP_SCANLINE_SIMD_SHARED
#define LOCKSTEP_SCANLINE_SIMD_SHARED
#include <cstddef>
#include <cstdint>
#endif  // LOCKSTEP_SCANLINE_SIMD_SHARED

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "optimized/scanline_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace lockstep::opt::scanline_kernels {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The span [0, n) of one row of a z-buffer in float: lane i holds d0 + i dd;
// where it is nearer (less, or greater for reversed depth) than depth[i], the
// depth and the triangle id are written. The buffers hold a whole vector past n.
void FillF(float* depth, int32_t* tri, int64_t n, double d0, double dd, int32_t id, bool greater) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const int64_t N = int64_t(hn::Lanes(df));
  auto d = hn::Add(hn::Set(df, float(d0)), hn::Mul(hn::Iota(df, 0), hn::Set(df, float(dd))));
  const auto step = hn::Set(df, float(dd * double(N)));
  const auto vid = hn::Set(di, id);
  for (int64_t i = 0; i < n; i += N) {
    const auto cur = hn::LoadU(df, depth + i);
    auto m = greater ? hn::Gt(d, cur) : hn::Lt(d, cur);
    if (n - i < N) m = hn::And(m, hn::FirstN(df, size_t(n - i)));
    hn::StoreU(hn::IfThenElse(m, d, cur), df, depth + i);
    hn::StoreU(hn::IfThenElse(hn::RebindMask(di, m), vid, hn::LoadU(di, tri + i)), di, tri + i);
    d = hn::Add(d, step);
  }
}

// The same in double lanes (ids as doubles, exact below 2^53); fixed24: the
// stored value is the window depth clamped to [0, 1], scaled to 2^24 - 1 and
// rounded to the nearest integer (ties to even, as std::nearbyint).
void FillD(double* depth, double* tri, int64_t n, double d0, double dd, double id, bool greater,
           bool fixed24) {
  const hn::ScalableTag<double> dd_;
  const int64_t N = int64_t(hn::Lanes(dd_));
  auto d = hn::Add(hn::Set(dd_, d0), hn::Mul(hn::Iota(dd_, 0), hn::Set(dd_, dd)));
  const auto step = hn::Set(dd_, dd * double(N));
  const auto vid = hn::Set(dd_, id);
  const auto zero = hn::Zero(dd_), one = hn::Set(dd_, 1.0),
             scale = hn::Set(dd_, double((1 << 24) - 1));
  for (int64_t i = 0; i < n; i += N) {
    auto v = d;
    if (fixed24) v = hn::Round(hn::Mul(hn::Min(hn::Max(d, zero), one), scale));
    const auto cur = hn::LoadU(dd_, depth + i);
    auto m = greater ? hn::Gt(v, cur) : hn::Lt(v, cur);
    if (n - i < N) m = hn::And(m, hn::FirstN(dd_, size_t(n - i)));
    hn::StoreU(hn::IfThenElse(m, v, cur), dd_, depth + i);
    hn::StoreU(hn::IfThenElse(m, vid, hn::LoadU(dd_, tri + i)), dd_, tri + i);
    d = hn::Add(d, step);
  }
}

size_t LanesF() { return hn::Lanes(hn::ScalableTag<float>()); }
const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace lockstep::opt::scanline_kernels
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "optimized/zbuffer/zbuffer_simd.h"
#include "optimized/scanline_simd.h"
#include "optimized/tiling.h"

namespace lockstep::opt::scanline_kernels {
HWY_EXPORT(FillF);
HWY_EXPORT(FillD);
HWY_EXPORT(LanesF);
HWY_EXPORT(TargetName);
}  // namespace lockstep::opt::scanline_kernels

namespace lockstep::opt::simd {

namespace {

namespace sk = scanline_kernels;

int64_t ceil_div(int64_t a, int64_t d) { return -floor_div(-a, d); }

struct Column {
  int k = 0;
  int32_t ox = 0;
};
struct Pass {
  int32_t oy = 0;
  std::vector<Column> columns;
};

// The exact integer edge walk of the reference (reference/scanline.cpp, Edge).
struct Edge {
  uint32_t tri = 0;
  bool left = false;
  int last_row = 0;
  int64_t D = 1, q = 0, r = 0, qs = 0, rs = 0;
  int64_t bound() const { return left ? -q : q; }
  void step() {
    q += qs;
    r += rs;
    if (r >= D) {
      r -= D;
      q += 1;
    }
  }
};

// The triangle's stored depth as a plane over the screen: d(X, Y) = d0 + ddx (X - x0) + ddy (Y -
// y0), pixels.
struct DepthPlane {
  double x0 = 0, y0 = 0, d0 = 0, ddx = 0, ddy = 0;
};

struct Frame {
  const ScreenMesh* mesh = nullptr;
  RasterSettings s;
  int width = 0, height = 0, spp = 1, band = 16;
  std::vector<std::array<int32_t, 2>> offsets;
  std::vector<Pass> passes;
  std::vector<DepthPlane> planes;
  std::vector<uint8_t> flat_bottom;
  std::vector<std::vector<uint32_t>>
      band_tris;            // the triangles whose rows meet each band, in scene order
  bool float_lanes = true;  // float / reversed depth: float lanes; fixed24 / double: double lanes
};

Frame prepare(const ScreenMesh& mesh, const RasterSettings& s) {
  Frame f;
  f.mesh = &mesh;
  f.s = s;
  f.width = mesh.width;
  f.height = mesh.height;
  f.offsets = sample_offsets(s);
  f.spp = int(f.offsets.size());
  for (int k = 0; k < f.spp; ++k) {
    auto it = std::find_if(f.passes.begin(), f.passes.end(),
                           [&](const Pass& p) { return p.oy == f.offsets[k][1]; });
    if (it == f.passes.end()) {
      f.passes.push_back({f.offsets[k][1], {}});
      it = f.passes.end() - 1;
    }
    it->columns.push_back({k, f.offsets[k][0]});
  }
  f.float_lanes = s.depth == DepthFormat::kFloat || s.depth == DepthFormat::kReversed;
  // Stored depth = alpha + beta / z (window depth, or n/z for reversed-Z).
  const double n = mesh.near_z, far = mesh.far_z;
  double alpha = 0, beta = n;
  if (s.depth != DepthFormat::kReversed) {
    alpha = (1 / n) / (1 / n - 1 / far);
    beta = -1 / (1 / n - 1 / far);
  }
  const int bands = (f.height + f.band - 1) / f.band;
  f.band_tris.assign(size_t(std::max(bands, 0)), {});
  f.planes.resize(mesh.tris.size());
  f.flat_bottom.resize(mesh.tris.size());
  for (uint32_t ti = 0; ti < mesh.tris.size(); ++ti) {
    const ScreenTri& t = mesh.tris[ti];
    double x[3], y[3], w[3];
    for (int k = 0; k < 3; ++k) {
      x[k] = double(t.v[k].x) / kSubpixel;
      y[k] = double(t.v[k].y) / kSubpixel;
      w[k] = alpha + beta / t.v[k].z;
    }
    const double ex1 = x[1] - x[0], ey1 = y[1] - y[0], ew1 = w[1] - w[0];
    const double ex2 = x[2] - x[0], ey2 = y[2] - y[0], ew2 = w[2] - w[0];
    const double A = ey1 * ew2 - ew1 * ey2, B = ew1 * ex2 - ex1 * ew2, C = ex1 * ey2 - ey1 * ex2;
    f.planes[ti] = {x[0], y[0], w[0], -A / C, -B / C};
    const int32_t ymin = std::min({t.v[0].y, t.v[1].y, t.v[2].y}),
                  ymax = std::max({t.v[0].y, t.v[1].y, t.v[2].y});
    f.flat_bottom[ti] = (t.v[0].y == ymax) + (t.v[1].y == ymax) + (t.v[2].y == ymax) == 2;
    // The pixel rows whose sample rows (256 j .. 256 j + 255) meet [ymin, ymax].
    const int64_t j0 = std::max<int64_t>(ceil_div(int64_t(ymin) - (kSubpixel - 1), kSubpixel), 0);
    const int64_t j1 = std::min<int64_t>(floor_div(ymax, kSubpixel), f.height - 1);
    for (int64_t b = j0 / f.band; j0 <= j1 && b <= j1 / f.band; ++b)
      f.band_tris[size_t(b)].push_back(ti);
  }
  return f;
}

// Edge a -> b of triangle ti for the sample rows at oy, entering at row max(its first, j_begin).
bool make_edge(const Frame& f, uint32_t ti, int a, int b, int32_t oy, int j_begin, int j_end,
               Edge& e, int& first) {
  const ScreenTri& t = f.mesh->tris[ti];
  const ScreenVertex &va = t.v[a], &vb = t.v[b];
  const int64_t dx = int64_t(vb.x) - va.x, dy = int64_t(vb.y) - va.y;
  if (dy == 0) return false;
  e.tri = ti;
  e.left = dy < 0;
  e.D = std::abs(dy);
  const int64_t ytop = std::min(va.y, vb.y), ybot = std::max(va.y, vb.y);
  const int64_t j0 = std::max<int64_t>(ceil_div(ytop - oy, kSubpixel), j_begin);
  const int64_t j1 =
      std::min<int64_t>(floor_div(ybot - oy - (f.flat_bottom[ti] ? 1 : 0), kSubpixel), j_end - 1);
  if (j0 > j1) return false;
  first = int(j0);
  e.last_row = int(j1);
  const int64_t y = j0 * kSubpixel + oy;
  const int64_t C0 = dx * (y - va.y) + dy * va.x;
  const int64_t M = e.left ? C0 : C0 - 1;
  e.q = floor_div(M, e.D);
  e.r = M - e.q * e.D;
  const int64_t Ms = dx * kSubpixel;
  e.qs = floor_div(Ms, e.D);
  e.rs = Ms - e.qs * e.D;
  return true;
}

// One pixel row's results, sample index i * spp + k.
struct RowOut {
  std::vector<uint32_t> tri;
  std::vector<double> depth;
  std::vector<uint16_t> count;
};

// Rows [j_begin, j_end) (one band): on_row(j, out) when row j is done.
template <class OnRow>
void scan_band(const Frame& f, int j_begin, int j_end, bool counts, OnRow on_row) {
  const int w = f.width, spp = f.spp;
  const size_t lanes = HWY_DYNAMIC_DISPATCH(sk::LanesF)();
  const size_t pad = 16 + lanes;  // a whole vector past the last pixel (double lanes are fewer)
  const std::vector<uint32_t>& tris = f.band_tris[size_t(j_begin / f.band)];
  const bool greater = f.s.depth == DepthFormat::kReversed;
  const bool fixed24 = f.s.depth == DepthFormat::kFixed24;
  const double empty = empty_depth(f.s.depth);

  // The edge tables of the band's passes, bucketed by row within the band.
  const int rows = j_end - j_begin;
  std::vector<std::vector<std::vector<Edge>>> et(f.passes.size(),
                                                 std::vector<std::vector<Edge>>(size_t(rows)));
  for (size_t p = 0; p < f.passes.size(); ++p)
    for (uint32_t ti : tris)
      for (int a = 0; a < 3; ++a) {
        Edge e;
        int first = 0;
        if (make_edge(f, ti, a, (a + 1) % 3, f.passes[p].oy, j_begin, j_end, e, first))
          et[p][size_t(first - j_begin)].push_back(e);
      }
  std::vector<std::vector<Edge>> ael(f.passes.size());

  // The row z-buffer, one contiguous row per sample column (k).
  std::vector<float> zf(f.float_lanes ? size_t(spp) * (w + pad) : 0);
  std::vector<int32_t> tf(zf.size());
  std::vector<double> zd(f.float_lanes ? 0 : size_t(spp) * (w + pad));
  std::vector<double> td(zd.size());
  std::vector<uint16_t> cnt(counts ? size_t(spp) * (w + pad) : 0);
  RowOut out;
  out.tri.resize(size_t(w) * spp);
  out.depth.resize(size_t(w) * spp);
  if (counts) out.count.resize(size_t(w) * spp);

  for (int j = j_begin; j < j_end; ++j) {
    if (f.float_lanes) {
      std::fill(zf.begin(), zf.end(), float(empty));
      std::fill(tf.begin(), tf.end(), -1);
    } else {
      std::fill(zd.begin(), zd.end(), empty);
      std::fill(td.begin(), td.end(), -1.0);
    }
    std::fill(cnt.begin(), cnt.end(), 0);
    for (size_t p = 0; p < f.passes.size(); ++p) {
      // The AEL stays in scene order without sorting: edges leave in place,
      // and the row's new edges (in scene order already: the band's triangles
      // are listed in order) are merged in.
      std::vector<Edge>& active = ael[p];
      std::erase_if(active, [&](const Edge& e) { return e.last_row < j; });
      const std::vector<Edge>& fresh = et[p][size_t(j - j_begin)];
      if (!fresh.empty()) {
        const size_t old = active.size();
        active.insert(active.end(), fresh.begin(), fresh.end());
        std::inplace_merge(active.begin(), active.begin() + ptrdiff_t(old), active.end(),
                           [](const Edge& a, const Edge& b) { return a.tri < b.tri; });
      }
      const int64_t ys = int64_t(j) * kSubpixel + f.passes[p].oy;
      for (size_t g = 0; g < active.size();) {
        int64_t xl = INT64_MIN, xr = INT64_MAX;
        const uint32_t ti = active[g].tri;
        bool has_l = false, has_r = false;
        for (; g < active.size() && active[g].tri == ti; ++g) {
          if (active[g].left) {
            xl = std::max(xl, active[g].bound());
            has_l = true;
          } else {
            xr = std::min(xr, active[g].bound());
            has_r = true;
          }
        }
        if (!has_l || !has_r || xl > xr) continue;
        const DepthPlane& pl = f.planes[ti];
        for (const Column& col : f.passes[p].columns) {
          const int64_t i0 = std::max<int64_t>(ceil_div(xl - col.ox, kSubpixel), 0);
          const int64_t i1 = std::min<int64_t>(floor_div(xr - col.ox, kSubpixel), w - 1);
          if (i0 > i1) continue;
          // The stored depth at the first sample, from the plane, in double.
          const double X = double(i0 * kSubpixel + col.ox) / kSubpixel, Y = double(ys) / kSubpixel;
          const double d0 = pl.d0 + pl.ddx * (X - pl.x0) + pl.ddy * (Y - pl.y0);
          const size_t base = size_t(col.k) * (w + pad) + size_t(i0);
          if (f.float_lanes) HWY_DYNAMIC_DISPATCH(sk::FillF)
          (zf.data() + base, tf.data() + base, i1 - i0 + 1, d0, pl.ddx, int32_t(ti), greater);
          else HWY_DYNAMIC_DISPATCH(sk::FillD)(zd.data() + base, td.data() + base, i1 - i0 + 1, d0,
                                               pl.ddx, double(ti), greater, fixed24);
          if (counts)
            for (size_t i = base; i <= base + size_t(i1 - i0); ++i) ++cnt[i];
        }
      }
      for (Edge& e : active) e.step();
    }
    // Gather the columns into the row's samples.
    for (int k = 0; k < spp; ++k)
      for (int i = 0; i < w; ++i) {
        const size_t c = size_t(k) * (w + pad) + size_t(i), o = size_t(i) * spp + k;
        if (f.float_lanes) {
          out.tri[o] = tf[c] < 0 ? Visibility::kNone : uint32_t(tf[c]);
          out.depth[o] = double(zf[c]);
        } else {
          out.tri[o] = td[c] < 0 ? Visibility::kNone : uint32_t(td[c]);
          out.depth[o] = zd[c];
        }
        if (counts) out.count[o] = cnt[c];
      }
    on_row(j, out);
  }
}

// Bands of rows on TBB.
template <class OnRow>
void scan_frame(const Frame& f, int threads, const std::function<void(double)>& progress,
                bool counts, OnRow on_row) {
  if (f.width <= 0 || f.height <= 0) return;
  parallel_tiles(f.width, f.height, f.width, f.band, threads, progress,
                 [&](int, int y0, int, int y1) { scan_band(f, y0, y1, counts, on_row); });
}

}  // namespace

const char* scanline_target_name() { return HWY_DYNAMIC_DISPATCH(sk::TargetName)(); }
size_t scanline_lanes() { return HWY_DYNAMIC_DISPATCH(sk::LanesF)(); }

void scanline_visibility(const ScreenMesh& mesh, const RasterSettings& s, int threads,
                         Visibility& vis) {
  const Frame f = prepare(mesh, s);
  const size_t samples = size_t(mesh.width) * mesh.height * f.spp;
  vis.width = mesh.width;
  vis.height = mesh.height;
  vis.spp = f.spp;
  vis.tri.assign(samples, Visibility::kNone);
  vis.depth.assign(samples, empty_depth(s.depth));
  vis.count.assign(samples, 0);
  scan_frame(f, threads, {}, true, [&](int j, const RowOut& out) {
    const size_t at = size_t(j) * mesh.width * f.spp;
    std::copy(out.tri.begin(), out.tri.end(), vis.tri.begin() + at);
    std::copy(out.depth.begin(), out.depth.end(), vis.depth.begin() + at);
    std::copy(out.count.begin(), out.count.end(), vis.count.begin() + at);
  });
}

Image scanline(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  Image img;
  VisibleBuffer visible;
  scanline_into(scene, opts, stats, img, visible);
  return img;
}

VisibleBuffer visible_buffer(const Scene& scene, const FrameOptions& opts) {
  const RasterSettings s = frame_settings(scene, opts);
  VisibleBuffer visible(size_t(opts.width) * size_t(opts.height) * sample_offsets(s).size());
  std::fill(visible.begin(), visible.end(), Visibility::kNone);  // first touch, here
  return visible;
}

void scanline_into(const Scene& scene, const FrameOptions& opts, FrameStats* stats, Image& img,
                   VisibleBuffer& visible) {
  const RasterSettings s = frame_settings(scene, opts);
  // The set-up: view_scene's mesh, bit for bit (opt::simd::view_scene, in parallel).
  const ScreenMesh mesh = opt::simd::view_scene(scene, opts.width, opts.height, s, opts.threads);
  const Frame f = prepare(mesh, s);
  // Visibility first, by scanlines: the visible triangle per sample (the
  // session's buffer when it keeps one: 4 MiB of first-touch faults at 1024^2
  // otherwise, a third of a fresh frame's).
  visible.resize(size_t(opts.width) * size_t(opts.height) * size_t(f.spp));
  std::fill(visible.begin(), visible.end(), Visibility::kNone);
  scan_frame(f, opts.threads, {}, false, [&](int j, const RowOut& out) {
    std::copy(out.tri.begin(), out.tri.end(),
              visible.begin() + ptrdiff_t(size_t(j) * opts.width * f.spp));
  });
  // Then each visible sample shaded once, by the z-buffer's SIMD shading.
  opt::simd::shade_visibility_into(scene, mesh, s, visible.data(), opts, img);
  if (stats) {
    stats->items = mesh.scene_tris + mesh.sphere_tris;
    stats->dropped = mesh.dropped;
    count_float_lighting_limits(scene, mesh.camera, stats);
  }
}

}  // namespace lockstep::opt::simd
#endif  // HWY_ONCE
