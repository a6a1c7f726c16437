// Ray casting, reference: one primary ray per pixel, nearest hit over all
// objects by brute force, Phong at the hit (core/shading.h), background on a miss.
//
// Source: Appel 1968 / Whitted 1980 without the recursive rays; the loop is
// the one in every lecture: for each pixel, for each object, keep the nearest.
// Scalar, double precision, single-threaded, on purpose.

#include "core/camera.h"
#include "reference/ray_cast.h"
#include "core/shading.h"
#include "reference/ray_polygon.h"
#include "reference/ray_sphere.h"

namespace lockstep::ref {

Hit nearest_hit(const Scene& scene, const Ray& ray, SphereSides sides) {
  Hit best;
  best.t = ray.tmax;
  // Spheres: try the roots in order; a root counts only if it is in range and
  // its side of the sphere is the visible one (NFF: outside, or inside for r <
  // 0), or, for solid spheres, whatever its side.
  for (uint32_t s = 0; s < scene.sphere_count(); ++s) {
    double t0, t1;
    if (!sphere_roots<double>(ray.o, ray.d, scene.sphere_center[s], scene.sphere_radius[s], t0, t1)) continue;
    for (double t : {t0, t1}) {
      if (!(t > ray.tmin && t < best.t)) continue;
      const Vec3 outward = ray.o + t * ray.d - scene.sphere_center[s];
      if (sides == SphereSides::kNff && !visible_side(scene, s, dot(ray.d, outward))) continue;
      best.t = t;
      best.prim = s;
      break;
    }
  }
  // Polygons: plane, inside test, and the one-sided rule (back faces culled).
  for (uint32_t p = 0; p < scene.polygon_count(); ++p) {
    const uint32_t prim = scene.sphere_count() + p;
    if (!visible_side(scene, prim, dot(ray.d, scene.poly_plane[p].n))) continue;
    const double t = ray_polygon_t(Ray{ray.o, ray.d, ray.tmin, best.t}, scene, p);
    if (t < best.t) {
      best.t = t;
      best.prim = prim;
    }
  }
  // Cones: the nearest visible root on the finite part (reference/ray_cone.cpp).
  for (uint32_t c = 0; c < scene.cone_count(); ++c) {
    const double t = ray_cone_t(scene, c, ray, best.t, sides);
    if (t < best.t) {
      best.t = t;
      best.prim = scene.cone_first_prim() + c;
    }
  }
  if (!best.hit()) best.t = kInfinity;
  return best;
}

void trace(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, FrameStats* stats) {
  for (size_t i = 0; i < rays.size(); ++i) hits[i] = nearest_hit(scene, rays[i]);
  if (stats) {
    stats->items = rays.size();    stats->drop(kNormalLostToRange, range_lost_polygons(scene));
  }
}

Image render(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  const Camera camera = Camera::from_view(scene.view, opts.width, opts.height);
  Image image(opts.width, opts.height);
  for (int j = 0; j < opts.height; ++j) {
    for (int i = 0; i < opts.width; ++i) {
      const Ray ray = camera.primary(i, j);
      image.set(i, j, shade(scene, ray, nearest_hit(scene, ray)));
    }
    if (opts.progress) opts.progress(double(j + 1) / opts.height);
  }
  if (stats) {
    stats->items = uint64_t(opts.width) * uint64_t(opts.height);    stats->drop(kNormalLostToRange, range_lost_polygons(scene));
  }
  return image;
}

}  // namespace lockstep::ref
