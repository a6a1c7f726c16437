// lockstep optimized: the painter's algorithm (optimized/painter_simd.h).
//
// The same plan as the reference (reference/painter.cpp), reached faster:
//   * depth sort: Highway's vqsort (hwy/contrib/sort) on 64-bit keys whose high
//     half is the farthest depth as a float (bits made unsigned-monotonic) and
//     whose low half is the complemented triangle index, descending: ties of the
//     float key come out in scene order. Runs of equal float keys (distinct
//     doubles can round to one float) are then put in the reference's order by
//     the double key, so the sort equals painter_sort exactly.
//   * pair tests: the x sweep cut into chunks over TBB threads, each pair
//     classified by the reference's classify_pair (exact predicates: the filter
//     decides almost every orientation in plain doubles), after test 5 alone
//     (exact integers), which settles most pairs of a mesh; the plan is built
//     from the findings by the shared painter_plan, which does not depend on
//     their order.
//   * painting: what is painted is only the owner of each sample (the triangle
//     painted last); a triangle's samples on a row are a span whose ends come
//     exactly from the three edge functions in integers (the fill rule as
//     thresholds: e >= 0 on top-left edges, e >= 1 elsewhere), filled with
//     Highway stores. Triangles of a split group go sample by sample through
//     the reference's exact nearer_at.
//   * shading: each sample once, by its owner, with the reference's fragment
//     arithmetic and shade_fragment, over TBB row bands -- the image is the
//     reference's bit for bit.
#include <hwy/contrib/sort/vqsort.h>
#include <hwy/highway.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <mutex>

#include "core/error.h"
#include "optimized/painter_simd.h"
#include "optimized/zbuffer/zbuffer_simd.h"
#include "optimized/tiling.h"

namespace lockstep::opt::simd {

namespace hn = hwy::HWY_NAMESPACE;

namespace {

int64_t ceil_div(int64_t a, int64_t b) { return -floor_div(-a, b); }

// Float bits as an unsigned key with the same order.
uint32_t sortable(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}

// Fills n owners from p with t, a vector at a time.
void fill_owner(uint32_t* p, size_t n, uint32_t t) {
  const hn::ScalableTag<uint32_t> d;
  const size_t lanes = hn::Lanes(d);
  const auto v = hn::Set(d, t);
  size_t i = 0;
  for (; i + lanes <= n; i += lanes) hn::StoreU(v, d, p + i);
  for (; i < n; ++i) p[i] = t;
}

// The sample colour as the reference stores it (Vec3f), back in double.
// GCC 12.2 at -O3 miscompiles Vec3(Vec3f(c)) here: its SLP vectorizer turns
// the x and y round trips double -> float -> double into plain copies (only z
// is rounded; seen in the assembly: vmovupd of x, y, vcvtsd2ss/vcvtss2sd of z),
// and the painter was 1 ulp off the reference. Without SLP vectorization in
// this one function, every component is rounded.
[[gnu::noinline, gnu::optimize("no-tree-slp-vectorize")]] Vec3 stored_color(const Vec3& c) {
  const Vec3f f(c);
  return Vec3(f);
}

// One edge of a triangle as a function of the pixel column on a sample row:
// e(i) = c - d * i; the sample is inside when e(i) >= threshold.
struct RowEdge {
  int64_t ax, ay, dx, dy, threshold;
};

}  // namespace

std::vector<uint32_t> depth_sort(const std::vector<PainterTri>& tris) {
  const size_t n = tris.size();
  std::vector<uint64_t> keys(n);
  for (size_t i = 0; i < n; ++i)
    keys[i] = (uint64_t(sortable(float(tris[i].zmax))) << 32) | uint64_t(~uint32_t(i));
  hwy::Sorter sorter;
  sorter(keys.data(), n, hwy::SortDescending());
  std::vector<uint32_t> sorted(n);
  for (size_t i = 0; i < n; ++i) sorted[i] = ~uint32_t(keys[i]);
  // Equal float keys: the reference's order (double key descending, then index).
  for (size_t a = 0; a < n;) {
    size_t b = a + 1;
    while (b < n && (keys[b] >> 32) == (keys[a] >> 32)) ++b;
    if (b - a > 1)
      std::stable_sort(sorted.begin() + a, sorted.begin() + b,
                       [&](uint32_t x, uint32_t y) { return tris[x].zmax > tris[y].zmax; });
    a = b;
  }
  return sorted;
}

namespace {

// The reference's painter_pairs, its sweep cut into chunks over threads.
std::vector<PairFinding> pairs_parallel(const std::vector<PainterTri>& tris,
                                        const std::vector<uint32_t>& sorted, int threads) {
  const uint32_t n = uint32_t(tris.size());
  std::vector<uint32_t> pos(n);
  for (uint32_t i = 0; i < n; ++i) pos[sorted[i]] = i;
  std::vector<uint32_t> by_x(n);
  for (uint32_t i = 0; i < n; ++i) by_x[i] = i;
  std::sort(by_x.begin(), by_x.end(), [&](uint32_t a, uint32_t b) {
    return tris[a].xmin != tris[b].xmin ? tris[a].xmin < tris[b].xmin : a < b;
  });
  std::vector<PairFinding> out;
  std::mutex m;
  tbb::task_arena(resolve_threads(threads)).execute([&] {
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, 256),
                      [&](const tbb::blocked_range<uint32_t>& r) {
                        std::vector<PairFinding> local;
                        for (uint32_t a = r.begin(); a < r.end(); ++a) {
                          const PainterTri& ta = tris[by_x[a]];
                          for (uint32_t b = a + 1; b < n && tris[by_x[b]].xmin < ta.xmax; ++b) {
                            const PainterTri& tb = tris[by_x[b]];
                            if (ta.ymax <= tb.ymin || tb.ymax <= ta.ymin)
                              continue;  // test 2, before the call
                            uint32_t ip = by_x[a], iq = by_x[b];
                            if (pos[iq] < pos[ip]) std::swap(ip, iq);
                            const PairVerdict v = classify_pair(tris[ip], tris[iq]);
                            if (v.test == 1 || v.test == 2) continue;
                            local.push_back({ip, iq, v});
                          }
                        }
                        std::lock_guard<std::mutex> lock(m);
                        out.insert(out.end(), local.begin(), local.end());
                      });
  });
  return out;
}

}  // namespace

Image painter(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  const RasterSettings s = frame_settings(scene, opts);
  const int w = opts.width, h = opts.height;
  const double samples = double(w) * h * s.spp;
  // view_scene's mesh, bit for bit, set up in parallel (optimized/zbuffer/zbuffer_setup.cpp).
  const ScreenMesh mesh = opt::simd::view_scene(scene, w, h, s, opts.threads);
  const auto offsets = sample_offsets(s);
  const int spp = int(offsets.size());

  std::vector<PainterTri> tris(mesh.tris.size());
  for (size_t i = 0; i < tris.size(); ++i) tris[i] = painter_tri(mesh.tris[i]);
  std::vector<uint32_t> sorted = depth_sort(tris);
  const std::vector<PairFinding> pairs = pairs_parallel(tris, sorted, opts.threads);
  const PainterPlan plan = painter_plan(tris, std::move(sorted), pairs);

  // Paint owners, in plan order (sequential: later triangles overwrite).
  std::vector<uint32_t, LargeAllocator<uint32_t>> owner(size_t(samples), Visibility::kNone);
  for (size_t n = 0; n < plan.order.size(); ++n) {
    const uint32_t t = plan.order[n];
    const PainterTri& pt = tris[t];
    const ScreenTri& st = mesh.tris[t];
    const bool resolve = s.split && plan.group_size[plan.group[t]] > 1;
    RowEdge edges[3];
    for (int v = 0; v < 3; ++v) {
      const ScreenVertex& a = st.v[(v + 1) % 3];
      const ScreenVertex& b = st.v[(v + 2) % 3];
      const int64_t dx = int64_t(b.x) - a.x, dy = int64_t(b.y) - a.y;
      const bool top_left = (dy == 0 && dx > 0) || dy < 0;
      edges[v] = {a.x, a.y, dx, dy, top_left ? 0 : 1};
    }
    const int64_t i0 = std::max<int64_t>(0, floor_div(pt.xmin, kSubpixel));
    const int64_t i1 = std::min<int64_t>(w - 1, floor_div(pt.xmax, kSubpixel));
    const int64_t j0 = std::max<int64_t>(0, floor_div(pt.ymin, kSubpixel));
    const int64_t j1 = std::min<int64_t>(h - 1, floor_div(pt.ymax, kSubpixel));
    if (i0 > i1) continue;
    for (int64_t j = j0; j <= j1; ++j) {
      for (int k = 0; k < spp; ++k) {
        const int64_t sy = j * kSubpixel + offsets[k][1];
        const int64_t ox = offsets[k][0];
        // The span [lo, hi] of columns whose sample k is inside all three edges:
        // E(i) = dx (sy - ay) - dy (i 256 + ox - ax) = c - dy 256 i >= threshold.
        int64_t lo = i0, hi = i1;
        for (const RowEdge& e : edges) {
          const int64_t c =
              e.dx * (sy - e.ay) - e.dy * (ox - e.ax) - e.threshold;  // need c - D i >= 0
          const int64_t D = e.dy * kSubpixel;
          if (D == 0) {
            if (c < 0) lo = hi + 1;
          } else if (D > 0) {
            hi = std::min(hi, floor_div(c, D));
          } else {
            lo = std::max(lo, ceil_div(-c, -D));
          }
        }
        if (lo > hi) continue;
        const size_t row = size_t(j) * size_t(w);
        if (resolve) {
          for (int64_t i = lo; i <= hi; ++i) {
            uint32_t& o = owner[(row + size_t(i)) * spp + k];
            if (o != Visibility::kNone && plan.group[o] == plan.group[t] &&
                !nearer_at(pt, t, tris[o], o, i * kSubpixel + ox, sy))
              continue;
            o = t;
          }
        } else if (spp == 1) {
          fill_owner(owner.data() + row + size_t(lo), size_t(hi - lo + 1), t);
        } else {
          for (int64_t i = lo; i <= hi; ++i) owner[(row + size_t(i)) * spp + k] = t;
        }
      }
    }
  }

  // Shade every sample once, by its owner, and resolve the pixels.
  Image image(w, h);
  image.depth.assign(size_t(w) * size_t(h), float(kInfinity));
  const Vec3f background(scene.background);
  parallel_tiles(w, h, w, 8, opts.threads, opts.progress, [&](int x0, int y0, int x1, int y1) {
    for (int j = y0; j < y1; ++j)
      for (int i = x0; i < x1; ++i) {
        Vec3 sum;
        float z = float(kInfinity);
        for (int k = 0; k < spp; ++k) {
          const size_t idx = (size_t(j) * size_t(w) + size_t(i)) * size_t(spp) + size_t(k);
          const uint32_t t = owner[idx];
          if (t == Visibility::kNone) {
            sum += Vec3(background);
            continue;
          }
          const PainterTri& pt = tris[t];
          const int64_t sx = int64_t(i) * kSubpixel + offsets[k][0];
          const int64_t sy = int64_t(j) * kSubpixel + offsets[k][1];
          std::array<int64_t, 3> e;
          for (int v = 0; v < 3; ++v) {
            const int a = (v + 1) % 3, b = (v + 2) % 3;
            e[v] = (pt.x[b] - pt.x[a]) * (sy - pt.y[a]) - (pt.y[b] - pt.y[a]) * (sx - pt.x[a]);
          }
          const Fragment f = painter_fragment(mesh, t, sx, sy, e, pt.area, s.perspective);
          sum += stored_color(shade_fragment(scene, mesh, s, f));
          z = std::min(z, float(f.z));
        }
        image.set(i, j, sum / double(spp));
        image.depth[size_t(j) * size_t(w) + size_t(i)] = z;
      }
  });
  if (stats) {
    stats->items = mesh.scene_tris + mesh.sphere_tris;
    stats->dropped = mesh.dropped;
    stats->notes = painter_notes(mesh, plan, s.split);
  }
  return image;
}

}  // namespace lockstep::opt::simd
