// lockstep optimized: the simd z-buffer with shadows=map (core/shadow_map.h)
// and shadows=volume (the stencil counts: optimized/zbuffer/zbuffer_shadow_volume.cpp).
//
// Both passes on the fast rasterizer: pass 1 draws each light's six cube faces
// through opt::simd::zbuffer_distances (Highway edge functions, TBB tiles; the
// same snapped mesh and exact edge functions as the reference, so the same
// coverage, depth in double), each texel's distance written from the tile's
// buffers as the tile is drawn (it used to go through a Visibility copied out
// and then walked again, which cost more than the reference's whole pass 1);
// pass 2 finds the eye's visible samples the same way (opt::simd::view_scene's
// mesh, bit for bit the reference's). The shading is not SIMD: each visible
// sample is shaded in double by shade_fragment with the map's test or the
// volumes' masks (what ref::zbuffer computes, rows in parallel on TBB), not by
// the SIMD float shading kernels, which have no per-light visibility input.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>

#include "core/shadow_map.h"
#include "optimized/tiling.h"
#include "optimized/zbuffer/zbuffer_simd.h"

namespace lockstep::opt::simd {

namespace {

int64_t edge(const ScreenVertex& a, const ScreenVertex& b, int64_t px, int64_t py) {
  return int64_t(b.x - a.x) * (py - a.y) - int64_t(b.y - a.y) * (px - a.x);
}

// The fragment the reference's loop makes of triangle tri at sample (px, py)
// (1/256 pixel): screen barycentrics from the exact edge functions, depth from
// the plane of 1/z, perspective-correct barycentrics (reference/zbuffer.cpp).
Fragment fragment_at(const ScreenMesh& mesh, uint32_t tri, int64_t px, int64_t py,
                     bool perspective) {
  const ScreenTri& t = mesh.tris[tri];
  const ScreenVertex &v0 = t.v[0], &v1 = t.v[1], &v2 = t.v[2];
  const int64_t area = edge(v0, v1, v2.x, v2.y);
  const int64_t e0 = edge(v1, v2, px, py), e1 = edge(v2, v0, px, py), e2 = edge(v0, v1, px, py);
  const double l0 = double(e0) / double(area), l1 = double(e1) / double(area),
               l2 = double(e2) / double(area);
  const double inv_z = l0 / v0.z + l1 / v1.z + l2 / v2.z;
  Fragment f;
  f.tri = tri;
  f.z = 1 / inv_z;
  f.sx = double(px) / kSubpixel;
  f.sy = double(py) / kSubpixel;
  if (perspective) {
    f.b[0] = l0 / v0.z / inv_z;
    f.b[1] = l1 / v1.z / inv_z;
    f.b[2] = l2 / v2.z / inv_z;
  } else {
    f.b[0] = l0;
    f.b[1] = l1;
    f.b[2] = l2;
  }
  return f;
}

}  // namespace

ShadowMaps shadow_maps(const Scene& scene, const RasterSettings& s, int threads) {
  return build_shadow_maps_direct(
      scene, s, [threads](const ScreenMesh& frame, const RasterSettings& depth, float* dist) {
        zbuffer_distances(frame, depth, threads, dist);
      });
}

Image zbuffer_shadowed(const Scene& scene, const FrameOptions& opts, const RasterSettings& s,
                       FrameStats* stats) {
  check_shadow_settings(s, scene.source, opts.params.get("shading", "phong"));
  const bool volume = s.shadows == ShadowMode::kVolume;
  const ShadowMaps maps = volume ? ShadowMaps{} : shadow_maps(scene, s, opts.threads);
  const ScreenMesh mesh = view_scene(scene, opts.width, opts.height, s, opts.threads);
  Visibility vis;
  zbuffer_visibility(mesh, s, opts.threads, vis);
  const auto offsets = sample_offsets(s);
  const int spp = vis.spp, w = opts.width, h = opts.height;
  const LightReach reach = [&](uint32_t light, const Vec3& p, const Vec3& normal) {
    return lit_fraction(maps.cubes[light], s, p, normal);
  };
  // Volumes: the lights each visible sample's stencil counts left at 0
  // (optimized/zbuffer/zbuffer_shadow_volume.cpp), read by the shading below as the
  // reference's shade_fragment_lit reads them (a light's term added when lit:
  // shade_fragment with reach 1 or 0 sums the same terms in the same order).
  const ShadowVolumeMasks masks =
      volume ? shadow_volume_masks(scene, mesh, s, vis, opts.threads) : ShadowVolumeMasks{};
  Image image(w, h);
  image.depth.assign(size_t(w) * size_t(h), float(kInfinity));
  tbb::task_arena arena(resolve_threads(opts.threads));
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
      for (int j = rows.begin(); j < rows.end(); ++j)
        for (int i = 0; i < w; ++i) {
          Vec3 sum;
          float z = float(kInfinity);
          for (int k = 0; k < spp; ++k) {
            const uint32_t tri =
                vis.tri[(size_t(j) * size_t(w) + size_t(i)) * size_t(spp) + size_t(k)];
            if (tri == Visibility::kNone) {
              sum += Vec3(Vec3f(scene.background));
              continue;
            }
            const Fragment f =
                fragment_at(mesh, tri, int64_t(i) * kSubpixel + offsets[size_t(k)][0],
                            int64_t(j) * kSubpixel + offsets[size_t(k)][1], s.perspective);
            if (volume) {
              const uint8_t* lit =
                  &masks.lit[((size_t(j) * size_t(w) + size_t(i)) * size_t(spp) + size_t(k)) *
                             masks.lights];
              const LightReach from_mask = [lit](uint32_t light, const Vec3&, const Vec3&) {
                return lit[light] ? 1.0 : 0.0;
              };
              sum += Vec3(Vec3f(shade_fragment(scene, mesh, s, f, from_mask)));
            } else {
              sum += Vec3(Vec3f(shade_fragment(scene, mesh, s, f, reach)));
            }
            z = std::min(z, float(f.z));
          }
          image.set(i, j, sum / double(spp));
          image.depth[size_t(j) * size_t(w) + size_t(i)] = z;
        }
    });
  });
  if (stats) {
    stats->items = mesh.scene_tris + mesh.sphere_tris;
    stats->dropped = mesh.dropped;
    if (!masks.note.empty()) stats->notes.push_back(masks.note);
  }
  if (opts.progress) opts.progress(1.0);
  return image;
}

}  // namespace lockstep::opt::simd
