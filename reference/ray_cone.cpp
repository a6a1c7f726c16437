// Ray-cone kernel, reference: the nearest visible root of the cone's quadric
// (core/cone_quadric.h for the derivation and the two forms).
#include "core/cone_quadric.h"

#include "reference/ray_cast.h"

namespace lockstep::ref {

double ray_cone_t(const Scene& scene, uint32_t cone, const Ray& ray, double tmax, SphereSides sides, bool textbook) {
  ConeQuadric<double> c;
  double t0, t1, shift = 0;
  if (textbook) {
    c = cone_quadric<double>(ray.o, ray.d, scene.cone_base[cone], scene.cone_r0[cone], scene.cone_apex[cone],
                             scene.cone_r1[cone]);
    if (!cone_roots_textbook(c, t0, t1)) return kInfinity;
  } else if (!cone_roots_careful(ray.o, ray.d, scene.cone_base[cone], scene.cone_r0[cone], scene.cone_apex[cone],
                                 scene.cone_r1[cone], c, shift, t0, t1)) {
    return kInfinity;
  }
  const bool inside = scene.cone_inside[cone] != 0;
  for (double t : {t0, t1}) {
    // c is about the moved origin: its height and slope are at t - shift.
    if (!(t > ray.tmin && t < tmax) || !cone_in_height(c, t - shift)) continue;
    if (sides == SphereSides::kNff) {
      // d.n for the outward normal n = w_perp - r k u is half the quadric's
      // slope along the ray: negative where the ray enters through the outside.
      double slope;
      cone_residual(c, t - shift, slope);
      if (inside ? !(slope > 0) : !(slope < 0)) continue;
    }
    return t;
  }
  return kInfinity;
}

void ray_cone(std::span<const Ray> rays, const Scene& scene, uint32_t cone, std::span<double> t) {
  for (size_t i = 0; i < rays.size(); ++i)
    t[i] = ray_cone_t(scene, cone, rays[i], rays[i].tmax, SphereSides::kSolid, true);
}

}  // namespace lockstep::ref
