// lockstep reference: the z-buffer (Catmull 1974; Foley et al., 2nd ed., 15.4),
// over the screen mesh of core/viewing.cpp, shaded by core/raster_shading.cpp.
//
// For every triangle, for every sample in its bounding box: the three edge
// functions in exact integer arithmetic decide coverage (top-left rule for
// samples exactly on an edge); the normalised edge functions are the screen
// barycentrics; 1/z is affine in screen space, so the depth at the sample comes
// from the plane of 1/z through the three vertices; if it is nearer than what
// the z-buffer holds, depth and colour are written.
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "core/error.h"
#include "core/shadow_map.h"
#include "reference/raster.h"
#include "reference/shadow_map.h"
#include "reference/shadow_volume.h"

namespace lockstep {

namespace {

// E_ab(P) for the edge a -> b: positive on the inside of a positive-area triangle.
int64_t edge(const ScreenVertex& a, const ScreenVertex& b, int64_t px, int64_t py) {
  return int64_t(b.x - a.x) * (py - a.y) - int64_t(b.y - a.y) * (px - a.x);
}

// The top-left rule: a sample exactly on edge a -> b belongs to this triangle
// only if the edge is a top edge (horizontal, going right) or a left edge
// (going up, with y down).
bool top_left(const ScreenVertex& a, const ScreenVertex& b) {
  const int32_t dx = b.x - a.x, dy = b.y - a.y;
  return (dy == 0 && dx > 0) || dy < 0;
}

bool owns(int64_t e, bool is_top_left) { return e > 0 || (e == 0 && is_top_left); }

}  // namespace

// ---------------------------------------------------------------- the z-buffer

namespace {

// The textbook loop, shared by zbuffer_visibility (no colour) and zbuffer
// (colour written with the depth): on_write(sample index, fragment) is called
// for every fragment that passes the depth test.
template <class OnWrite>
void zbuffer_loop(const ScreenMesh& mesh, const RasterSettings& s, Visibility& vis,
                  const std::function<void(double)>& progress, OnWrite on_write) {
  const int w = mesh.width, h = mesh.height;
  const auto offsets = sample_offsets(s);
  const int spp = int(offsets.size());
  vis.width = w;
  vis.height = h;
  vis.spp = spp;
  vis.tri.assign(size_t(w) * h * spp, Visibility::kNone);
  vis.depth.assign(size_t(w) * h * spp, empty_depth(s.depth));
  vis.count.assign(size_t(w) * h * spp, 0);

  for (uint32_t ti = 0; ti < mesh.tris.size(); ++ti) {
    if (progress && (ti & 4095) == 0) progress(double(ti) / double(mesh.tris.size()));
    const ScreenTri& t = mesh.tris[ti];
    const ScreenVertex &v0 = t.v[0], &v1 = t.v[1], &v2 = t.v[2];
    const int64_t area = edge(v0, v1, v2.x, v2.y);  // > 0 (view_scene's guarantee)
    const bool tl0 = top_left(v1, v2), tl1 = top_left(v2, v0), tl2 = top_left(v0, v1);

    // The pixels whose squares the triangle's bounding box touches, clamped to the image.
    const int32_t xmin = std::min({v0.x, v1.x, v2.x}), xmax = std::max({v0.x, v1.x, v2.x});
    const int32_t ymin = std::min({v0.y, v1.y, v2.y}), ymax = std::max({v0.y, v1.y, v2.y});
    const int i0 = std::max(0, int(std::floor(double(xmin) / kSubpixel)));
    const int i1 = std::min(w - 1, int(std::floor(double(xmax) / kSubpixel)));
    const int j0 = std::max(0, int(std::floor(double(ymin) / kSubpixel)));
    const int j1 = std::min(h - 1, int(std::floor(double(ymax) / kSubpixel)));

    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        for (int k = 0; k < spp; ++k) {
          const int64_t px = int64_t(i) * kSubpixel + offsets[k][0];
          const int64_t py = int64_t(j) * kSubpixel + offsets[k][1];
          // Coverage: all three edge functions on the inside (exact integers).
          const int64_t e0 = edge(v1, v2, px, py), e1 = edge(v2, v0, px, py), e2 = edge(v0, v1, px, py);
          if (!owns(e0, tl0) || !owns(e1, tl1) || !owns(e2, tl2)) continue;
          const size_t index = (size_t(j) * w + i) * spp + k;
          ++vis.count[index];
          // Screen barycentrics, then depth from the plane of 1/z.
          const double l0 = double(e0) / double(area), l1 = double(e1) / double(area), l2 = double(e2) / double(area);
          const double inv_z = l0 / v0.z + l1 / v1.z + l2 / v2.z;
          const double z = 1 / inv_z;
          const double d = stored_depth(s.depth, z, mesh.near_z, mesh.far_z);
          if (!nearer(s.depth, d, vis.depth[index])) continue;  // the first of equal depths stays
          vis.depth[index] = d;
          vis.tri[index] = ti;
          Fragment f;
          f.tri = ti;
          f.z = z;
          f.sx = double(px) / kSubpixel;
          f.sy = double(py) / kSubpixel;
          if (s.perspective) {
            // Perspective-correct: the barycentrics of the point in 3D are the
            // screen ones weighted by 1/z (Heckbert and Moreton 1991).
            f.b[0] = l0 / v0.z / inv_z;
            f.b[1] = l1 / v1.z / inv_z;
            f.b[2] = l2 / v2.z / inv_z;
          } else {
            f.b[0] = l0;
            f.b[1] = l1;
            f.b[2] = l2;
          }
          on_write(index, f);
        }
  }
}

}  // namespace

namespace ref {

void zbuffer_visibility(const ScreenMesh& mesh, const RasterSettings& s, Visibility& vis) {
  zbuffer_loop(mesh, s, vis, {}, [](size_t, const Fragment&) {});
}

Image zbuffer(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  const RasterSettings s = frame_settings(scene, opts);
  // This row draws both kinds; both need per-sample lighting.
  check_shadow_settings(s, scene.source, opts.params.get("shading", "phong"));
  // Shadows: pass 1 fills each light's cube map first (reference/shadow_map.h).
  const ShadowMaps maps = s.shadows == ShadowMode::kMap ? shadow_maps(scene, s) : ShadowMaps{};
  const LightReach reach = [&](uint32_t light, const Vec3& p, const Vec3& normal) {
    return lit_fraction(maps.cubes[light], s, p, normal);
  };
  // The sample buffers: colour, depth, visible triangle, coverage count.
  const double samples = double(opts.width) * opts.height * s.spp;
  const ScreenMesh mesh = view_scene(scene, opts.width, opts.height, s);
  Visibility vis;
  // Shadows: the visible samples first, then per light the stencil counts of
  // its shadow volume there (reference/shadow_volume.h); the colour pass below
  // lights each sample with the lights its counts left at 0.
  ShadowMasks masks;
  if (s.shadows == ShadowMode::kVolume) {
    zbuffer_loop(mesh, s, vis, {}, [](size_t, const Fragment&) {});
    const OccluderMesh occ = occluder_mesh(scene, mesh, s);
    masks = shadow_masks(scene, mesh, s, occ, vis);
    if (stats && occ.open_tris) stats->notes.push_back(occluder_note(occ));
  }
  std::vector<Vec3f> sample_color(size_t(samples), Vec3f(scene.background));
  std::vector<float> sample_z(sample_color.size(), float(kInfinity));
  zbuffer_loop(mesh, s, vis, opts.progress, [&](size_t index, const Fragment& f) {
    // An overdrawn fragment may get the final sample's lights; the visible one, written last, is right.
    sample_color[index] = Vec3f(masks.lights ? shade_fragment_lit(scene, mesh, s, f, &masks.lit[index * masks.lights])
                                : s.shadows == ShadowMode::kMap ? shade_fragment(scene, mesh, s, f, reach)
                                                                : shade_fragment(scene, mesh, s, f));
    sample_z[index] = float(f.z);
  });
  // Resolve: the box filter over each pixel's samples; depth is the nearest sample's.
  Image image(opts.width, opts.height);
  image.depth.assign(size_t(opts.width) * opts.height, float(kInfinity));
  const int spp = vis.spp;
  for (int j = 0; j < opts.height; ++j)
    for (int i = 0; i < opts.width; ++i) {
      Vec3 sum;
      float z = float(kInfinity);
      for (int k = 0; k < spp; ++k) {
        const size_t index = (size_t(j) * opts.width + i) * spp + k;
        sum += Vec3(sample_color[index]);
        z = std::min(z, sample_z[index]);
      }
      image.set(i, j, sum / double(spp));
      image.depth[size_t(j) * opts.width + i] = z;
    }
  if (stats) {
    stats->items = mesh.scene_tris + mesh.sphere_tris;
    stats->dropped = mesh.dropped;
  }
  if (opts.progress) opts.progress(1.0);
  return image;
}

}  // namespace ref

}  // namespace lockstep
