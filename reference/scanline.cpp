// lockstep reference: the scanline z-buffer (Foley, van Dam, Feiner, Hughes,
// "Computer Graphics: Principles and Practice", 2nd ed., 3.6 "Filling
// polygons" and 15.4 "The z-buffer algorithm"; Watkins 1970, "A real-time
// visible surface algorithm"), over the screen mesh of core/viewing.cpp.
//
// Polygon scan conversion visits a polygon row by row: an edge table (ET)
// holds every edge in the bucket of the first sample row it crosses; an active
// edge list (AEL) holds the edges that cross the current row; the samples
// between a triangle's left and right edge on that row form a span. Everything
// along the way is incremental (coherence):
//   - the edge's crossing of the next row: x += dx/dy, kept exactly as an
//     integer and a remainder (Foley 3.6's integer edge walk), so that the span
//     holds exactly the samples the edge functions of ref::zbuffer accept;
//   - 1/z down the edge and across the span: 1/z is affine in screen space
//     (perspective maps planes to planes), so along a span
//         w(x + 1) = w(x) - A/C,  w = 1/z,
//     where Ax + By + Cw + D = 0 is the plane through the three projected
//     vertices (x_i, y_i, 1/z_i);
//   - the attributes (here the barycentric weights, which carry every vertex
//     attribute: colour, normal, position) by bilinear interpolation: down the
//     left and the right edge, then across the span (Gouraud 1971). For
//     perspective-correct interpolation the weights divided by z are
//     interpolated (they are affine in screen space) and divided by their sum,
//     the interpolated 1/z, per sample (Heckbert and Moreton 1991).
//
// Samples: pixel row j with spp = n*n samples holds n (regular grid) or n*n
// (rotated grid) sample rows y = 256 j + oy. Each distinct oy is scanned as its
// own sequence of rows one pixel apart (a "pass" with its own ET and AEL), so
// that every step down an edge is the same 256 units. So the scan of one
// sample row (scan_row: AEL update, spans, step) is the lecture's algorithm
// as it stands, and supersampling is only the loop around it (scan_frame: per
// pixel row, every pass's sample row). The z-buffer itself is one pixel row
// high (Foley 15.4's scan-line z-buffer): the visible fragment of each sample
// of the row is kept, and shaded once the row is done.
//
// Ties: within a row the active triangles are visited in scene order and a
// sample keeps the first of equal depths, as in ref::zbuffer.
#include "reference/scanline.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace lockstep {

namespace {

int64_t ceil_div(int64_t a, int64_t d) { return -floor_div(-a, d); }

// ---------------------------------------------------------------- sample rows

// One pass: the sample rows y = 256 j + oy of every pixel row j, and the
// samples on such a row: sample k of the pixel at x = 256 i + ox.
struct Column {
  int k = 0;
  int32_t ox = 0;
};
struct Pass {
  int32_t oy = 0;
  std::vector<Column> columns;
};

std::vector<Pass> passes_of(const std::vector<std::array<int32_t, 2>>& offsets) {
  std::vector<Pass> passes;
  for (int k = 0; k < int(offsets.size()); ++k) {
    auto it = std::find_if(passes.begin(), passes.end(),
                           [&](const Pass& p) { return p.oy == offsets[k][1]; });
    if (it == passes.end()) {
      passes.push_back({offsets[k][1], {}});
      it = passes.end() - 1;
    }
    it->columns.push_back({k, offsets[k][0]});
  }
  return passes;
}

// ---------------------------------------------------------------- edges

// The attributes interpolated bilinearly: the three barycentric weights (for
// perspective-correct interpolation, each divided by z).
using Attr = std::array<double, 3>;

// An edge of triangle `tri`, as the AEL holds it on its current row.
struct Edge {
  uint32_t tri = 0;
  bool left = false;  // dy < 0 (going up): the triangle is to its right, samples x >= the crossing
  int last_row = 0;   // the last pixel row j whose sample row it crosses
  // The exact crossing (Foley 3.6): with E = C0 - dy * x the edge function on
  // the row, M = C0 (left) or C0 - 1 (right) = q * D + r, 0 <= r < D = |dy|:
  // the first sample x a left edge accepts is -q, the last a right edge accepts is q.
  int64_t D = 1, q = 0, r = 0;
  int64_t qs = 0, rs = 0;  // the step of M per row, 256 dx = qs * D + rs
  // Down the edge, per row: 1/z and the attributes at the crossing (linear in y).
  double w = 0, dw = 0;
  Attr a{}, da{};

  // The first (left edge) or last (right edge) sample x on the row, in 1/256 pixel.
  int64_t bound() const { return left ? -q : q; }
  // Where the edge crosses the row, in pixels (M's exact quotient, rounded once).
  double crossing() const {
    const double x =
        left ? -(double(q) + double(r) / double(D)) : double(q) + double(r + 1) / double(D);
    return x / kSubpixel;
  }
  // One row down: the integer walk carries the remainder; 1/z and the
  // attributes add their per-row increments.
  void step() {
    q += qs;
    r += rs;
    if (r >= D) {
      r -= D;
      q += 1;
    }
    w += dw;
    for (int k = 0; k < 3; ++k) a[k] += da[k];
  }
};

// A triangle's vertices in pixels, their 1/z, their attributes, and the plane of 1/z.
struct TriSetup {
  double x[3], y[3], w[3];
  Attr a[3];
  double dwdx = 0;  // -A/C: the change of 1/z per pixel along a row
};

TriSetup setup_triangle(const ScreenTri& t, bool perspective) {
  TriSetup ts;
  for (int k = 0; k < 3; ++k) {
    ts.x[k] = double(t.v[k].x) / kSubpixel;
    ts.y[k] = double(t.v[k].y) / kSubpixel;
    ts.w[k] = 1 / t.v[k].z;
    // Vertex k's weights are the unit vector e_k; perspective-correct: e_k / z_k.
    ts.a[k] = {0, 0, 0};
    ts.a[k][k] = perspective ? ts.w[k] : 1.0;
  }
  // The plane Ax + By + Cw + D = 0 through (x_k, y_k, w_k): (A, B, C) = (P1 - P0) x (P2 - P0).
  // The screen differences are exact (multiples of 1/256 below 2^25).
  const double ex1 = ts.x[1] - ts.x[0], ey1 = ts.y[1] - ts.y[0], ew1 = ts.w[1] - ts.w[0];
  const double ex2 = ts.x[2] - ts.x[0], ey2 = ts.y[2] - ts.y[0], ew2 = ts.w[2] - ts.w[0];
  const double A = ey1 * ew2 - ew1 * ey2;
  const double C = ex1 * ey2 - ey1 * ex2;  // twice the screen area: > 0
  ts.dwdx = -A / C;
  return ts;
}

// The edge a -> b of triangle tri (a, b: vertex numbers) for the pass with
// sample rows at oy, starting on pixel row j0 (its first row on screen); false
// when it is horizontal or crosses no sample row of the pass on screen.
// bottom_cut: the triangle's bottom is a horizontal edge at the edge's lower
// end, which owns no sample on its own row (the top-left rule), so the edge
// stops above it.
bool make_edge(const ScreenTri& t, const TriSetup& ts, uint32_t tri, int a, int b, int32_t oy,
               int height, bool bottom_cut, Edge& e, int& first_row) {
  const ScreenVertex &va = t.v[a], &vb = t.v[b];
  const int64_t dx = int64_t(vb.x) - va.x, dy = int64_t(vb.y) - va.y;
  if (dy == 0) return false;  // horizontal: decided by the other two edges and bottom_cut
  e.tri = tri;
  e.left = dy < 0;
  e.D = std::abs(dy);
  // Top and bottom vertex (y down: top has the smaller y).
  const int top = dy < 0 ? b : a, bot = dy < 0 ? a : b;
  const int64_t ytop = t.v[top].y, ybot = t.v[bot].y;
  // The sample rows y = 256 j + oy with ytop <= y <= ybot (< ybot when cut).
  int64_t j0 = ceil_div(ytop - oy, kSubpixel);
  int64_t j1 = floor_div(ybot - oy - (bottom_cut ? 1 : 0), kSubpixel);
  j0 = std::max<int64_t>(j0, 0);
  j1 = std::min<int64_t>(j1, height - 1);
  if (j0 > j1) return false;
  first_row = int(j0);
  e.last_row = int(j1);
  // The edge function on sample row y: E(x) = dx (y - ya) - dy (x - xa) = C0 - dy x.
  const int64_t y = j0 * kSubpixel + oy;
  const int64_t C0 = dx * (y - va.y) + dy * va.x;
  const int64_t M = e.left ? C0 : C0 - 1;  // left: E >= 0 (owns E = 0); right: E > 0, i.e. E >= 1
  e.q = floor_div(M, e.D);
  e.r = M - e.q * e.D;
  const int64_t Ms = dx * kSubpixel;  // M's change per row
  e.qs = floor_div(Ms, e.D);
  e.rs = Ms - e.qs * e.D;
  // 1/z and the attributes at the crossing, linear in y from the top vertex
  // to the bottom one; the step per row is their change per pixel of y.
  const double yrow = double(y) / kSubpixel;
  const double len = ts.y[bot] - ts.y[top];
  const double s = (yrow - ts.y[top]) / len;
  e.w = ts.w[top] + s * (ts.w[bot] - ts.w[top]);
  e.dw = (ts.w[bot] - ts.w[top]) / len;
  for (int k = 0; k < 3; ++k) {
    e.a[k] = ts.a[top][k] + s * (ts.a[bot][k] - ts.a[top][k]);
    e.da[k] = (ts.a[bot][k] - ts.a[top][k]) / len;
  }
  return true;
}

// ---------------------------------------------------------------- the edge table

// The edge table of one pass (sample rows y = 256 j + oy): every edge of every
// triangle, in the bucket of the first pixel row j whose sample row it
// crosses; within a bucket in scene order.
std::vector<std::vector<Edge>> edge_table(const ScreenMesh& mesh,
                                          const std::vector<TriSetup>& setups, int32_t oy) {
  std::vector<std::vector<Edge>> et(size_t(mesh.height));
  for (uint32_t ti = 0; ti < mesh.tris.size(); ++ti) {
    const ScreenTri& t = mesh.tris[ti];
    // A flat bottom: two vertices on the lowest row, joined by a horizontal
    // edge that (positive area, y down) runs right to left and owns no
    // sample on its row (top-left rule). Both other edges end there: cut.
    const int32_t ymax = std::max({t.v[0].y, t.v[1].y, t.v[2].y});
    const bool flat_bottom = (t.v[0].y == ymax) + (t.v[1].y == ymax) + (t.v[2].y == ymax) == 2;
    for (int a = 0; a < 3; ++a) {
      const int b = (a + 1) % 3;
      Edge e;
      int first = 0;
      if (make_edge(t, setups[ti], ti, a, b, oy, mesh.height, flat_bottom, e, first))
        et[first].push_back(e);
    }
  }
  return et;
}

// ---------------------------------------------------------------- one span

// The samples of triangle ti on one sample row between its left edge L and its
// right edge R (both crossing the row): 1/z with the plane's constant slope
// -A/C, the attributes linear between their values on the two edges, one
// sample right at a time. Each sample goes to on_sample(index, fragment).
template <class OnSample>
void scan_span(const Edge& L, const Edge& R, const TriSetup& ts, uint32_t ti, const Pass& pass,
               int j, int width, int spp, bool perspective, OnSample& on_sample) {
  const double yrow = double(int64_t(j) * kSubpixel + pass.oy) / kSubpixel;
  const double xl = L.crossing(), xr = R.crossing();
  Attr slope{};
  if (xr > xl)
    for (int k = 0; k < 3; ++k) slope[k] = (R.a[k] - L.a[k]) / (xr - xl);
  for (const Column& col : pass.columns) {
    // The samples x = 256 i + ox with L.bound <= x <= R.bound, on screen.
    const int64_t i0 = std::max<int64_t>(ceil_div(L.bound() - col.ox, kSubpixel), 0);
    const int64_t i1 = std::min<int64_t>(floor_div(R.bound() - col.ox, kSubpixel), width - 1);
    if (i0 > i1) continue;
    // Values at the first sample, from the left edge's crossing.
    const double x0 = double(i0 * kSubpixel + col.ox) / kSubpixel;
    double wz = L.w + (x0 - xl) * ts.dwdx;
    Attr a;
    for (int k = 0; k < 3; ++k) a[k] = L.a[k] + (x0 - xl) * slope[k];
    for (int64_t i = i0; i <= i1; ++i) {
      Fragment f;
      f.tri = ti;
      f.z = 1 / wz;
      f.sx = double(i * kSubpixel + col.ox) / kSubpixel;
      f.sy = yrow;
      if (perspective) {
        // The interpolated weights / z, divided by their sum (the interpolated 1/z).
        const double sum = a[0] + a[1] + a[2];
        for (int k = 0; k < 3; ++k) f.b[k] = a[k] / sum;
      } else {
        for (int k = 0; k < 3; ++k) f.b[k] = a[k];
      }
      on_sample((size_t(j) * width + size_t(i)) * spp + col.k, f);
      // One sample (one pixel) right.
      wz += ts.dwdx;
      for (int k = 0; k < 3; ++k) a[k] += slope[k];
    }
  }
}

// ---------------------------------------------------------------- one sample row

// Scans the sample row of pixel row j in one pass (y = 256 j + pass.oy):
// `starting` is the pass's edge-table bucket for row j, `active` its active
// edge list, carried from the row above to the row below. Every covered
// sample goes to on_sample(index, fragment), the triangles in scene order.
template <class OnSample>
void scan_row(const std::vector<TriSetup>& setups, const Pass& pass, int j, int width, int spp,
              bool perspective, const std::vector<Edge>& starting, std::vector<Edge>& active,
              OnSample& on_sample) {
  // 1. Edges starting on this row join the AEL; edges that ended leave it.
  for (const Edge& e : starting) active.push_back(e);
  std::erase_if(active, [&](const Edge& e) { return e.last_row < j; });
  // 2. Group by triangle in scene order (the tie rule), left edges first.
  std::sort(active.begin(), active.end(), [](const Edge& a, const Edge& b) {
    return a.tri != b.tri ? a.tri < b.tri : a.left > b.left;
  });
  // 3. One span per triangle: between its innermost left and right edge.
  for (size_t g = 0; g < active.size();) {
    size_t end = g;
    const Edge *L = nullptr, *R = nullptr;
    for (; end < active.size() && active[end].tri == active[g].tri; ++end) {
      const Edge& e = active[end];
      // Two edges of one side are active together only on the row of
      // their shared vertex; the inner one bounds the span.
      if (e.left && (!L || e.bound() > L->bound())) L = &e;
      if (!e.left && (!R || e.bound() < R->bound())) R = &e;
    }
    const uint32_t ti = active[g].tri;
    g = end;
    if (!L || !R || L->bound() > R->bound()) continue;  // no sample on this row
    scan_span(*L, *R, setups[ti], ti, pass, j, width, spp, perspective, on_sample);
  }
  // 4. Every active edge one row down.
  for (Edge& e : active) e.step();
}

// ---------------------------------------------------------------- the frame

// The scan of the whole frame: pixel row by pixel row, and within a pixel row
// the supersampling passes, each scanning its own sample row (scan_row). Every
// covered sample is handed to on_sample(index, fragment); on_row(j) is called
// when pixel row j is complete (all its samples scanned).
template <class OnSample, class OnRow>
void scan_frame(const ScreenMesh& mesh, const RasterSettings& s,
                const std::function<void(double)>& progress, OnSample on_sample, OnRow on_row) {
  const auto offsets = sample_offsets(s);
  const int spp = int(offsets.size());
  const std::vector<Pass> passes = passes_of(offsets);

  // Per triangle: the vertices in pixels and the plane of 1/z.
  std::vector<TriSetup> setups;
  setups.reserve(mesh.tris.size());
  for (const ScreenTri& t : mesh.tris) setups.push_back(setup_triangle(t, s.perspective));

  // Per pass: its edge table and its active edge list.
  std::vector<std::vector<std::vector<Edge>>> et;
  for (const Pass& pass : passes) et.push_back(edge_table(mesh, setups, pass.oy));
  std::vector<std::vector<Edge>> ael(passes.size());

  for (int j = 0; j < mesh.height; ++j) {
    if (progress && (j & 15) == 0) progress(double(j) / mesh.height);
    for (size_t p = 0; p < passes.size(); ++p)
      scan_row(setups, passes[p], j, mesh.width, spp, s.perspective, et[p][j], ael[p], on_sample);
    on_row(j);
  }
}

}  // namespace

namespace ref {

void scanline_fragments(const ScreenMesh& mesh, const RasterSettings& s,
                        const std::function<void(size_t sample, const Fragment& f)>& on_sample) {
  scan_frame(
      mesh, s, {}, [&](size_t index, const Fragment& f) { on_sample(index, f); }, [](int) {});
}

void scanline_visibility(const ScreenMesh& mesh, const RasterSettings& s, Visibility& vis) {
  const size_t samples = size_t(mesh.width) * mesh.height * sample_offsets(s).size();
  vis.width = mesh.width;
  vis.height = mesh.height;
  vis.spp = int(sample_offsets(s).size());
  vis.tri.assign(samples, Visibility::kNone);
  vis.depth.assign(samples, empty_depth(s.depth));
  vis.count.assign(samples, 0);
  scan_frame(
      mesh, s, {},
      [&](size_t index, const Fragment& f) {
        ++vis.count[index];
        const double d = stored_depth(s.depth, f.z, mesh.near_z, mesh.far_z);
        if (!nearer(s.depth, d, vis.depth[index])) return;  // the first of equal depths stays
        vis.depth[index] = d;
        vis.tri[index] = f.tri;
      },
      [](int) {});
}

Image scanline(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  const RasterSettings s = frame_settings(scene, opts);
  const ScreenMesh mesh = view_scene(scene, opts.width, opts.height, s);
  const int w = opts.width, spp = int(sample_offsets(s).size());

  // The one-row z-buffer: per sample of the current pixel row, the stored
  // depth and the visible fragment (shaded when the row is done).
  const size_t row = size_t(w) * spp;
  std::vector<double> depth(row, empty_depth(s.depth));
  std::vector<Fragment> visible(row);
  std::vector<bool> hit(row, false);

  Image image(opts.width, opts.height);
  image.depth.assign(size_t(opts.width) * opts.height, float(kInfinity));
  scan_frame(
      mesh, s, opts.progress,
      [&](size_t index, const Fragment& f) {
        const size_t k = index % row;  // the sample within its pixel row
        const double d = stored_depth(s.depth, f.z, mesh.near_z, mesh.far_z);
        if (!nearer(s.depth, d, depth[k])) return;
        depth[k] = d;
        visible[k] = f;
        hit[k] = true;
      },
      [&](int j) {
        // Shade the row's visible fragments, box-filter each pixel's samples.
        for (int i = 0; i < w; ++i) {
          Vec3 sum;
          float z = float(kInfinity);
          for (int k = 0; k < spp; ++k) {
            const size_t x = size_t(i) * spp + k;
            if (!hit[x]) {
              sum += Vec3(Vec3f(scene.background));
              continue;
            }
            // Colours are kept in float per sample, as ref::zbuffer keeps them.
            sum += Vec3(Vec3f(shade_fragment(scene, mesh, s, visible[x])));
            z = std::min(z, float(visible[x].z));
          }
          image.set(i, j, sum / double(spp));
          image.depth[size_t(j) * w + i] = z;
        }
        std::fill(depth.begin(), depth.end(), empty_depth(s.depth));
        std::fill(hit.begin(), hit.end(), false);
      });
  if (stats) {
    stats->items = mesh.scene_tris + mesh.sphere_tris;
    stats->dropped = mesh.dropped;
  }
  if (opts.progress) opts.progress(1.0);
  return image;
}

// ---------------------------------------------------------------- the interpolation lessons

std::array<double, 3> barycentric(const ScreenValue& a, const ScreenValue& b, const ScreenValue& c,
                                  double px, double py) {
  // Twice the signed area of (p, q, r).
  auto area = [](double x0, double y0, double x1, double y1, double x2, double y2) {
    return (x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0);
  };
  const double whole = area(a.x, a.y, b.x, b.y, c.x, c.y);
  return {area(px, py, b.x, b.y, c.x, c.y) / whole, area(a.x, a.y, px, py, c.x, c.y) / whole,
          area(a.x, a.y, b.x, b.y, px, py) / whole};
}

double bilinear_polygon(std::span<const ScreenValue> polygon, double px, double py) {
  // Every edge that crosses the row y = py gives a point (x, value) on the
  // row, its value linear in y along the edge.
  double xl = kInfinity, vl = 0, xr = -kInfinity, vr = 0;
  const size_t n = polygon.size();
  for (size_t e = 0; e < n; ++e) {
    const ScreenValue& a = polygon[e];
    const ScreenValue& b = polygon[(e + 1) % n];
    if (a.y == b.y) continue;  // horizontal: its ends are on the neighbouring edges
    const double lo = std::min(a.y, b.y), hi = std::max(a.y, b.y);
    if (py < lo || py > hi) continue;
    const double t = (py - a.y) / (b.y - a.y);  // down the edge
    const double x = a.x + t * (b.x - a.x);
    const double v = a.value + t * (b.value - a.value);
    if (x < xl) xl = x, vl = v;
    if (x > xr) xr = x, vr = v;
  }
  if (!(xr > xl)) return vl;  // a span of one point (a vertex)
  // Across the span.
  return vl + (px - xl) / (xr - xl) * (vr - vl);
}

}  // namespace ref

}  // namespace lockstep
