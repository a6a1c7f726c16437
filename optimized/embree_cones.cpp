// lockstep optimized: NFF cones ('c') in Embree 3, as a user geometry
// (RTC_GEOMETRY_TYPE_USER: bounds, intersect and occluded callbacks), attached
// by build_scene (optimized/embree_scene.h) with the fixed id kConeGeom.
//
// Why not Embree's own RTC_GEOMETRY_TYPE_CONE_LINEAR_CURVE: it draws each
// linear curve segment as a *capped* cone (Embree 3.12 release notes: "a real
// geometric surface for curves with linear basis is rendered using capped
// cones"; the ROUND_LINEAR variant closes the segment with a sphere instead),
// solid, seen from both sides, with its radii and roots in float. NFF's `c` is
// an open-ended truncated cone seen from outside only (inside only for
// negative radii): looking into the open end of a tube, NFF shows no end disc
// and no inner wall (it is the invisible side), where Embree's cap would show
// a disc. Removing the caps in a filter would need the hit's position along
// the segment and would still leave a float root (the textbook quadric, as
// Embree's spheres, which loses the silhouette of thin far cylinders). So the
// cone is a user geometry running the careful root form in double
// (optimized/ray_cone.h): exact open ends, NFF's sidedness decided from the
// quadric's slope at the root (no filter callback), t good to double before
// refine_hit() even looks at it. The cost is a callback per candidate cone,
// which the SPD scenes (7 to 54 cones) do not notice.
//
// Occlusion (shadow rays) sees every surface from both sides, as the
// reference ray tracer's shadow test does (reference/ray_trace.cpp).
#include <algorithm>
#include <cmath>

#include "optimized/embree_scene.h"
#include "optimized/ray_cone.h"

namespace lockstep::opt::embree {

namespace {

// The cone's own box: each end disc of radius r about a unit axis u reaches
// r sqrt(1 - u_k^2) along axis k, and the side lies in the hull of the two
// discs (a long thin tube across the axes gets a box far tighter than its
// bounding sphere's). Padded by a few float ulps of the coordinates'
// magnitude so that rounding the box to float cannot cut the cone.
void cone_bounds(const RTCBoundsFunctionArguments* args) {
  const auto& data = *static_cast<const ConeGeomData*>(args->geometryUserPtr);
  const ConeShape& c = data.shape[args->primID];
  const Vec3 u = normalize(c.apex - c.base);
  float lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    const double reach = std::sqrt(std::max(0.0, 1 - u[k] * u[k]));
    const double a0 = c.base[k] - c.r0 * reach, a1 = c.apex[k] - c.r1 * reach;
    const double b0 = c.base[k] + c.r0 * reach, b1 = c.apex[k] + c.r1 * reach;
    const double pad = 4e-7 * (std::abs(c.base[k]) + std::abs(c.apex[k]) + c.r0 + c.r1) + 1e-30;
    lo[k] = float(std::min(a0, a1) - pad);
    hi[k] = float(std::max(b0, b1) + pad);
  }
  RTCBounds* b = args->bounds_o;
  b->lower_x = lo[0], b->lower_y = lo[1], b->lower_z = lo[2];
  b->upper_x = hi[0], b->upper_y = hi[1], b->upper_z = hi[2];
}

// The nearest visible root of lane i in its (tnear, tfar), from the float ray
// Embree traces, in double; false if none.
bool cone_hit(const ConeShape& c, bool solid, RTCRayN* ray, unsigned n, unsigned i, double& t) {
  const Vec3 o{RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i), RTCRayN_org_z(ray, n, i)};
  const Vec3 d{RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i), RTCRayN_dir_z(ray, n, i)};
  t = cone_nearest(c, o, d, RTCRayN_tnear(ray, n, i), RTCRayN_tfar(ray, n, i), solid);
  // Embree keeps t in float: the rounded root must still lie in the range.
  return t<kInfinity&& float(t)> RTCRayN_tnear(ray, n, i) && float(t) < RTCRayN_tfar(ray, n, i);
}

void cone_intersect(const RTCIntersectFunctionNArguments* args) {
  const auto& data = *static_cast<const ConeGeomData*>(args->geometryUserPtr);
  const unsigned n = args->N, prim = args->primID;
  const ConeShape& c = data.shape[prim];
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, n);
  for (unsigned i = 0; i < n; ++i) {
    double t;
    if (!args->valid[i] || !cone_hit(c, data.solid, ray, n, i, t)) continue;
    // The outward normal (core/shading.cpp's cone gradient) in the frame; the
    // rows shade from the scene's own normal, this is for Embree's record.
    const Vec3 p{RTCRayN_org_x(ray, n, i) + t * RTCRayN_dir_x(ray, n, i),
                 RTCRayN_org_y(ray, n, i) + t * RTCRayN_dir_y(ray, n, i),
                 RTCRayN_org_z(ray, n, i) + t * RTCRayN_dir_z(ray, n, i)};
    const Vec3 axis = c.apex - c.base;
    const double h = length(axis);
    const Vec3 u = axis / h;
    const double k = (c.r1 - c.r0) / h;
    const Vec3 w = p - c.base;
    const double s = dot(w, u);
    const Vec3 g = (w - s * u) - (c.r0 + k * s) * k * u;
    record_user_hit(args, i, float(t), g, kConeGeom);
  }
}

void cone_occluded(const RTCOccludedFunctionNArguments* args) {
  const auto& data = *static_cast<const ConeGeomData*>(args->geometryUserPtr);
  const unsigned n = args->N;
  const ConeShape& c = data.shape[args->primID];
  for (unsigned i = 0; i < n; ++i) {
    double t;
    if (args->valid[i] && cone_hit(c, true, args->ray, n, i, t))
      RTCRayN_tfar(args->ray, n, i) = -HUGE_VALF;  // Embree's "occluded"
  }
}

}  // namespace

void attach_cones(EmbreeScene& es, const Scene& scene, const BuildOptions& options) {
  if (scene.cone_count() == 0) return;
  es.cones.solid = options.solid_spheres;  // ray tracing: cones are solids too (core/ray_trace.h)
  es.cones.shape = cone_shapes(scene, [&](const Vec3& p) { return es.frame.point(p); });
  attach_user_geometry(es, scene.cone_count(), &es.cones, cone_bounds, cone_intersect, cone_occluded, kConeGeom,
                       "cones");
}

}  // namespace lockstep::opt::embree
