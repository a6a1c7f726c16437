// The optimized z-buffer (contract: reference/raster.h, optimized/raster.h).
//
//   1. Set-up and binning (TBB over chunks of triangles): one TriSetup per
//      screen triangle (exact int64 edge functions with the top-left bias, the
//      depth plane, the shading planes) and its sample bounding box, appended to
//      the lists of the tiles that box touches. Each chunk keeps its own lists,
//      so a tile reads its triangles chunk by chunk: in mesh order.
//   2. Tiles (optimized/tiling.h, work-stealing over the threads): raster the
//      tile's triangles into tile-local buffers (zbuffer_simd_kernels.cpp), then
//      either copy them into the Visibility (zbuffer_visibility) or shade the
//      visible samples and box-filter them into the image (zbuffer), while the
//      tile is still in cache.
// The screen mesh itself comes from ref::view_scene (shared set-up: viewing,
// culling, clipping, sphere tessellation, snapping), so both z-buffers see the
// same snapped coordinates.
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "hwy/aligned_allocator.h"
#include "optimized/raster.h"
#include "optimized/tiling.h"
#include "optimized/zbuffer_simd_kernels.h"

namespace lockstep::opt::simd {

namespace {

using zsimd::RasterParams;
using zsimd::TileJob;
using zsimd::TriSetup;

int64_t floor_div(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
int64_t ceil_div(int64_t a, int64_t b) { return -floor_div(-a, b); }

// Tiles: 64 x 64 pixels up to 4 samples per pixel, smaller beyond (about 16k
// samples per tile: the buffers stay in L2).
void tile_size(int spp, int& tw, int& th) {
  tw = th = 64;
  while (tw > 16 && tw * th * spp > 64 * 64 * 4) (th > 16 && th >= tw) ? th /= 2 : tw /= 2;
}

struct Binned {
  int tw = 64, th = 64, ntx = 0, nty = 0, nchunks = 0;
  std::vector<TriSetup> setup;
  std::vector<std::vector<uint32_t>> bins;  // [chunk * tiles + tile]: triangle ids in mesh order
};

// The stored depth's plane quantity at a vertex of eye depth z (see
// zbuffer_simd_kernels.cpp): the stored depth itself under perspective, eye z
// under affine interpolation.
double plane_value(const RasterSettings& s, double z, double near_z, double far_z) {
  if (!s.perspective) return z;
  switch (s.depth) {
    case DepthFormat::kReversed: return near_z / z;
    case DepthFormat::kDouble: return stored_depth(DepthFormat::kDouble, z, near_z, far_z);
    default: return (1.0 / near_z - 1.0 / z) / (1.0 / near_z - 1.0 / far_z);
  }
}

void set_up(const ScreenMesh& mesh, const RasterSettings& s, uint32_t id, int32_t ox0, int32_t ox1, int32_t oy0,
            int32_t oy1, TriSetup& t) {
  const ScreenTri& tri = mesh.tris[id];
  const auto& v = tri.v;
  int64_t xmin = v[0].x, xmax = v[0].x, ymin = v[0].y, ymax = v[0].y;
  for (int k = 1; k < 3; ++k) {
    xmin = std::min<int64_t>(xmin, v[k].x), xmax = std::max<int64_t>(xmax, v[k].x);
    ymin = std::min<int64_t>(ymin, v[k].y), ymax = std::max<int64_t>(ymax, v[k].y);
  }
  // Pixels i with a sample 256 i + ox inside [xmin, xmax] for some offset ox.
  t.i0 = int32_t(std::max<int64_t>(0, ceil_div(xmin - ox1, kSubpixel)));
  t.i1 = int32_t(std::min<int64_t>(mesh.width - 1, floor_div(xmax - ox0, kSubpixel)));
  t.j0 = int32_t(std::max<int64_t>(0, ceil_div(ymin - oy1, kSubpixel)));
  t.j1 = int32_t(std::min<int64_t>(mesh.height - 1, floor_div(ymax - oy0, kSubpixel)));
  for (int k = 0; k < 3; ++k) {
    const ScreenVertex& a = v[(k + 1) % 3];
    const ScreenVertex& b = v[(k + 2) % 3];
    const int64_t dx = int64_t(b.x) - a.x, dy = int64_t(b.y) - a.y;
    t.ax[k] = a.x, t.ay[k] = a.y;
    t.ex[k] = -dy, t.ey[k] = dx;
    const bool top_left = (dy == 0 && dx > 0) || dy < 0;
    t.bias[k] = top_left ? 0 : 1;
  }
  t.x0 = v[0].x, t.y0 = v[0].y;
  // Plane through the three vertices' values, from the barycentric gradients
  // b_k = E_k / A (A = E_2(v2), twice the area in snapped units).
  const double area = double(t.ex[2] * (int64_t(v[2].x) - t.ax[2]) + t.ey[2] * (int64_t(v[2].y) - t.ay[2]));
  auto plane = [&](double a0, double a1, double a2, double& c0, double& cx, double& cy) {
    c0 = a0;
    cx = ((a1 - a0) * double(t.ex[1]) + (a2 - a0) * double(t.ex[2])) / area;
    cy = ((a1 - a0) * double(t.ey[1]) + (a2 - a0) * double(t.ey[2])) / area;
  };
  plane(plane_value(s, v[0].z, mesh.near_z, mesh.far_z), plane_value(s, v[1].z, mesh.near_z, mesh.far_z),
        plane_value(s, v[2].z, mesh.near_z, mesh.far_z), t.q0, t.qx, t.qy);
}

Binned bin_mesh(const ScreenMesh& mesh, const RasterSettings& s, const std::vector<std::array<int32_t, 2>>& off,
                int threads) {
  Binned b;
  tile_size(int(off.size()), b.tw, b.th);
  b.ntx = (mesh.width + b.tw - 1) / b.tw;
  b.nty = (mesh.height + b.th - 1) / b.th;
  const size_t tiles = size_t(b.ntx) * size_t(b.nty);
  int32_t ox0 = kSubpixel, ox1 = 0, oy0 = kSubpixel, oy1 = 0;
  for (const auto& o : off) {
    ox0 = std::min(ox0, o[0]), ox1 = std::max(ox1, o[0]);
    oy0 = std::min(oy0, o[1]), oy1 = std::max(oy1, o[1]);
  }
  const size_t n = mesh.tris.size();
  b.setup.resize(n);
  const size_t per_chunk = 4096;
  b.nchunks = int((n + per_chunk - 1) / per_chunk);
  b.bins.resize(size_t(b.nchunks) * tiles);
  auto chunk = [&](int c) {
    const size_t first = size_t(c) * per_chunk, last = std::min(n, first + per_chunk);
    std::vector<uint32_t>* bins = b.bins.data() + size_t(c) * tiles;
    for (size_t id = first; id < last; ++id) {
      TriSetup& t = b.setup[id];
      set_up(mesh, s, uint32_t(id), ox0, ox1, oy0, oy1, t);
      if (t.i0 > t.i1 || t.j0 > t.j1) continue;
      for (int ty = t.j0 / b.th; ty <= t.j1 / b.th; ++ty)
        for (int tx = t.i0 / b.tw; tx <= t.i1 / b.tw; ++tx) bins[size_t(ty) * b.ntx + tx].push_back(uint32_t(id));
    }
  };
  if (b.nchunks <= 1) {
    if (b.nchunks == 1) chunk(0);
  } else {
    tbb::task_arena arena(resolve_threads(threads));
    arena.execute([&] { tbb::parallel_for(0, b.nchunks, chunk); });
  }
  return b;
}

// One thread's tile buffers.
// One thread's tile buffers (vector-aligned: the kernels use aligned loads).
template <class T>
struct TileBuffers {
  size_t size = 0;
  hwy::AlignedFreeUniquePtr<T[]> depth;
  hwy::AlignedFreeUniquePtr<int32_t[]> tri, count;
  std::vector<const std::vector<uint32_t>*> lists;
  void reset(size_t n, T far_value) {
    if (n != size) {
      depth = hwy::AllocateAligned<T>(n);
      tri = hwy::AllocateAligned<int32_t>(n);
      count = hwy::AllocateAligned<int32_t>(n);
      size = n;
    }
    std::fill_n(depth.get(), n, far_value);
    std::fill_n(tri.get(), n, -1);
    std::fill_n(count.get(), n, 0);
  }
};

template <class T>
void raster_one_tile(const RasterParams& p, const Binned& b, int x0, int y0, int x1, int y1, T far_value,
                     TileBuffers<T>& buf) {
  const size_t n = size_t(p.buf_w) * size_t(p.buf_h) * size_t(p.spp);
  buf.reset(n, far_value);
  const size_t tiles = size_t(b.ntx) * size_t(b.nty);
  const size_t tile = size_t(y0 / b.th) * size_t(b.ntx) + size_t(x0 / b.tw);
  buf.lists.clear();
  for (int c = 0; c < b.nchunks; ++c) {
    const auto& l = b.bins[size_t(c) * tiles + tile];
    if (!l.empty()) buf.lists.push_back(&l);
  }
  TileJob job;
  job.x0 = x0, job.y0 = y0, job.x1 = x1, job.y1 = y1;
  job.lists = buf.lists.data();
  job.nlists = int(buf.lists.size());
  zsimd::raster_tile(p, job, buf.depth.get(), buf.tri.get(), buf.count.get());
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
  const Binned b = bin_mesh(mesh, s, off, threads);
  RasterParams p;
  p.tris = b.setup.data();
  p.offsets = off.data();
  p.spp = spp;
  p.depth = s.depth;
  p.perspective = s.perspective;
  p.near_z = mesh.near_z, p.far_z = mesh.far_z;
  p.buf_w = b.tw, p.buf_h = b.th;
  const T far_value = s.depth == DepthFormat::kReversed ? -std::numeric_limits<T>::infinity()
                                                        : std::numeric_limits<T>::infinity();
  const double empty = empty_depth(s.depth);
  const bool fixed24 = s.depth == DepthFormat::kFixed24;
  tbb::enumerable_thread_specific<TileBuffers<T>> buffers;
  parallel_tiles(mesh.width, mesh.height, b.tw, b.th, threads, {}, [&](int x0, int y0, int x1, int y1) {
    TileBuffers<T>& buf = buffers.local();
    raster_one_tile(p, b, x0, y0, x1, y1, far_value, buf);
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x)
        for (int k = 0; k < spp; ++k) {
          const size_t at = (size_t(k) * b.th + size_t(y - y0)) * b.tw + size_t(x - x0);
          const size_t out = (size_t(y) * mesh.width + size_t(x)) * spp + size_t(k);
          const int32_t t = buf.tri[at];
          vis.tri[out] = t < 0 ? Visibility::kNone : uint32_t(t);
          vis.depth[out] = t < 0 ? empty : fixed24 ? double(buf.depth[at]) / double((1 << 24) - 1) : double(buf.depth[at]);
          vis.count[out] = uint16_t(std::min<int32_t>(buf.count[at], 0xffff));
        }
  });
}

}  // namespace

void zbuffer_visibility(const ScreenMesh& mesh, const RasterSettings& s, int threads, Visibility& vis) {
  if (s.depth == DepthFormat::kDouble)
    visibility_t<double>(mesh, s, threads, vis);
  else
    visibility_t<float>(mesh, s, threads, vis);
}

}  // namespace lockstep::opt::simd
