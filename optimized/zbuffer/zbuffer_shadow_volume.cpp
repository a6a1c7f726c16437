// lockstep optimized: the simd z-buffer with shadows=volume (issue #22).
//
// The reference's method (reference/shadow_volume.h: Crow's volumes, z-pass or
// Everitt-Kilgard z-fail with caps, counted on the z-buffer's own snapped
// samples) and the same shared steps (core/shadow_volume.h: occluders,
// silhouettes, the volume's triangles through the viewing pipeline, the depth
// at a sample, the stencil rule), so that the counts, and so the images, equal
// the reference's bit for bit. What is fast here is the counting:
//   - the visible depth per sample straight from the visibility buffer (the
//     reference walks every triangle's box to find it);
//   - the volume's screen triangles binned to tiles, the tiles counted on TBB
//     threads, edge functions stepped incrementally in exact int64;
//   - a face's depth at a sample is only computed (sample_depth, double, as the
//     reference) where its answer is in doubt: a covered sample's depth lies
//     between the face's nearest and farthest vertex depths (1/z is a convex
//     combination of the vertices' 1/z inside the triangle; the computed one
//     within 2^-49 relative of it, all terms positive), so a visible depth
//     beyond those bounds (with a 1e-12 relative margin) decides in front or
//     behind without it. On teapot-2 and gears-2 at 512^2 (map of measured
//     fractions in the commit message) most covered samples are decided so.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/shadow_volume.h"
#include "optimized/tiling.h"
#include "optimized/zbuffer/zbuffer_simd.h"

namespace lockstep::opt::simd {

namespace {

// Tiles of the counting pass: 64 x 64 pixels (the count and depth rows of a
// tile stay in L2 while its faces are drawn).
constexpr int kTile = 64;

// A volume face set up for counting: edge k runs from vertex k+1 to k+2
// (the reference's e0 = E(v1, v2), e1 = E(v2, v0), e2 = E(v0, v1)).
struct Face {
  const ScreenTri* tri = nullptr;
  int64_t ax[3], ay[3], dx[3], dy[3];
  int64_t bias[3];  // 1 for a top-left edge: e + bias > 0 is the top-left rule's "owns"
  int i0 = 0, i1 = -1, j0 = 0, j1 = -1;
  double lo = 0, hi = 0;  // the depth bounds, margins included (lo > hi: always compute)
  int32_t step_in_front = 0, step_behind = 0;
};

Face set_up(const ScreenTri& t, bool zfail, bool front, bool cap, int w, int h) {
  Face f;
  f.tri = &t;
  for (int k = 0; k < 3; ++k) {
    const ScreenVertex &a = t.v[size_t(k + 1) % 3], &b = t.v[size_t(k + 2) % 3];
    f.ax[k] = a.x, f.ay[k] = a.y;
    f.dx[k] = int64_t(b.x) - a.x, f.dy[k] = int64_t(b.y) - a.y;
    f.bias[k] = (f.dy[k] == 0 && f.dx[k] > 0) || f.dy[k] < 0 ? 1 : 0;
  }
  const int32_t xmin = std::min({t.v[0].x, t.v[1].x, t.v[2].x}),
                xmax = std::max({t.v[0].x, t.v[1].x, t.v[2].x});
  const int32_t ymin = std::min({t.v[0].y, t.v[1].y, t.v[2].y}),
                ymax = std::max({t.v[0].y, t.v[1].y, t.v[2].y});
  f.i0 = std::max(0, int(std::floor(double(xmin) / kSubpixel)));
  f.i1 = std::min(w - 1, int(std::floor(double(xmax) / kSubpixel)));
  f.j0 = std::max(0, int(std::floor(double(ymin) / kSubpixel)));
  f.j1 = std::min(h - 1, int(std::floor(double(ymax) / kSubpixel)));
  const double zmin = std::min({t.v[0].z, t.v[1].z, t.v[2].z}),
               zmax = std::max({t.v[0].z, t.v[1].z, t.v[2].z});
  constexpr double kMargin = 1e-12;
  if (zmin > 0 && std::isfinite(zmax) && std::isnormal(1 / zmax) && std::isfinite(1 / zmin)) {
    f.lo = zmin * (1 - kMargin);
    f.hi = zmax * (1 + kMargin);
  } else {
    f.lo = -kInfinity, f.hi = kInfinity;  // never decided by the bounds
  }
  // The step where the face is certainly in front of (z < z_visible) or
  // behind (z > z_visible) the visible surface: stencil_step's own answers.
  f.step_in_front = stencil_step(zfail, front, cap, 0.0, 1.0);
  f.step_behind = stencil_step(zfail, front, cap, 1.0, 0.0);
  return f;
}


// Adds face f's stencil steps to the samples of tile [x0, x1) x [y0, y1).
// z_visible: the visible depth per sample, NaN where nothing is drawn (so
// that both bound tests fail there and the sample is skipped).
void count_face(const Face& f, int x0, int y0, int x1, int y1, int w, int spp,
                const std::vector<std::array<int32_t, 2>>& offsets, bool zfail, bool front,
                bool cap, const double* z_visible, int32_t* count) {
  const int i0 = std::max(f.i0, x0), i1 = std::min(f.i1, x1 - 1);
  const int j0 = std::max(f.j0, y0), j1 = std::min(f.j1, y1 - 1);
  if (i0 > i1 || j0 > j1) return;
  int64_t step_x[3];
  for (int k = 0; k < 3; ++k) step_x[k] = -f.dy[k] * kSubpixel;
  const double lo = f.lo, hi = f.hi;
  const int32_t sf = f.step_in_front, sb = f.step_behind;
  for (int s = 0; s < spp; ++s) {
    const int64_t ox = offsets[size_t(s)][0], oy = offsets[size_t(s)][1];
    for (int j = j0; j <= j1; ++j) {
      const int64_t py = int64_t(j) * kSubpixel + oy, px = int64_t(i0) * kSubpixel + ox;
      // The row's span of covered samples, exactly: edge k at column i0 + t
      // is e + t step, owned while e + t step + bias > 0 (int64 throughout).
      int64_t e[3], t_lo = 0, t_hi = i1 - i0;
      for (int k = 0; k < 3; ++k) {
        e[k] = f.dx[k] * (py - f.ay[k]) - f.dy[k] * (px - f.ax[k]);
        const int64_t c = e[k] + f.bias[k], st = step_x[k];
        if (st > 0)
          t_lo = std::max(t_lo, floor_div(-c, st) + 1);
        else if (st < 0)
          t_hi = std::min(t_hi, -floor_div(-c, -st) - 1);  // t < c / -st: t <= ceil(c / -st) - 1
        else if (c <= 0)
          t_hi = -1;
      }
      if (t_lo > t_hi) continue;
      const size_t first = (size_t(j) * size_t(w) + size_t(i0 + t_lo)) * size_t(spp) + size_t(s);
      const size_t n = size_t(t_hi - t_lo + 1);
      const double* z = z_visible + first;
      int32_t* out = count + first;
      // Decided by the bounds (no branch: the compiler's vectors), and
      // whether any sample is left in doubt.
      bool doubt = false;
      if (spp == 1) {
        for (size_t i = 0; i < n; ++i) {
          const double zv = z[i];
          out[i] += zv > hi ? sf : zv < lo ? sb : 0;
          doubt |= zv <= hi && zv >= lo;
        }
      } else {
        for (size_t i = 0; i < n; ++i) {
          const double zv = z[i * size_t(spp)];
          out[i * size_t(spp)] += zv > hi ? sf : zv < lo ? sb : 0;
          doubt |= zv <= hi && zv >= lo;
        }
      }
      if (!doubt) continue;
      // The rest as the reference decides them: the face's depth there.
      for (size_t i = 0; i < n; ++i) {
        const double zv = z[i * size_t(spp)];
        if (!(zv <= hi && zv >= lo)) continue;
        const int64_t t = t_lo + int64_t(i);
        const double zf =
            sample_depth(*f.tri, e[0] + t * step_x[0], e[1] + t * step_x[1], e[2] + t * step_x[2]);
        out[i * size_t(spp)] += stencil_step(zfail, front, cap, zf, zv);
      }
    }
  }
}

}  // namespace

ShadowVolumeMasks shadow_volume_masks(const Scene& scene, const ScreenMesh& mesh,
                                      const RasterSettings& s, const Visibility& vis, int threads) {
  ShadowVolumeMasks out;
  out.lights = uint32_t(scene.lights.size());
  const int w = mesh.width, h = mesh.height, spp = vis.spp;
  const size_t samples = vis.tri.size();
  out.lit.assign(samples * out.lights, 1);
  if (out.lights == 0) return out;
  const OccluderMesh occ = occluder_mesh(scene, mesh, s);
  out.note = occluder_note(occ);
  const auto offsets = sample_offsets(s);
  tbb::task_arena arena(resolve_threads(threads));

  // The visible surface's depth per sample (NaN where nothing is drawn: the
  // reference's +inf, where it counts nothing), from its triangle's exact
  // edge functions there, as the reference's visible_z finds it.
  std::vector<double> z(samples, std::numeric_limits<double>::quiet_NaN());
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
      for (int j = rows.begin(); j < rows.end(); ++j)
        for (int i = 0; i < w; ++i)
          for (int k = 0; k < spp; ++k) {
            const size_t index = (size_t(j) * size_t(w) + size_t(i)) * size_t(spp) + size_t(k);
            const uint32_t ti = vis.tri[index];
            if (ti == Visibility::kNone) continue;
            const ScreenTri& t = mesh.tris[ti];
            const int64_t px = int64_t(i) * kSubpixel + offsets[size_t(k)][0];
            const int64_t py = int64_t(j) * kSubpixel + offsets[size_t(k)][1];
            auto edge = [&](const ScreenVertex& a, const ScreenVertex& b) {
              return int64_t(b.x - a.x) * (py - a.y) - int64_t(b.y - a.y) * (px - a.x);
            };
            z[index] =
                sample_depth(t, edge(t.v[1], t.v[2]), edge(t.v[2], t.v[0]), edge(t.v[0], t.v[1]));
          }
    });
  });

  const int ntx = (w + kTile - 1) / kTile, nty = (h + kTile - 1) / kTile;
  std::vector<int32_t> count(samples);
  std::vector<Face> faces;
  std::vector<std::vector<uint32_t>> bins(size_t(ntx) * size_t(nty));
  for (uint32_t light = 0; light < out.lights; ++light) {
    const Vec3 at = scene.lights[light].position;
    // Capped for z-pass too (reference/shadow_volume.cpp shadow_masks says why).
    std::vector<uint8_t> is_cap;
    const auto volume = shadow_volume(occ, at, shadow_far(scene, at), true, false, &is_cap);
    out.volume_tris += volume.size();
    const ViewedVolume vv = view_volume(scene, mesh, s, volume, &is_cap);
    faces.clear();
    for (auto& b : bins) b.clear();
    for (size_t i = 0; i < vv.mesh.tris.size(); ++i) {
      faces.push_back(set_up(vv.mesh.tris[i], s.zfail, vv.front[i], vv.cap[i], w, h));
      const Face& f = faces.back();
      if (f.i0 > f.i1 || f.j0 > f.j1) continue;
      for (int ty = f.j0 / kTile; ty <= f.j1 / kTile; ++ty)
        for (int tx = f.i0 / kTile; tx <= f.i1 / kTile; ++tx)
          bins[size_t(ty) * size_t(ntx) + size_t(tx)].push_back(uint32_t(i));
    }
    std::fill(count.begin(), count.end(), 0);
    parallel_tiles(w, h, kTile, kTile, threads, {}, [&](int x0, int y0, int x1, int y1) {
      for (const uint32_t i : bins[size_t(y0 / kTile) * size_t(ntx) + size_t(x0 / kTile)])
        count_face(faces[i], x0, y0, x1, y1, w, spp, offsets, s.zfail, vv.front[i], vv.cap[i],
                   z.data(), count.data());
    });
    for (size_t i = 0; i < samples; ++i) out.lit[i * out.lights + light] = count[i] == 0;
  }
  return out;
}

}  // namespace lockstep::opt::simd
