// lockstep optimized: per-tile cone culling (see cone_cull.h).
//
// Per frame, each primitive's bounding sphere becomes a direction and an
// angular radius from the eye; per tile, the cone through the tile's four
// corner pixels is tested against them. Both in double: the test costs one dot
// product and one cosine per primitive and tile, small beside tracing the
// tile's packets against the primitives it keeps.
#include "optimized/cone_cull.h"

#include <algorithm>
#include <cmath>

namespace lockstep::opt::simd {

ConeBounds cone_bounds(const SimdScene& s) {
  ConeBounds cb;
  const size_t n = s.b_center.size();
  cb.dir.resize(n);
  cb.beta.resize(n);
  cb.contains_eye.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const double dist = length(s.b_center[i]);
    const double r = s.b_radius[i] * (1 + 1e-6) + 1e-30;
    cb.contains_eye[i] = dist <= r;
    if (cb.contains_eye[i]) continue;
    cb.dir[i] = s.b_center[i] / dist;
    cb.beta[i] = std::asin(r / dist);
  }
  return cb;
}

void cull_tile(const SimdScene& s, const ConeBounds& cb, const Camera& cam, int i0, int i1, int j0, int j1,
               Candidates& out) {
  out.spheres.clear();
  out.triangles.clear();
  // Cone through the tile's four corner pixel centres (the directions of all
  // pixels in between lie in their convex hull on the image plane).
  const Vec3 corner[4] = {normalize(cam.camera_dir(i0, j0)), normalize(cam.camera_dir(i1 - 1, j0)),
                          normalize(cam.camera_dir(i0, j1 - 1)), normalize(cam.camera_dir(i1 - 1, j1 - 1))};
  const Vec3 axis = normalize(corner[0] + corner[1] + corner[2] + corner[3]);
  double cos_alpha = 1;
  for (const Vec3& c : corner) cos_alpha = std::min(cos_alpha, dot(axis, c));
  const double alpha = std::acos(std::clamp(cos_alpha, -1.0, 1.0)) + 1e-5;
  const size_t ns = s.spheres();
  for (size_t i = 0; i < cb.dir.size(); ++i) {
    bool keep = cb.contains_eye[i] != 0;
    if (!keep) {
      const double reach = alpha + cb.beta[i];
      keep = reach >= M_PI || dot(axis, cb.dir[i]) >= std::cos(reach);
    }
    if (!keep) continue;
    if (i < ns) out.spheres.push_back(uint32_t(i));
    else out.triangles.push_back(uint32_t(i - ns));
  }
}

}  // namespace lockstep::opt::simd
