// lockstep props/raster: SetupIdentical -- opt::simd::view_scene's mesh is
// view_scene's, bit for bit, on corpus scenes (SetupIdentical.zbuffer__simd_corpus)
// and on random soups (SetupIdentical.zbuffer__simd; registered in visibility.cpp).
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "io/nff.h"
#include "optimized/zbuffer/zbuffer_simd.h"
#include "props/raster/visibility.h"

namespace lockstep::props::raster::vis {

namespace {

// Where opt::simd::view_scene's mesh differs from view_scene's ("" when it is
// the same, bit for bit).
std::string mesh_difference(const ScreenMesh& a, const ScreenMesh& b) {
  if (a.tris.size() != b.tris.size())
    return std::to_string(a.tris.size()) + " triangles against " + std::to_string(b.tris.size());
  if (a.scene_tris != b.scene_tris || a.sphere_tris != b.sphere_tris || a.culled != b.culled ||
      a.clipped != b.clipped || a.degenerate != b.degenerate || a.near_z != b.near_z ||
      a.far_z != b.far_z)
    return "other counts or near/far";
  auto same = [](const Vec3& x, const Vec3& y) { return x.x == y.x && x.y == y.y && x.z == y.z; };
  for (size_t i = 0; i < a.tris.size(); ++i) {
    const ScreenTri &s = a.tris[i], &t = b.tris[i];
    bool ok = s.prim == t.prim && s.source_tri == t.source_tri &&
              same(s.face_normal, t.face_normal) && same(s.flat_color, t.flat_color);
    for (int k = 0; k < 3; ++k) {
      const ScreenVertex &u = s.v[size_t(k)], &w = t.v[size_t(k)];
      ok = ok && u.x == w.x && u.y == w.y && u.z == w.z && same(u.world, w.world) &&
           same(u.normal, w.normal) && same(u.color, w.color);
    }
    if (!ok) return "triangle " + std::to_string(i) + " differs";
  }
  return "";
}

}  // namespace

// The optimized set-up against view_scene on corpus scenes (spheres: balls,
// shells, near-sphere, which crosses the hither plane), every culling mode, the
// shadings whose set-up differs (flat colour, Gouraud colours; Phong's is
// flat's without the colour); the sphere scenes also at 640 x 480, where their
// spheres get many more rings.
void setup_identical() {
  for (const char* name :
       {"tetra-3.nff", "teapot-2.nff", "gears-2.nff", "mount-3.nff", "patches.nff", "concave.nff",
        "watertight-cube.nff", "balls-2.nff", "balls-3.nff", "shells-1.nff", "near-sphere.nff",
        "sidedness.nff", "spotlights.nff"}) {
    const Scene scene = read_nff(std::string(LOCKSTEP_CORPUS_DIR) + "/scenes/" + name);
    std::vector<std::array<int, 2>> sizes = {{96, 80}};
    if (scene.sphere_count() > 0) sizes.push_back({640, 480});
    for (const auto& [w, h] : sizes)
      for (CullMode cull : {CullMode::kWorld, CullMode::kProjection, CullMode::kNone})
        for (Shading sh : {Shading::kFlat, Shading::kGouraud})
          for (int threads : {1, 2}) {
            RasterSettings s;
            s.cull = cull;
            s.shading = sh;
            const ScreenMesh a = opt::simd::view_scene(scene, w, h, s, threads);
            const ScreenMesh b = lockstep::view_scene(scene, w, h, s);
            EXPECT_EQ(mesh_difference(a, b), "") << name << " " << w << "x" << h << " cull "
                                                 << int(cull) << " shading " << int(sh);
          }
  }
}

// One outcome per (culling mode, shading) of the case's scene (soups have
// two-sided triangles and triangles crossing the hither plane: the fallback).
Verdict setup_case(const RasterCase& c) {
  const auto scene = c.scene();
  RasterSettings s = raster_settings(c.params, "<case>");
  Verdict v;
  for (CullMode cull : {CullMode::kWorld, CullMode::kProjection, CullMode::kNone})
    for (Shading sh : {Shading::kFlat, Shading::kGouraud}) {
      s.cull = cull;
      s.shading = sh;
      Outcome out;
      out.detail = mesh_difference(opt::simd::view_scene(*scene, c.width, c.height, s, 1),
                                   lockstep::view_scene(*scene, c.width, c.height, s));
      if (!out.detail.empty()) {
        out.kind = Outcome::unexplained, out.label = "mesh";
        out.detail +=
            " (cull " + std::to_string(int(cull)) + ", shading " + std::to_string(int(sh)) + ")";
      }
      v.rays.push_back(out);
    }
  return v;
}

}  // namespace lockstep::props::raster::vis
