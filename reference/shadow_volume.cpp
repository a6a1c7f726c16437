// lockstep reference: shadow volumes (see reference/shadow_volume.h for the
// method, the sources and what is exact).
#include "reference/shadow_volume.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/shading.h"

namespace lockstep::ref {

using Tri = std::array<Vec3, 3>;

// ---------------------------------------------------------------- stencil counting

namespace {

int64_t edge(const ScreenVertex& a, const ScreenVertex& b, int64_t px, int64_t py) {
  return int64_t(b.x - a.x) * (py - a.y) - int64_t(b.y - a.y) * (px - a.x);
}
bool top_left(const ScreenVertex& a, const ScreenVertex& b) {
  const int32_t dx = b.x - a.x, dy = b.y - a.y;
  return (dy == 0 && dx > 0) || dy < 0;
}
bool owns(int64_t e, bool is_top_left) { return e > 0 || (e == 0 && is_top_left); }

// Every sample of triangle t (the z-buffer's loop): visit(index, z).
template <class Visit>
void for_samples(const ScreenTri& t, int w, int h,
                 const std::vector<std::array<int32_t, 2>>& offsets, Visit visit) {
  const ScreenVertex &v0 = t.v[0], &v1 = t.v[1], &v2 = t.v[2];
  const bool tl0 = top_left(v1, v2), tl1 = top_left(v2, v0), tl2 = top_left(v0, v1);
  const int32_t xmin = std::min({v0.x, v1.x, v2.x}), xmax = std::max({v0.x, v1.x, v2.x});
  const int32_t ymin = std::min({v0.y, v1.y, v2.y}), ymax = std::max({v0.y, v1.y, v2.y});
  const int i0 = std::max(0, int(std::floor(double(xmin) / kSubpixel)));
  const int i1 = std::min(w - 1, int(std::floor(double(xmax) / kSubpixel)));
  const int j0 = std::max(0, int(std::floor(double(ymin) / kSubpixel)));
  const int j1 = std::min(h - 1, int(std::floor(double(ymax) / kSubpixel)));
  const int spp = int(offsets.size());
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i)
      for (int k = 0; k < spp; ++k) {
        const int64_t px = int64_t(i) * kSubpixel + offsets[k][0];
        const int64_t py = int64_t(j) * kSubpixel + offsets[k][1];
        const int64_t e0 = edge(v1, v2, px, py), e1 = edge(v2, v0, px, py),
                      e2 = edge(v0, v1, px, py);
        if (!owns(e0, tl0) || !owns(e1, tl1) || !owns(e2, tl2)) continue;
        visit((size_t(j) * w + i) * spp + k, sample_depth(t, e0, e1, e2));
      }
}

}  // namespace

std::vector<double> visible_z(const ScreenMesh& mesh, const RasterSettings& s,
                              const Visibility& vis) {
  std::vector<double> z(vis.tri.size(), kInfinity);
  const auto offsets = sample_offsets(s);
  for (uint32_t ti = 0; ti < mesh.tris.size(); ++ti)
    for_samples(mesh.tris[ti], mesh.width, mesh.height, offsets, [&](size_t index, double d) {
      if (vis.tri[index] == ti) z[index] = d;
    });
  return z;
}

void stencil_counts(const Scene& scene, const ScreenMesh& frame, const RasterSettings& s,
                    const std::vector<Tri>& volume, const std::vector<double>& z_visible,
                    std::vector<int32_t>& count, const std::vector<uint8_t>* is_cap) {
  count.assign(z_visible.size(), 0);
  const ViewedVolume vv = view_volume(scene, frame, s, volume, is_cap);
  const auto offsets = sample_offsets(s);
  for (size_t i = 0; i < vv.mesh.tris.size(); ++i)
    for_samples(vv.mesh.tris[i], vv.mesh.width, vv.mesh.height, offsets,
                [&](size_t index, double z) {
                  const double zv = z_visible[index];
                  if (zv == kInfinity) return;  // nothing drawn there
                  // A cap at exactly the visible depth is the visible triangle's own.
                  // Counting it or not is the count just before or just after the surface
                  // along the view ray; shadow rays leave from the surface's light side,
                  // which is the eye's side when the cap (outward = towards the light)
                  // faces the eye, and the far side when it does not. So an equal front
                  // cap is behind the surface, an equal back cap in front of it. A side
                  // at the visible depth (the sample on the silhouette edge it rises
                  // from) is behind, whichever way it faces, so that the two coincident
                  // sides of an edge shared by two per-triangle volumes cancel
                  // (stencil_step).
                  count[index] += stencil_step(s.zfail, vv.front[i], vv.cap[i], z, zv);
                });
}

ShadowMasks shadow_masks(const Scene& scene, const ScreenMesh& frame, const RasterSettings& s,
                         const OccluderMesh& occ, const Visibility& vis) {
  ShadowMasks masks;
  masks.lights = uint32_t(scene.lights.size());
  masks.lit.assign(vis.tri.size() * masks.lights, 1);
  const std::vector<double> z = visible_z(frame, s, vis);
  std::vector<int32_t> count;
  for (uint32_t k = 0; k < masks.lights; ++k) {
    const Vec3 light = scene.lights[k].position;
    // Capped for z-pass too: a front cap is where the view ray enters a
    // volume through its occluder, which counts when the occluder is not
    // drawn (a back face culled from the eye still casts a shadow) and at a
    // visible cap itself (a smooth-shaded triangle facing away from the light
    // but lit by its normal: stencil_counts' equal-depth rule). The back cap
    // lies beyond the scene and the eye, never in front of a visible point.
    std::vector<uint8_t> is_cap;
    const std::vector<Tri> volume =
        shadow_volume(occ, light, shadow_far(scene, light), true, false, &is_cap);
    masks.volume_tris += volume.size();
    stencil_counts(scene, frame, s, volume, z, count, &is_cap);
    for (size_t i = 0; i < count.size(); ++i) masks.lit[i * masks.lights + k] = count[i] == 0;
  }
  return masks;
}

// ---------------------------------------------------------------- shading

Vec3 shade_fragment_lit(const Scene& scene, const ScreenMesh& mesh, const RasterSettings& s,
                        const Fragment& f, const uint8_t* lit) {
  // shade_fragment's Phong (core/raster_shading.cpp), the light sum of phong()
  // (core/shading.cpp) restricted to the lights that reach the point.
  const ScreenTri& t = mesh.tris[f.tri];
  const Camera& cam = mesh.camera;
  const Material& m = scene.material_of_prim(t.prim);
  const double cx = (f.sx - 0.5 * mesh.width) * cam.pitch,
               cy = (0.5 * mesh.height - f.sy) * cam.pitch;
  const Vec3 dir = cam.forward + cx * cam.right + cy * cam.up;
  const Vec3 v = -normalize(dir);
  Vec3 n = f.b[0] * t.v[0].normal + f.b[1] * t.v[1].normal + f.b[2] * t.v[2].normal;
  n = length(n) > 0 ? normalize(n) : t.face_normal;
  if (dot(n, dir) > 0) n = -n;
  const Vec3 p = cam.eye + f.z * dir;
  const Specular spec = s.shading == Shading::kBlinn ? Specular::kBlinn : Specular::kPhong;
  Vec3 c = kAmbient * (m.kd * m.color);
  for (size_t k = 0; k < scene.lights.size(); ++k)
    if (lit[k]) c += phong_light(m, n, v, light_at(scene, scene.lights[k], p), spec);
  if (s.silhouette && std::abs(dot(n, v)) < s.silhouette_eps) c = Vec3{0, 0, 0};
  return c;
}

}  // namespace lockstep::ref
