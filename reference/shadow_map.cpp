// lockstep reference: shadow maps, pass 1 (reference/shadow_map.h).
//
// Williams, "Casting curved shadows on curved surfaces", SIGGRAPH 1978; cube
// maps for point lights as in Akenine-Moller et al., "Real-Time Rendering",
// 4th ed., 7.4. The rasterizer's own pipeline draws each face: the same
// tessellation of spheres (in texels), the same clipping, snapping and
// top-left rule as the eye's pass, with no back-face culling.
#include "reference/shadow_map.h"

#include <cmath>

#include "reference/raster.h"

namespace lockstep::ref {

ShadowMaps shadow_maps(const Scene& scene, const RasterSettings& s) {
  const RasterSettings depth = depth_pass_settings(s);
  const int n = s.map_size;
  ShadowMaps maps;
  // One visibility buffer for every face: its arrays keep their pages (a
  // fresh 14 bytes a texel per face cost as much as drawing the face).
  Visibility vis;
  for (const Light& light : scene.lights) {
    ShadowCube cube;
    cube.light = light.position;
    cube.n = n;
    for (int face = 0; face < kCubeFaces; ++face) {
      ScreenMesh frame = cube_face_frame(scene, light.position, face, n);
      view_spheres(scene, depth, 0, scene.sphere_count(), frame);
      view_polygons(scene, depth, 0, scene.polygon_count(), frame);
      zbuffer_visibility(frame, depth, vis);
      std::vector<float>& dist = cube.dist[size_t(face)];
      dist.assign(size_t(n) * size_t(n), float(kInfinity));
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const size_t k = size_t(j) * size_t(n) + size_t(i);
          if (vis.tri[k] != Visibility::kNone) dist[k] = float(texel_distance(frame, vis.depth[k], i, j));
        }
    }
    maps.cubes.push_back(std::move(cube));
  }
  return maps;
}

}  // namespace lockstep::ref
