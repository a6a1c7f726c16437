// The optimized z-buffer (contract: core/raster.h, optimized/zbuffer/zbuffer_simd.h).
//
//   1. Set-up and binning (Binner; TBB over chunks of triangles): one TriSetup
//      per screen triangle (exact int64 edge functions with the top-left bias,
//      the depth plane, the shading planes) and its sample bounding box,
//      appended to the lists of the tiles that box touches. Each chunk keeps
//      its own lists, so a tile reads its triangles chunk by chunk: in mesh order.
//   2. Tiles (optimized/tiling.h, work-stealing over the threads): raster the
//      tile's triangles into tile-local buffers (zbuffer_raster_kernels.cpp), then
//      either copy them into the Visibility (zbuffer_visibility) or shade the
//      visible samples and box-filter them into the image (zbuffer), while the
//      tile is still in cache. Flat shading without silhouettes is drawn
//      forward: the raster writes each passing sample's 1/z and colour, and
//      shading has no per-triangle work left; the other shadings are deferred
//      (the visible triangle per sample, then its planes). A tile whose
//      triangles come back to front is drawn in reverse with ties winning
//      (the same buffers; RasterSettings::order), so hidden samples write nothing.
// The screen mesh is view_scene's (viewing, culling, clipping, sphere
// tessellation, snapping), made by zsimd::view_scene_chunks (zbuffer_setup.cpp)
// with the same coordinates bit for bit; for the image it hands each triangle
// straight to the Binner (no ScreenTri is kept; for forward flat shading only
// positions and vertex depths, a sphere at a time), leaves out triangles with
// no sample in their box and those hidden behind nearer spheres (same image:
// see zbuffer_occlusion.h), and lights flat colours in SIMD.
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <type_traits>

#include "core/error.h"
#include "core/shading.h"
#include "core/shadow_map.h"
#include "hwy/aligned_allocator.h"
#include "optimized/zbuffer/zbuffer_simd.h"
#include "optimized/tiling.h"
#include "optimized/zbuffer/zbuffer_simd_kernels.h"

namespace lockstep::opt::simd {

namespace {

using zsimd::RasterParams;
using zsimd::TileJob;
using zsimd::TriSetup;

// Tiles: at most 256 x 128 samples per tile (buffers of 256 KB: in L2; large
// tiles repeat less per-triangle work at their edges: 6-8% faster frames on
// small triangles than 64 x 64), fewer pixels when supersampling, and smaller
// tiles (not below 64 x 64 pixels) while the frame has fewer than 32 of them
// (so that both threads stay busy on small frames).
void tile_size(int spp, int width, int height, int& tw, int& th) {
  tw = 256, th = 128;
  auto halve = [&] { (th > 16 && th >= tw) ? th /= 2 : tw /= 2; };
  while (tw > 16 && tw * th * spp > 256 * 128) halve();
  auto tiles = [&] { return long((width + tw - 1) / tw) * long((height + th - 1) / th); };
  while (tiles() < 32 && tw * th > 64 * 64) halve();
}

using zsimd::DepthMap;

// kFixed24 rasters in double too: its 24-bit codes need more than float's 24-bit
// significand (a float window depth near 1 is only good to one code, and the
// plane's rounding adds a few more).
bool double_depth(DepthFormat f) { return f == DepthFormat::kDouble || f == DepthFormat::kFixed24; }

// A triangle's TriSetup from its snapped vertices (x[k], y[k]) and their w and
// stored depth q (for the double raster: its corners, else the forward part;
// the flat colour left to set_flats); inv_area: 1 / (twice its snapped area),
// for set_up_shading.
void set_up(const int32_t x[3], const int32_t y[3], const double w[3], const double q[3],
            const zsimd::SampleGrid& grid, bool double_raster, TriSetup& t, double& inv_area) {
  int64_t xmin = x[0], xmax = x[0], ymin = y[0], ymax = y[0];
  for (int k = 1; k < 3; ++k) {
    xmin = std::min<int64_t>(xmin, x[k]), xmax = std::max<int64_t>(xmax, x[k]);
    ymin = std::min<int64_t>(ymin, y[k]), ymax = std::max<int64_t>(ymax, y[k]);
  }
  int32_t i0, i1, j0, j1;
  grid.pixels(xmin, xmax, ymin, ymax, i0, i1, j0, j1);
  t.set_box(i0, i1, j0, j1);
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    const int64_t dx = int64_t(x[b]) - x[a], dy = int64_t(y[b]) - y[a];
    t.ax[k] = x[a], t.ay[k] = y[a];
    t.ex[k] = int32_t(-dy), t.ey[k] = int32_t(dx);
    const bool top_left = (dy == 0 && dx > 0) || dy < 0;
    t.bias[k] = top_left ? 0 : 1;  // (uint8_t)
  }
  // Plane through the three vertices' values, from the barycentric gradients
  // b_k = E_k / A (A = E_2(v2), twice the area in snapped units).
  const double area = double(int64_t(t.ex[2]) * (int64_t(x[2]) - t.ax[2]) +
                             int64_t(t.ey[2]) * (int64_t(y[2]) - t.ay[2]));
  inv_area = 1 / area;
  // The depth plane divides by the area (not times 1/area): the depth test's
  // numbers, kept within a few ulps of the reference's (CoverageAgreement).
  t.q0 = q[0];
  t.qx = ((q[1] - q[0]) * double(t.ex[1]) + (q[2] - q[0]) * double(t.ex[2])) / area;
  t.qy = ((q[1] - q[0]) * double(t.ey[1]) + (q[2] - q[0]) * double(t.ey[2])) / area;
  if (double_raster) {
    for (int k = 0; k < 3; ++k) t.dbl.qv[k] = q[k];
    t.dbl.area = area;
    return;
  }
  t.fwd.w0 = w[0];
  t.fwd.wx = ((w[1] - w[0]) * double(t.ex[1]) + (w[2] - w[0]) * double(t.ex[2])) * inv_area;
  t.fwd.wy = ((w[1] - w[0]) * double(t.ey[1]) + (w[2] - w[0]) * double(t.ey[2])) * inv_area;
}

// The same from a ScreenTri; vd: its vertices' w and stored depth, or null
// (then worked out here with depth). w: the vertices' 1/z, for set_up_shading.
void set_up(const ScreenTri& tri, const zsimd::VertexDepth* vd, const DepthMap& depth,
            const zsimd::SampleGrid& grid, bool double_raster, TriSetup& t, double w[3],
            double& inv_area) {
  const auto& v = tri.v;
  const int32_t x[3] = {v[0].x, v[1].x, v[2].x}, y[3] = {v[0].y, v[1].y, v[2].y};
  double q[3];
  for (int k = 0; k < 3; ++k) {
    w[k] = vd ? vd[k].w : 1 / v[k].z;
    q[k] = vd ? vd[k].q : depth(v[k].z, w[k]);
  }
  set_up(x, y, w, q, grid, double_raster, t, inv_area);
  if (!double_raster)
    for (int c = 0; c < 3; ++c) t.fwd.flat[c] = float(tri.flat_color[c]);
}

// How many of ShadeTri's plane rows a shading needs: 1/z always, the normal
// for lighting and silhouettes, the colour for Gouraud.
int shade_rows(const RasterSettings& s) {
  if (s.shading == Shading::kGouraud) return 7;
  if (s.shading != Shading::kFlat || s.silhouette) return 4;
  return 1;
}

// The shading data of a triangle (see zsimd::ShadeTri): out, its flat colour
// (kFlat only: else null), and its rows of attribute planes at planes (a0, ax,
// ay per row).
void set_up_shading(const Scene& scene, const RasterSettings& s, const ScreenTri& tri,
                    const TriSetup& t, const double w[3], double inv_area, zsimd::ShadeTri& out,
                    std::array<float, 3>* flat, double* planes) {
  const auto& v = tri.v;
  const int rows = shade_rows(s);
  for (int row = 0; row < rows; ++row) {
    double a[3];
    for (int k = 0; k < 3; ++k) {
      const ScreenVertex& x = v[k];
      double value = 1.0;
      switch (row) {
        case 1:
          value = x.normal.x;
          break;
        case 2:
          value = x.normal.y;
          break;
        case 3:
          value = x.normal.z;
          break;
        case 4:
          value = x.color.x;
          break;
        case 5:
          value = x.color.y;
          break;
        case 6:
          value = x.color.z;
          break;
      }
      // 1/z and, under perspective, attribute / z: affine in screen space.
      a[k] = row == 0 ? w[k] : s.perspective ? value * w[k] : value;
    }
    double* c = planes + 3 * row;
    c[0] = a[0];
    c[1] = ((a[1] - a[0]) * double(t.ex[1]) + (a[2] - a[0]) * double(t.ex[2])) * inv_area;
    c[2] = ((a[1] - a[0]) * double(t.ey[1]) + (a[2] - a[0]) * double(t.ey[2])) * inv_area;
  }
  out.material = scene.material_id_of_prim(tri.prim);
  if (flat)
    *flat = {float(tri.flat_color.x), float(tri.flat_color.y), float(tri.flat_color.z)};
  out.face[0] = float(tri.face_normal.x), out.face[1] = float(tri.face_normal.y),
  out.face[2] = float(tri.face_normal.z);
}

// One chunk of the binned mesh: per triangle its TriSetup, and for shading its
// TilePlanes (the ShadeTri; the planes too where ready: set_up_shaded's), its
// `rows` attribute planes in double (a0, ax, ay per row) where they are not,
// and under flat shading its colour; per tile the chunk's triangles there
// (indices into the chunk), in mesh order.
// (Not value-initialised: the set-ups write every field that is read.)
template <class T>
using Uninit = std::vector<T, NoInitAllocator<T>>;
struct BinChunk {
  Uninit<TriSetup> setup;
  Uninit<zsimd::TilePlanes> local;
  Uninit<uint8_t> ready;  // 1: local's planes are ready for the one tile the triangle meets
  Uninit<double> planes;
  Uninit<std::array<float, 3>> flat;  // kFlat only
  std::vector<std::vector<uint32_t>> bins;
  uint32_t first = 0;  // the mesh id of the chunk's first triangle
};

// The triangles binned to tiles, chunk by chunk: the z-buffer's set-up (the
// image path feeds it from view_scene_chunks directly, as a TriSink; the
// visibility and shade_visibility from a ScreenMesh, bin_mesh). With scene:
// shading is set up too.
class Binner final : public zsimd::TriSink {
 public:
  Binner(const RasterSettings& s, const std::vector<std::array<int32_t, 2>>& off,
         const Scene* scene)
      : s_(s),
        off_(off),
        scene_(scene),
        double_raster_(double_depth(s.depth)),
        flat_(scene != nullptr && s.shading == Shading::kFlat),
        rows(shade_rows(s)) {}

  void begin(const ScreenMesh& frame, size_t nchunks) override {
    tile_size(int(off_.size()), frame.width, frame.height, tw, th);
    ntx = (frame.width + tw - 1) / tw;
    nty = (frame.height + th - 1) / th;
    tw_log2 = std::countr_zero(unsigned(tw)), th_log2 = std::countr_zero(unsigned(th));
    grid_ = zsimd::SampleGrid(off_, frame.width, frame.height);
    depth_ = DepthMap(s_.depth, frame.near_z, frame.far_z);
    chunks.resize(nchunks);
    for (BinChunk& c : chunks) c.bins.resize(size_t(ntx) * size_t(nty));
  }

  void reserve(size_t c, size_t n) override {
    chunks[c].setup.reserve(n);
    if (scene_) {
      chunks[c].local.reserve(n), chunks[c].ready.reserve(n);
      chunks[c].planes.reserve(n * size_t(rows) * 3);
    }
    if (flat_) chunks[c].flat.reserve(n);
  }

  size_t add(size_t c, const ScreenTri& tri, const zsimd::VertexDepth* vd) override {
    BinChunk& ch = chunks[c];
    const size_t at = ch.setup.size();
    TriSetup& t = ch.setup.emplace_back();
    double w[3], inv_area;
    set_up(tri, vd, depth_, grid_, double_raster_, t, w, inv_area);
    if (scene_) {
      ch.planes.resize(ch.planes.size() + size_t(rows) * 3);
      std::array<float, 3>* flat = flat_ ? &ch.flat.emplace_back() : nullptr;
      ch.ready.push_back(0);
      set_up_shading(*scene_, s_, tri, t, w, inv_area, ch.local.emplace_back().tri, flat,
                     ch.planes.data() + ch.planes.size() - size_t(rows) * 3);
    }
    bin(ch, t, at);
    return at;
  }

  bool positions_only() const override { return scene_ == nullptr; }
  bool double_raster() const { return double_raster_; }
  const DepthMap& depth() const { return depth_; }
  size_t add_positions(size_t c, const zsimd::IndexedTris& tris, size_t n,
                       bool tested = false) override {
    return add_positions_t(c, tris, n, tested, [&](size_t i, int k, int32_t& x, int32_t& y,
                                                   double& w, double& q) {
      const uint32_t v = (k == 0 ? tris.a : k == 1 ? tris.b : tris.c)[i];
      x = tris.pv[v].x, y = tris.pv[v].y, w = tris.vd[v].w, q = tris.vd[v].q;
    });
  }
  size_t add_positions(size_t c, const zsimd::TriVertices& tris, size_t n,
                       bool tested = false) override {
    return add_positions_t(c, tris, n, tested, [&](size_t i, int k, int32_t& x, int32_t& y,
                                                   double& w, double& q) {
      x = tris.x[k][i], y = tris.y[k][i], w = tris.w[k][i], q = tris.q[k][i];
    });
  }

  bool shaded_bulk() const override {
    return scene_ != nullptr && !double_raster_ && rows == 4 && s_.shading != Shading::kFlat;
  }
  // The set-ups and the shading's planes in SIMD (set_up_shaded: the same bits
  // as set_up's and set_up_shading's, and for a triangle in one tile as
  // shade_one_tile's for it), then per triangle its ShadeTri.
  size_t add_shaded(size_t c, const zsimd::IndexedTris& tris, size_t n,
                    const zsimd::ShadedTris& sh) override {
    BinChunk& ch = chunks[c];
    const size_t first = ch.setup.size();
    ch.setup.resize(first + n);
    ch.local.resize(first + n);
    ch.ready.resize(first + n);
    ch.planes.resize((first + n) * 4 * 3);
    zsimd::set_up_shaded(tris, n, grid_, ch.setup.data() + first, sh.normal, sh.negate,
                         s_.perspective,
                         {ch.local.data() + first, ch.ready.data() + first,
                          ch.planes.data() + first * 4 * 3, tw_log2, th_log2});
    for (size_t i = 0; i < n; ++i) {
      const TriSetup& t = ch.setup[first + i];
      zsimd::ShadeTri& st = ch.local[first + i].tri;
      for (int k = 0; k < 3; ++k) st.face[k] = float(sh.face[k][i]);
      st.material = sh.material;
      bin(ch, t, first + i);
    }
    return first;
  }

  // Either form: the float raster drawn forward sets them up in SIMD, the
  // double one one at a time (vertex(i, k, x, y, w, q): triangle i's vertex k).
  template <class Tris, class Vertex>
  size_t add_positions_t(size_t c, const Tris& tris, size_t n, bool tested, const Vertex& vertex) {
    BinChunk& ch = chunks[c];
    const size_t first = ch.setup.size();
    ch.setup.resize(first + n);
    if (!double_raster_) {
      zsimd::set_up_forward(tris, n, grid_, ch.setup.data() + first, tested);
      for (size_t i = 0; i < n; ++i) bin(ch, ch.setup[first + i], first + i);
      return first;
    }
    for (size_t i = 0; i < n; ++i) {
      int32_t x[3], y[3];
      double w[3], q[3];
      for (int k = 0; k < 3; ++k) vertex(i, k, x[k], y[k], w[k], q[k]);
      TriSetup& t = ch.setup[first + i];
      double inv_area;
      set_up(x, y, w, q, grid_, double_raster_, t, inv_area);
      bin(ch, t, first + i);
    }
    return first;
  }

  // Triangle at of chunk ch into the bins of the tiles its box meets (none:
  // no sample in its box).
  void bin(BinChunk& ch, const TriSetup& t, size_t at) {
    if (t.i0 > t.i1 || t.j0 > t.j1) return;
    // (Tiles are powers of two: shifts, not divisions, for the pixels' tiles.)
    for (int ty = t.j0 >> th_log2; ty <= t.j1 >> th_log2; ++ty)
      for (int tx = t.i0 >> tw_log2; tx <= t.i1 >> tw_log2; ++tx)
        ch.bins[size_t(ty) * size_t(ntx) + size_t(tx)].push_back(uint32_t(at));
  }

  void set_flats(size_t c, const size_t* at, size_t n, const float* const rgb[3]) override {
    BinChunk& ch = chunks[c];
    if (flat_)
      for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) ch.flat[at[i]][k] = rgb[k][i];
    if (!double_raster_)
      for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) ch.setup[at[i]].fwd.flat[k] = rgb[k][i];
  }

  // After the last triangle: each chunk's first mesh id; the triangle count.
  size_t finish() {
    size_t n = 0;
    for (BinChunk& c : chunks) c.first = uint32_t(n), n += c.setup.size();
    total = n;
    return n;
  }

  // A tile's lists of triangles, for raster_tile.
  void tile_lists(size_t tile, std::vector<zsimd::TileList>& out) const {
    out.clear();
    for (const BinChunk& c : chunks)
      if (!c.bins[tile].empty()) out.push_back({&c.bins[tile], c.setup.data(), int32_t(c.first)});
  }
  size_t tile_of(int x0, int y0) const { return size_t(y0 / th) * size_t(ntx) + size_t(x0 / tw); }
  // Whether the chunks hold flat colours (BinChunk::flat).
  bool flat_shading() const { return flat_; }

  int tw = 64, th = 64, ntx = 0, nty = 0;
  int tw_log2 = 6, th_log2 = 6;
  std::vector<BinChunk> chunks;
  size_t total = 0;

 private:
  RasterSettings s_;
  std::vector<std::array<int32_t, 2>> off_;
  const Scene* scene_;
  bool double_raster_;
  bool flat_;  // shading set up, flat: BinChunk::flat
  zsimd::SampleGrid grid_;
  DepthMap depth_;

 public:
  const int rows;  // attribute planes per triangle
};

// The triangles of mesh, binned (ids: mesh ids), chunks of 4096 in parallel.
// With scene: also set up shading.
void bin_mesh(const ScreenMesh& mesh, int threads, Binner& b) {
  const size_t n = mesh.tris.size(), per_chunk = 4096;
  const size_t nchunks = (n + per_chunk - 1) / per_chunk;
  b.begin(mesh, nchunks);
  auto chunk = [&](size_t c) {
    const size_t first = c * per_chunk, last = std::min(n, first + per_chunk);
    b.reserve(c, last - first);
    if (b.positions_only() && !b.double_raster()) {
      // The image path's set-up (set_up_forward) on the mesh's positions, so
      // that the visibility properties check it too: three vertices a
      // triangle, triangle i's 3i, 3i + 1, 3i + 2.
      const size_t m = last - first, padded = (m + 15) / 16 * 16;
      std::vector<zsimd::ProjectedVertex> pv(3 * m);
      std::vector<zsimd::VertexDepth> vd(3 * m);
      std::vector<uint32_t> index[3];
      for (auto& ix : index) ix.assign(padded, 0);
      for (size_t i = 0; i < m; ++i)
        for (int k = 0; k < 3; ++k) {
          const ScreenVertex& v = mesh.tris[first + i].v[size_t(k)];
          zsimd::ProjectedVertex& p = pv[3 * i + size_t(k)];
          p.z = v.z, p.x = v.x, p.y = v.y, p.inside = 1;
          zsimd::VertexDepth& d = vd[3 * i + size_t(k)];
          d.w = 1 / v.z;
          d.q = b.depth()(v.z, d.w);
          index[k][i] = uint32_t(3 * i + size_t(k));
        }
      b.add_positions(c, {pv.data(), vd.data(), index[0].data(), index[1].data(), index[2].data()},
                      m);
      return;
    }
    for (size_t id = first; id < last; ++id) b.add(c, mesh.tris[id], nullptr);
  };
  if (nchunks <= 1) {
    if (nchunks == 1) chunk(0);
  } else {
    tbb::task_arena arena(resolve_threads(threads));
    arena.execute([&] { tbb::parallel_for(size_t(0), nchunks, chunk); });
  }
  b.finish();
}

// One thread's tile buffers.
// One thread's tile buffers (vector-aligned: the kernels use aligned loads).
template <class T>
struct TileBuffers {
  size_t size = 0;
  hwy::AlignedFreeUniquePtr<T[]> depth;
  hwy::AlignedFreeUniquePtr<int32_t[]> tri, count;
  hwy::AlignedFreeUniquePtr<float[]> forward;  // w, r, g, b planes (forward flat shading)
  zsimd::ForwardFlat flat;
  std::vector<zsimd::TileList> lists;
  // slack: depth values past the last sample the kernel may read (not use): a
  // row and a vector (raster_tile's two-row blocks).
  // ids: the raster writes triangle ids (not when drawing forward).
  void reset(size_t n, size_t slack, T far_value, bool counting, bool ids = true) {
    if (n != size) {
      depth = hwy::AllocateAligned<T>(n + slack);
      tri = hwy::AllocateAligned<int32_t>(n);
      count = hwy::AllocateAligned<int32_t>(n);
      forward.reset();
      size = n;
    }
    std::fill_n(depth.get(), n, far_value);
    if (ids) std::fill_n(tri.get(), n, -1);
    if (counting) std::fill_n(count.get(), n, 0);
  }
};

// Whether a tile's triangles come back to front (the mean depth of its last 32
// nearer than that of its first 32): then the tile is drawn in reverse
// (TileJob::reverse), front to back.
bool back_to_front(const std::vector<zsimd::TileList>& lists, bool reversed_depth) {
  constexpr size_t kSample = 32;
  double first = 0, last = 0;
  size_t nf = 0, nl = 0;
  for (size_t l = 0; l < lists.size() && nf < kSample; ++l)
    for (size_t i = 0; i < lists[l].ids->size() && nf < kSample; ++i, ++nf)
      first += lists[l].tris[(*lists[l].ids)[i]].q0;
  for (size_t l = lists.size(); l-- > 0 && nl < kSample;)
    for (size_t i = lists[l].ids->size(); i-- > 0 && nl < kSample; ++nl)
      last += lists[l].tris[(*lists[l].ids)[i]].q0;
  if (nf < kSample) return false;  // few triangles: either way
  return reversed_depth ? last > first : last < first;
}

// forward: flat shading drawn forward (float depth only): buf.flat gets w and
// the colour per sample (not reset: only samples with a triangle are read).
template <class T>
void raster_one_tile(RasterParams p, const Binner& b, int x0, int y0, int x1, int y1, T far_value,
                     bool counting, bool forward, TileBuffers<T>& buf) {
  const size_t n = size_t(p.buf_w) * size_t(p.buf_h) * size_t(p.spp);
  buf.reset(n, size_t(p.buf_w) + 16, far_value, counting, !forward);
  if (forward) {
    if (!buf.forward) {
      buf.forward = hwy::AllocateAligned<float>(4 * n);
      buf.flat.w = buf.forward.get();
      for (int c = 0; c < 3; ++c) buf.flat.rgb[c] = buf.forward.get() + size_t(c + 1) * n;
    }
    p.flat = &buf.flat;
  }
  b.tile_lists(b.tile_of(x0, y0), buf.lists);
  TileJob job;
  job.x0 = x0, job.y0 = y0, job.x1 = x1, job.y1 = y1;
  job.lists = buf.lists.data();
  job.nlists = int(buf.lists.size());
  job.reverse = p.order == DrawOrder::kReverse ||
                (p.order == DrawOrder::kAuto &&
                 back_to_front(buf.lists, p.depth == DepthFormat::kReversed));
  zsimd::raster_tile(p, job, buf.depth.get(), buf.tri.get(), counting ? buf.count.get() : nullptr);
}

RasterParams raster_params(const RasterSettings& s, const Binner& b,
                           const std::vector<std::array<int32_t, 2>>& off) {
  RasterParams p;
  p.offsets = off.data();
  p.spp = int(off.size());
  p.depth = s.depth;
  p.order = s.order;
  p.buf_w = b.tw, p.buf_h = b.th;
  return p;
}

template <class T>
T far_value(DepthFormat f) {
  return f == DepthFormat::kReversed ? -std::numeric_limits<T>::infinity()
                                     : std::numeric_limits<T>::infinity();
}

template <class T>
void visibility_t(const ScreenMesh& mesh, const RasterSettings& s, int threads, Visibility& vis) {
  const auto off = sample_offsets(s);
  const int spp = int(off.size());
  vis.width = mesh.width, vis.height = mesh.height, vis.spp = spp;
  const size_t total = size_t(mesh.width) * size_t(mesh.height) * size_t(spp);
  vis.tri.assign(total, Visibility::kNone);
  vis.depth.assign(total, empty_depth(s.depth));
  vis.count.assign(total, 0);
  Binner b(s, off, nullptr);
  bin_mesh(mesh, threads, b);
  const RasterParams p = raster_params(s, b, off);
  const double empty = empty_depth(s.depth);
  tbb::enumerable_thread_specific<TileBuffers<T>> buffers;
  parallel_tiles(
      mesh.width, mesh.height, b.tw, b.th, threads, {}, [&](int x0, int y0, int x1, int y1) {
        TileBuffers<T>& buf = buffers.local();
        raster_one_tile(p, b, x0, y0, x1, y1, far_value<T>(s.depth), true, false, buf);
        for (int y = y0; y < y1; ++y)
          for (int x = x0; x < x1; ++x)
            for (int k = 0; k < spp; ++k) {
              const size_t at = (size_t(k) * b.th + size_t(y - y0)) * b.tw + size_t(x - x0);
              const size_t out = (size_t(y) * mesh.width + size_t(x)) * spp + size_t(k);
              const int32_t t = buf.tri[at];
              vis.tri[out] = t < 0 ? Visibility::kNone : uint32_t(t);
              vis.depth[out] = t < 0 ? empty : double(buf.depth[at]);
              vis.count[out] = uint16_t(std::min<int32_t>(buf.count[at], 0xffff));
            }
      });
}

// Shadow maps' pass 1 on one cube face (core/shadow_map.h FaceDistances):
// visibility_t's raster, and per texel straight from the tile's buffers the
// distance the reference stores (texel_distance of the same window depth),
// while the tile is in cache and on the tile's thread. No Visibility: its
// three arrays (14 bytes a texel, written and read again) were most of the
// simd row's pass 1 (measured in the commit that added this).
template <class T>
void distances_t(const ScreenMesh& frame, const RasterSettings& s, int threads, float* dist) {
  const auto off = sample_offsets(s);
  Binner b(s, off, nullptr);
  bin_mesh(frame, threads, b);
  const RasterParams p = raster_params(s, b, off);
  tbb::enumerable_thread_specific<TileBuffers<T>> buffers;
  parallel_tiles(
      frame.width, frame.height, b.tw, b.th, threads, {}, [&](int x0, int y0, int x1, int y1) {
        TileBuffers<T>& buf = buffers.local();
        raster_one_tile(p, b, x0, y0, x1, y1, far_value<T>(s.depth), false, false, buf);
        for (int y = y0; y < y1; ++y)
          for (int x = x0; x < x1; ++x) {
            const size_t at = size_t(y - y0) * b.tw + size_t(x - x0);
            dist[size_t(y) * size_t(frame.width) + size_t(x)] =
                buf.tri[at] < 0 ? float(kInfinity)
                                : float(texel_distance(frame, double(buf.depth[at]), x, y));
          }
      });
}

// One thread's shading buffers.
struct ShadeBuffers {
  // Per mesh triangle: its planes for the tile (valid for the tile's triangles).
  std::vector<const zsimd::TilePlanes*> where;
  // The tile's triangles whose planes were not ready, moved to the tile here
  // (only the rows the shading reads are written).
  Uninit<zsimd::LocalPlanes> planes;
  hwy::AlignedFreeUniquePtr<float[]> rgb, z;
  size_t size = 0;
};

// The lights in float, relative to the eye (the kernels' origin), and the eye
// itself (ShadeParams::origin): lights holds the per-light floats the result
// points to.
zsimd::ShadeParams light_params(const Scene& scene, const Vec3& eye, std::vector<float>& lights) {
  lights.clear();
  const double default_ip = scene.lights.empty() ? 0 : 1 / std::sqrt(double(scene.lights.size()));
  for (const Light& l : scene.lights) {
    const Vec3 ip =
        l.has_color ? l.color : Vec3{default_ip, default_ip, default_ip};  // as light_at
    lights.insert(lights.end(),
                  {float(l.position.x - eye.x), float(l.position.y - eye.y), float(l.position.z - eye.z), float(ip.x),
                   float(ip.y), float(ip.z), float(l.atten.x), float(l.atten.y), float(l.atten.z),
                   l.spot ? 1.0f : 0.0f, float(l.spot_dir.x), float(l.spot_dir.y),
                   float(l.spot_dir.z), float(spot_cos_cutoff(l)), float(l.spot_exponent)});
  }
  zsimd::ShadeParams sp;
  sp.nlights = int(scene.lights.size());
  sp.light = lights.data();
  // Everything relative to the eye (ShadeParams::origin): the eye is the origin.
  sp.origin[0] = eye.x, sp.origin[1] = eye.y, sp.origin[2] = eye.z;
  return sp;
}

// The shading kernel's parameters for a frame: lights, materials and camera
// in float. lights and materials hold what sp.light and sp.materials point to.
zsimd::ShadeParams shade_params(const Scene& scene, const ScreenMesh& mesh, const RasterSettings& s,
                                const std::vector<std::array<int32_t, 2>>& off, const Binner& b,
                                std::vector<float>& lights,
                                std::vector<zsimd::ShadeMaterial>& materials) {
  zsimd::ShadeParams sp = light_params(scene, mesh.camera.eye, lights);
  // (As the reference's lighting reads them: kd * colour, ks, shine; one entry
  // at least, so that a lane of no triangle may read entry 0.)
  materials.clear();
  for (const Material& m : scene.materials)
    materials.push_back({{float(m.kd * m.color.x), float(m.kd * m.color.y),
                          float(m.kd * m.color.z)},
                         float(m.ks),
                         float(m.shine)});
  if (materials.empty()) materials.emplace_back();
  sp.materials = materials.data();
  sp.shading = s.shading;
  sp.perspective = s.perspective;
  sp.silhouette = s.silhouette;
  sp.silhouette_eps = float(s.silhouette_eps);
  sp.toon_bands = s.toon_bands;
  sp.background[0] = float(scene.background.x), sp.background[1] = float(scene.background.y),
  sp.background[2] = float(scene.background.z);
  sp.offsets = off.data();
  sp.spp = int(off.size());
  const Vec3 du = mesh.camera.pitch * mesh.camera.right, dv = -mesh.camera.pitch * mesh.camera.up;
  sp.dir_u[0] = float(du.x), sp.dir_u[1] = float(du.y), sp.dir_u[2] = float(du.z);
  sp.dir_v[0] = float(dv.x), sp.dir_v[1] = float(dv.y), sp.dir_v[2] = float(dv.z);
  sp.buf_w = b.tw, sp.buf_h = b.th;
  return sp;
}

// Shades tile [x0, x1) x [y0, y1) into img: tile_tri is the tile's visible
// triangle per sample (a tile buffer: plane k, row r, column c at
// [(k buf_h + r) buf_w + c], -1 for none), every one of them binned to the tile.
// forward: the tile was drawn with flat shading forward (w and colours per
// sample in *forward, drawn samples those of finite depth in forward_depth;
// no planes needed, tile_tri unused).
void shade_one_tile(const ScreenMesh& mesh, const Binner& b, const zsimd::ShadeParams& sp, int x0,
                    int y0, int x1, int y1, const int32_t* tile_tri, ShadeBuffers& sb, Image& img,
                    const zsimd::ForwardFlat* forward = nullptr,
                    const float* forward_depth = nullptr) {
  if (!forward && sb.where.size() != b.total) sb.where.assign(b.total, nullptr);
  const size_t plane = size_t(b.tw) * size_t(b.th);
  if (sb.size != plane) {
    sb.rgb = hwy::AllocateAligned<float>(3 * plane);
    sb.z = hwy::AllocateAligned<float>(plane);
    sb.size = plane;
  }
  // The tile's triangles' planes, moved to the tile's top-left corner, per
  // pixel: ready in their TilePlanes for a triangle that meets this tile only
  // (set_up_shaded's), else moved here from the double ones.
  const size_t tile = b.tile_of(x0, y0);
  const int64_t cx = int64_t(x0) * kSubpixel, cy = int64_t(y0) * kSubpixel;
  const int rows = b.rows;
  size_t binned = 0, moved = 0;
  for (const BinChunk& c : b.chunks) binned += forward ? 0 : c.bins[tile].size();
  sb.planes.resize(binned);  // (before any pointer into it is taken)
  for (const BinChunk& c : b.chunks) {
    if (forward) break;
    const std::vector<uint32_t>& bin = c.bins[tile];
    for (size_t k = 0; k < bin.size(); ++k) {
      const uint32_t i = bin[k];
      const zsimd::TilePlanes& T = c.local[i];
      // Ready: the kernel reads them there, soon (fetched now, not waited for).
      if (c.ready[i]) {
        __builtin_prefetch(&T);
        sb.where[c.first + i] = &T;
        continue;
      }
      // Else eight triangles ahead, written long before by the set-up and
      // read here out of order (as the raster prefetches): the set-up and
      // the double planes.
      if (k + 8 < bin.size()) {
        const size_t ahead = bin[k + 8];
        __builtin_prefetch(&c.local[ahead]);
        __builtin_prefetch(c.planes.data() + ahead * size_t(rows) * 3);
        __builtin_prefetch(c.planes.data() + ahead * size_t(rows) * 3 + 8);
        __builtin_prefetch(&c.setup[ahead]);
      }
      zsimd::LocalPlanes& L = sb.planes[moved++];
      const TriSetup& t = c.setup[i];
      const double* plane_rows = c.planes.data() + size_t(i) * size_t(rows) * 3;
      for (int row = 0; row < rows; ++row) {
        const double* a = plane_rows + 3 * row;
        float* p = row < 4 ? L.base.p[row] : L.more[row - 4];
        p[0] = float(a[0] + a[1] * double(cx - t.x0()) + a[2] * double(cy - t.y0()));
        p[1] = float(a[1] * kSubpixel);
        p[2] = float(a[2] * kSubpixel);
      }
      L.base.tri = T.tri;
      if (b.flat_shading()) std::copy_n(c.flat[i].data(), 3, L.flat);
      sb.where[c.first + i] = &L.base;
    }
  }
  // The view direction through the tile's top-left pixel corner (the reference's
  // dir = forward + cx right + cy up, cx = (sx - width/2) pitch, cy = (height/2 - sy) pitch).
  zsimd::ShadeParams tp = sp;
  if (forward) {
    tp.forward_w = forward->w;
    for (int c = 0; c < 3; ++c) tp.forward_rgb[c] = forward->rgb[c];
    tp.forward_depth = forward_depth;
  }
  const Camera& cam = mesh.camera;
  const Vec3 d0 = cam.forward + ((x0 - 0.5 * mesh.width) * cam.pitch) * cam.right +
                  ((0.5 * mesh.height - y0) * cam.pitch) * cam.up;
  tp.dir0[0] = float(d0.x), tp.dir0[1] = float(d0.y), tp.dir0[2] = float(d0.z);
  zsimd::shade_tile(tp, tile_tri, sb.where.data(), x1 - x0, y1 - y0, sb.rgb.get(),
                    sb.z.get(), img.pixel(x0, y0), size_t(mesh.width) * 4,
                    img.depth.data() + size_t(y0) * mesh.width + size_t(x0), size_t(mesh.width));
}

template <class T>
void zbuffer_t(const Scene& scene, const ScreenMesh& mesh, const Binner& b,
               const RasterSettings& s, const std::vector<std::array<int32_t, 2>>& off,
               const FrameOptions& opts, FrameStats* stats, Image& img) {
  const RasterParams p = raster_params(s, b, off);
  std::vector<float> lights;
  std::vector<zsimd::ShadeMaterial> materials;
  const zsimd::ShadeParams sp = shade_params(scene, mesh, s, off, b, lights, materials);
  // Flat shading without silhouettes is drawn forward: the raster writes each
  // sample's w and colour, and shading has no per-triangle work left.
  // (zbuffer() leaves the shading set-up out then.)
  const bool forward = std::is_same_v<T, float> && s.shading == Shading::kFlat && !s.silhouette;
  fit_frame(img, mesh.width, mesh.height);
  tbb::enumerable_thread_specific<TileBuffers<T>> buffers;
  tbb::enumerable_thread_specific<ShadeBuffers> shade_buffers;
  parallel_tiles(mesh.width, mesh.height, b.tw, b.th, opts.threads, opts.progress,
                 [&](int x0, int y0, int x1, int y1) {
                   TileBuffers<T>& buf = buffers.local();
                   raster_one_tile(p, b, x0, y0, x1, y1, far_value<T>(s.depth), false, forward,
                                   buf);
                   const float* forward_depth = nullptr;  // (forward: T is float)
                   if constexpr (std::is_same_v<T, float>) forward_depth = buf.depth.get();
                   shade_one_tile(mesh, b, sp, x0, y0, x1, y1, buf.tri.get(), shade_buffers.local(),
                                  img, forward ? &buf.flat : nullptr, forward_depth);
                 });
  if (stats) {
    stats->items = mesh.scene_tris + mesh.sphere_tris;
    stats->dropped = mesh.dropped;
    count_float_lighting_limits(scene, mesh.camera, stats);
    stats->skipped = mesh.hidden;
  }
}


}  // namespace

void count_float_lighting_limits(const Scene& scene, const Camera& cam, FrameStats* stats) {
  constexpr double kFar = 0x1p60, kNear = 0x1p-60;
  const Vec3 eye = cam.eye;
  const double band = 1 + kGuardBand * cam.pitch;
  // How far from the eye the drawn part of a vertex's triangles can be.
  auto reach = [&](const Vec3& v) {
    const Vec3 d = v - eye;
    return std::min(max_abs_component(d), band * std::max(dot(d, cam.forward), 0.0));
  };
  auto out = [&](double m) { return !(m <= kFar && m >= kNear); };
  bool lights_out = false;
  for (const Light& l : scene.lights) lights_out = lights_out || out(max_abs_component(l.position - eye));
  uint64_t n = 0;
  for (uint32_t k = 0; k < scene.sphere_count(); ++k)
    n += lights_out || out(max_abs_component(scene.sphere_center[k] - eye) + std::abs(scene.sphere_radius[k]));
  for (uint32_t p = 0; p < scene.polygon_count(); ++p) {
    double m = 0;
    for (const Vec3& v : scene.polygon_vertices(p)) m = std::max(m, reach(v));
    n += lights_out || out(m);
  }
  stats->drop("lit in float lanes beyond 2^60 = 1.2e18 or within 2^-60 = 8.7e-19 of the eye (drawn, shading unreliable)", n);
}

void fit_frame(Image& img, int width, int height) {
  const size_t n = size_t(width) * size_t(height);
  if (img.width == width && img.height == height && img.rgba.size() == 4 * n && img.depth.size() == n)
    return;
  img = Image::uninitialized(width, height);
  img.depth.resize(n);
}

Image new_frame(int width, int height) {
  Image img;
  fit_frame(img, width, height);
  std::fill(img.rgba.begin(), img.rgba.end(), 0.0f);  // first touch, here
  std::fill(img.depth.begin(), img.depth.end(), 0.0f);
  return img;
}

Image zbuffer(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  Image img;
  zbuffer_into(scene, opts, stats, img);
  return img;
}

void zbuffer_into(const Scene& scene, const FrameOptions& opts, FrameStats* stats, Image& img) {
  const RasterSettings s = frame_settings(scene, opts);
  if (s.shadows != ShadowMode::kNone) {
    img = zbuffer_shadowed(scene, opts, s, stats);
    return;
  }
  const auto off = sample_offsets(s);
  // The set-up hands its triangles straight to the binner (no ScreenTri is
  // kept), and only what the image needs: no triangle without a sample in its
  // box (it covers nothing), flat colours lit in SIMD.
  // Flat shading drawn forward (zbuffer_t) needs no shading set-up.
  const bool forward_flat =
      !double_depth(s.depth) && s.shading == Shading::kFlat && !s.silhouette;
  Binner b(s, off, forward_flat ? nullptr : &scene);
  zsimd::ImageOnly image;
  image.grid = zsimd::SampleGrid(off, opts.width, opts.height);
  std::vector<float> lights;
  image.light =
      light_params(scene, Camera::from_view(scene.view, opts.width, opts.height).eye, lights);
  image.sink = &b;
  ScreenMesh mesh;
  std::vector<std::vector<ScreenTri>> none;
  zsimd::view_scene_chunks(scene, opts.width, opts.height, s, opts.threads, mesh, none, &image);
  b.finish();
  if (double_depth(s.depth))
    zbuffer_t<double>(scene, mesh, b, s, off, opts, stats, img);
  else
    zbuffer_t<float>(scene, mesh, b, s, off, opts, stats, img);
}

Image shade_visibility(const Scene& scene, const ScreenMesh& mesh, const RasterSettings& s,
                       const uint32_t* visible, const FrameOptions& opts) {
  Image img;
  shade_visibility_into(scene, mesh, s, visible, opts, img);
  return img;
}

void shade_visibility_into(const Scene& scene, const ScreenMesh& mesh, const RasterSettings& s,
                           const uint32_t* visible, const FrameOptions& opts, Image& img) {
  const auto off = sample_offsets(s);
  const int spp = int(off.size());
  Binner b(s, off, &scene);
  bin_mesh(mesh, opts.threads, b);
  std::vector<float> lights;
  std::vector<zsimd::ShadeMaterial> materials;
  const zsimd::ShadeParams sp = shade_params(scene, mesh, s, off, b, lights, materials);
  fit_frame(img, mesh.width, mesh.height);
  struct IdBuffer {
    hwy::AlignedFreeUniquePtr<int32_t[]> tri;
    size_t size = 0;
  };
  tbb::enumerable_thread_specific<IdBuffer> buffers;
  tbb::enumerable_thread_specific<ShadeBuffers> shade_buffers;
  parallel_tiles(
      mesh.width, mesh.height, b.tw, b.th, opts.threads, opts.progress,
      [&](int x0, int y0, int x1, int y1) {
        IdBuffer& buf = buffers.local();
        const size_t n = size_t(b.tw) * size_t(b.th) * size_t(spp);
        if (buf.size != n) buf.tri = hwy::AllocateAligned<int32_t>(n), buf.size = n;
        std::fill_n(buf.tri.get(), n, -1);
        // The tile's samples into the kernel's layout (a visible triangle is
        // binned to the tile: its box holds the sample).
        for (int k = 0; k < spp; ++k)
          for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
              const uint32_t t =
                  visible[(size_t(y) * size_t(mesh.width) + size_t(x)) * size_t(spp) + size_t(k)];
              buf.tri[(size_t(k) * size_t(b.th) + size_t(y - y0)) * size_t(b.tw) + size_t(x - x0)] =
                  t == Visibility::kNone ? -1 : int32_t(t);
            }
        shade_one_tile(mesh, b, sp, x0, y0, x1, y1, buf.tri.get(), shade_buffers.local(), img);
      });
}

void zbuffer_distances(const ScreenMesh& face_frame, const RasterSettings& depth, int threads,
                       float* dist) {
  if (depth.spp != 1) throw std::logic_error("zbuffer_distances: one sample per texel");
  if (double_depth(depth.depth))
    distances_t<double>(face_frame, depth, threads, dist);
  else
    distances_t<float>(face_frame, depth, threads, dist);
}

void zbuffer_visibility(const ScreenMesh& mesh, const RasterSettings& s, int threads,
                        Visibility& vis) {
  if (double_depth(s.depth))
    visibility_t<double>(mesh, s, threads, vis);
  else
    visibility_t<float>(mesh, s, threads, vis);
}

}  // namespace lockstep::opt::simd
