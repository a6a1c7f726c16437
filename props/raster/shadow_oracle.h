// lockstep props: the shadow-ray oracle for shadow volumes (issue #22), shared
// by tests/shadow_volume_test.cpp and props/raster/shadow_volume.cpp.
//
// The oracle is the reference ray tracer's local term at depth 1 with shadow
// rays (reference/ray_trace.cpp): a light contributes at a hit when it is on
// the side the normal faces and a shadow ray from the hit, moved off the
// surface by the fixed eps, reaches it without meeting any surface (either
// side). look() asks that question at any screen position, not only at pixel
// centres, so that a pixel where shadow volumes and shadow rays disagree can be
// classified: if the oracle's own answer changes within kEdgeRadius pixels of
// the sample, the sample lies within rounding of a shadow edge (the volume's
// faces are snapped to 1/256 pixel and their depths come from snapped planes),
// and the difference is explained; otherwise it is wrong.
#pragma once

#include <cstdint>

#include "core/camera.h"
#include "core/ray_trace.h"
#include "core/scene.h"
#include "core/shading.h"
#include "reference/ray_cast.h"
#include "reference/ray_polygon.h"
#include "reference/ray_sphere.h"

namespace lockstep::shadow_oracle {

// How far from a sample (pixels) the oracle's answer may change for a
// difference to count as shadow-edge rounding: 4 snapping steps (1/64 pixel).
inline constexpr double kEdgeRadius = 1.0 / 64;

struct Look {
  bool hit = false;
  uint32_t prim = 0;
  uint64_t lit = 0;  // bit k: light k contributes (lights beyond 64 are not looked at)
  // Bit k: light k is on the side the shading normal faces (a shadow ray is cast).
  uint64_t faced = 0;
};

// Any surface but prim `skip` on the shadow ray in (0, tmax)?
// (reference/ray_trace.cpp's blocked)
inline bool blocked(const Scene& scene, const Ray& ray, uint32_t skip = 0xffffffffu) {
  for (uint32_t s = 0; s < scene.sphere_count(); ++s) {
    double t0, t1;
    if (s == skip || !ref::sphere_roots<double>(ray.o, ray.d, scene.sphere_center[s],
                                                scene.sphere_radius[s], t0, t1))
      continue;
    for (double t : {t0, t1})
      if (t > ray.tmin && t < ray.tmax) return true;
  }
  for (uint32_t p = 0; p < scene.polygon_count(); ++p)
    if (scene.sphere_count() + p != skip && ref::ray_polygon_t(ray, scene, p) < ray.tmax)
      return true;
  return false;
}

// The view ray through screen position (px, py), unit direction, and the
// length of its direction with forward component 1.
inline Ray view_ray(const Camera& cam, double px, double py, double* len_out = nullptr) {
  const Vec3 d0 = cam.forward + ((px - 0.5 * cam.width) * cam.pitch) * cam.right +
                  ((0.5 * cam.height - py) * cam.pitch) * cam.up;
  const double len = length(d0);
  if (len_out) *len_out = len;
  return Ray{cam.eye, d0 / len, cam.hither * len, kInfinity};
}

// Which lights reach the point where `ray` meets primitive hit.prim at hit.t.
inline Look lights_at(const Scene& scene, const Ray& ray, const Hit& hit) {
  Look out;
  if (!hit.hit() || !(hit.t < kInfinity)) return out;
  out.hit = true;
  out.prim = hit.prim;
  const Vec3 p = ray.o + hit.t * ray.d;
  const Vec3 n = surface_normal(scene, hit.prim, hit.tri, p, ray.d);
  const Vec3 ng = outward_normal(scene, hit.prim, p);
  TraceSettings ts;
  ts.offset = Offset::kFixed;
  for (uint32_t k = 0; k < scene.lights.size() && k < 64; ++k) {
    const LightSample ls = light_at(scene, scene.lights[k], p);
    if (dot(n, ls.l) <= 0) continue;
    out.faced |= uint64_t(1) << k;
    const Vec3 o = ray_start(p, 0, 0, ng, ls.l, ts, Arith::kDouble);
    const Vec3 to_light = scene.lights[k].position - o;
    const double dist = length(to_light);
    if (!blocked(scene, Ray{o, to_light / dist, 0.0, dist})) out.lit |= uint64_t(1) << k;
  }
  return out;
}

// The visible surface through screen position (px, py) (pixels, y down; pixel
// (i, j)'s centre is (i + 1/2, j + 1/2)) and which lights reach it.
inline Look look(const Scene& scene, const Camera& cam, double px, double py) {
  const Ray ray = view_ray(cam, px, py);
  return lights_at(scene, ray, ref::nearest_hit(scene, ray, ref::SphereSides::kSolid));
}

// The same at the point where the view ray through (px, py) meets polygon
// primitive `prim` (spheres first, then polygons: Scene::prim_count), nearest
// or not: the surface a z-buffer drew where it kept another than the nearest.
// hit is false when the ray misses it (or prim is not a polygon).
inline Look look_at(const Scene& scene, const Camera& cam, double px, double py, uint32_t prim) {
  const Ray ray = view_ray(cam, px, py);
  Hit hit;
  if (prim >= scene.sphere_count() && prim - scene.sphere_count() < scene.polygon_count()) {
    hit.t = ref::ray_polygon_t(ray, scene, prim - scene.sphere_count());
    if (hit.t < kInfinity) hit.prim = prim;
  }
  return lights_at(scene, ray, hit);
}

// Whether the oracle's answer (surface and lights) changes within radius r
// pixels of (px, py): the centre against 8 points on the square around it.
inline bool near_edge(const Scene& scene, const Camera& cam, double px, double py, double r) {
  const Look c = look(scene, cam, px, py);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      if (dx == 0 && dy == 0) continue;
      const Look o = look(scene, cam, px + dx * r, py + dy * r);
      if (o.hit != c.hit || o.prim != c.prim || o.lit != c.lit) return true;
    }
  return false;
}

// The smallest of r = 1/4096, 1/1024, 1/256, 1/64, 1/16 pixel at which the
// oracle changes near (px, py), or 0 when none does.
inline double edge_radius(const Scene& scene, const Camera& cam, double px, double py) {
  for (double r : {1.0 / 4096, 1.0 / 1024, 1.0 / 256, 1.0 / 64, 1.0 / 16})
    if (near_edge(scene, cam, px, py, r)) return r;
  return 0;
}

// Contact: whether another surface passes within delta of the visible point
// along its normal, so that the shadow ray's answer depends on which side of
// the surface it starts (the fixed-eps offset decides; the volume's answer
// comes from depths that differ in the last bits): shadow rays from
// p + delta n and p - delta n (n the geometric normal), ignoring the visible
// primitive itself, disagree for some light. Coplanar overlapping triangles
// (the flat handle of the SPD teapot at size 1) and objects resting on others.
inline bool contact(const Scene& scene, const Camera& cam, double px, double py, double delta) {
  const Ray ray = view_ray(cam, px, py);
  const Hit hit = ref::nearest_hit(scene, ray, ref::SphereSides::kSolid);
  if (!hit.hit()) return false;
  const Vec3 p = ray.o + hit.t * ray.d;
  const Vec3 ng = normalize(outward_normal(scene, hit.prim, p));
  for (const Light& light : scene.lights) {
    bool answer[2];
    for (int side = 0; side < 2; ++side) {
      const Vec3 o = p + (side ? delta : -delta) * ng;
      const Vec3 to_light = light.position - o;
      const double dist = length(to_light);
      answer[side] = blocked(scene, Ray{o, to_light / dist, 0.0, dist}, hit.prim);
    }
    if (answer[0] != answer[1]) return true;
  }
  return false;
}

// Z-pass counts the volume faces between the hither plane and the visible
// point, so it is off wherever the hither plane's point on the view ray lies
// in a shadow (the eye in shadow, as hither goes to 0): whether it does, for
// some light (shadow rays from that point).
inline bool hither_in_shadow(const Scene& scene, const Camera& cam, double px, double py,
                             double hither) {
  double len = 0;
  const Ray ray = view_ray(cam, px, py, &len);
  const Vec3 q = ray.o + (hither * len) * ray.d;
  for (const Light& light : scene.lights) {
    const Vec3 to_light = light.position - q;
    const double dist = length(to_light);
    if (blocked(scene, Ray{q, to_light / dist, 0.0, dist})) return true;
  }
  return false;
}

}  // namespace lockstep::shadow_oracle
