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
  return build_shadow_maps(
      scene, s, [](const ScreenMesh& frame, const RasterSettings& depth, Visibility& vis) {
        zbuffer_visibility(frame, depth, vis);
      });
}

}  // namespace lockstep::ref
