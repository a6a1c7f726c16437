// lockstep optimized: preparing the float scene for the SIMD kernels (see simd_scene.h).
//
// Every sphere and triangle is moved into the frame in double (relative to its
// origin, then rotated) and only then rounded to float, so that the kernels'
// float arithmetic starts from the best floats there are, however far the
// scene is from the world origin. Also records each primitive's bounding
// sphere in double, for the per-tile culling (optimized/cone_cull.h).
#include "optimized/simd_scene.h"

#include <algorithm>
#include <cmath>

namespace lockstep::opt::simd {

void SimdScene::add_sphere(const Vec3& c, double r, uint32_t prim) {
  const Vec3 cf = frame.point(c);
  sx.push_back(float(cf.x));
  sy.push_back(float(cf.y));
  sz.push_back(float(cf.z));
  const float rf = float(std::abs(r));
  sr2.push_back(rf * rf);
  s_inside.push_back(r < 0);
  s_prim.push_back(prim);
  // Spheres come before triangles in the bounds arrays.
  b_center.insert(b_center.begin() + long(spheres() - 1), cf);
  b_radius.insert(b_radius.begin() + long(spheres() - 1), std::abs(r));
}

void SimdScene::add_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n, bool two_sided,
                             uint32_t prim, uint32_t tri) {
  const Vec3 v[3] = {frame.point(a), frame.point(b), frame.point(c)};
  for (int k = 0; k < 3; ++k)
    for (int ax = 0; ax < 3; ++ax) tv[k][ax].push_back(float(v[k][ax]));
  const Vec3 nf = frame.dir(n);
  for (int ax = 0; ax < 3; ++ax) tn[ax].push_back(float(nf[ax]));
  t_two_sided.push_back(two_sided);
  t_prim.push_back(prim);
  t_tri.push_back(tri);
  const Vec3 centroid = (v[0] + v[1] + v[2]) / 3.0;
  b_center.push_back(centroid);
  b_radius.push_back(std::max({length(v[0] - centroid), length(v[1] - centroid), length(v[2] - centroid)}));
}

std::string float_triangle_limit(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double m = std::max({max_abs_component(a), max_abs_component(b), max_abs_component(c)});
  const double e = std::max({max_abs_component(b - a), max_abs_component(c - b), max_abs_component(a - c)});
  if (!(m <= kFloatTriangleMax)) return "triangle beyond float range: a coordinate above 2^40 = 1.1e12 from the eye";
  if (!(e >= kFloatMin)) return "triangle below float range: smaller than 2^-40 = 9.1e-13";
  return "";
}

std::string float_sphere_limit(const Vec3& centre, double radius) {
  const double r = std::abs(radius);
  if (!(std::max(max_abs_component(centre), r) <= kFloatSphereMax))
    return "sphere beyond float range: centre or radius above 2^60 = 1.2e18 from the eye";
  if (!(r >= kFloatMin)) return "sphere below float range: radius under 2^-40 = 9.1e-13";
  return "";
}

Candidates all_candidates(const SimdScene& s) {
  Candidates c;
  c.spheres.resize(s.spheres());
  c.triangles.resize(s.triangles());
  for (size_t i = 0; i < c.spheres.size(); ++i) c.spheres[i] = uint32_t(i);
  for (size_t i = 0; i < c.triangles.size(); ++i) c.triangles[i] = uint32_t(i);
  return c;
}

SimdScene prepare_scene(const Scene& scene, const Frame& frame, bool cull) {
  SimdScene s;
  s.frame = frame;
  s.cull = cull;
  for (uint32_t i = 0; i < scene.sphere_count(); ++i) {
    const std::string why = float_sphere_limit(frame.point(scene.sphere_center[i]), scene.sphere_radius[i]);
    if (!why.empty()) {
      ++s.dropped[why];
      s.add_sphere(frame.origin, 0, i);  // radius 0 at the eye: no ray takes it (c = 0 is not outside)
      continue;
    }
    s.add_sphere(scene.sphere_center[i], scene.sphere_radius[i], i);
  }
  for (uint32_t k = 0; k < scene.triangle_count(); ++k) {
    const uint32_t poly = scene.tri_poly[k];
    const auto& t = scene.tri_vertex[k];
    const bool two_sided = scene.materials[scene.poly_material[poly]].two_sided();
    const std::string why = float_triangle_limit(frame.point(scene.vertex[t[0]]), frame.point(scene.vertex[t[1]]),
                                                 frame.point(scene.vertex[t[2]]));
    if (!why.empty()) {
      ++s.dropped[why];
      // Zero area at the eye: every edge function is 0, det = 0, never taken.
      s.add_triangle(frame.origin, frame.origin, frame.origin, scene.poly_plane[poly].n, two_sided,
                     scene.sphere_count() + poly, k);
      continue;
    }
    s.add_triangle(scene.vertex[t[0]], scene.vertex[t[1]], scene.vertex[t[2]], scene.poly_plane[poly].n, two_sided,
                   scene.sphere_count() + poly, k);
  }
  if (const uint64_t n = range_lost_polygons(scene)) s.dropped[kNormalLostToRange] += n;
  return s;
}

}  // namespace lockstep::opt::simd
