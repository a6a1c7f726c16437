// Ray-cone kernel, reference: the nearest visible root of the cone's quadric
// (reference/ray_cone.h for the derivation and the two forms).
#include "reference/ray_cone.h"

#include "reference/ray_cast.h"

namespace lockstep::ref {

double ray_cone_t(const Scene& scene, uint32_t cone, const Ray& ray, double tmax, SphereSides sides, bool textbook) {
  const ConeQuadric<double> c = cone_quadric<double>(ray.o, ray.d, scene.cone_base[cone], scene.cone_r0[cone],
                                                     scene.cone_apex[cone], scene.cone_r1[cone]);
  double t0, t1;
  if (!(textbook ? cone_roots_textbook(c, t0, t1) : cone_roots_stable(c, t0, t1))) return kInfinity;
  const bool inside = scene.cone_inside[cone] != 0;
  for (double t : {t0, t1}) {
    if (!(t > ray.tmin && t < tmax) || !cone_in_height(c, t)) continue;
    if (sides == SphereSides::kNff) {
      // d.n for the outward normal n = w_perp - r k u is half the quadric's
      // slope along the ray: negative where the ray enters through the outside.
      double slope;
      cone_residual(c, t, slope);
      if (inside ? !(slope > 0) : !(slope < 0)) continue;
    }
    return t;
  }
  return kInfinity;
}

}  // namespace lockstep::ref
