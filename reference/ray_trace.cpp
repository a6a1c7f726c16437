// Ray tracing, reference: Whitted's recursive ray tracer, as the lecture notes
// give it.
//
// Sources: T. Whitted, "An Improved Illumination Model for Shaded Display",
// CACM 23(6), 1980; Glassner (ed.), "An Introduction to Ray Tracing", 1989:
// ch. 1 (Glassner) for the recursion, ch. 2 (Haines) for the intersections
// (ray casting's brute-force nearest hit, reference/ray_cast.h, with solid
// spheres; reference/ray_sphere.h and reference/ray_polygon.h for shadows),
// ch. 5 (Heckbert) for the reflected and refracted directions (core/ray_trace.h:
// reflect, refract); R. Hall and D. Greenberg, "A Testbed for Realistic Image
// Synthesis", IEEE CG&A 3(8), 1983, for the adaptive cut-off on a ray's weight.
//
//   trace(ray, depth, weight):
//     find the nearest hit by trying every object; none: the background
//     colour = ambient
//     for each light: if a shadow ray from the hit reaches it, add its
//                     diffuse + specular term (Phong, core/shading.h)
//     if depth < max depth:
//       reflected ray (weight x kr), if that weight is not below the cut-off
//       refracted ray (weight x kt) by Snell's law, unless totally reflected
//     return colour + kr trace(reflected) + kt trace(refracted)
//
// Self-intersection, the textbook way: every ray that starts on a surface
// starts from the hit moved by a fixed eps (1e-6 world units unless the
// settings say otherwise) along the geometric normal, to the side the new ray
// leaves on, and counts hits from t = 0. The hit is first moved onto its
// surface (a sphere radially, a polygon onto its plane: core/ray_trace.h
// surface_point), since the ray's t carries an error that grows with the
// distance it was seen from (the textbook sphere from 1e5 away: ~1e-6). With
// the setting robust, the offset is the hit's error bound in double ulps of
// the surface's world coordinates (core/ray_trace.h robust_offset) instead.
//
// Double precision, scalar, one thread, brute force over every object: on
// purpose.
#include "reference/ray_trace.h"

#include <algorithm>

#include "core/camera.h"
#include "core/shading.h"
#include "reference/ray_cast.h"
#include "reference/ray_polygon.h"
#include "reference/ray_sphere.h"

namespace lockstep::ref {

namespace {

// The shadow test: is any surface, of either side, on the ray in (tmin, tmax)?
// The first blocker found goes into *blocker.
bool blocked(const Scene& scene, const Ray& ray, Hit* blocker) {
  for (uint32_t s = 0; s < scene.sphere_count(); ++s) {
    double t0, t1;
    if (!sphere_roots<double>(ray.o, ray.d, scene.sphere_center[s], scene.sphere_radius[s], t0, t1))
      continue;
    for (double t : {t0, t1})
      if (t > ray.tmin && t < ray.tmax) {
        *blocker = Hit{t, s};
        return true;
      }
  }
  for (uint32_t p = 0; p < scene.polygon_count(); ++p) {
    const double t = ray_polygon_t(ray, scene, p);
    if (t < ray.tmax) {
      *blocker = Hit{t, scene.sphere_count() + p};
      return true;
    }
  }
  for (uint32_t c = 0; c < scene.cone_count(); ++c) {
    const double t = ray_cone_t(scene, c, ray, ray.tmax, SphereSides::kSolid);
    if (t < ray.tmax) {
      *blocker = Hit{t, scene.cone_first_prim() + c};
      return true;
    }
  }
  return false;
}

struct Tracer {
  const Scene& scene;
  const TraceSettings& settings;
  RayTree* tree = nullptr;
  RayCounts rays;

  Vec3 trace(const Ray& ray, RayKind kind, int depth, double weight, int parent, bool entering) {
    rays.add(kind);
    const int me = record(tree, RayNode{kind,
                                        parent,
                                        depth,
                                        ray.o,
                                        ray.d,
                                        ray.tmax,
                                        {},
                                        weight,
                                        {},
                                        0,
                                        false,
                                        false,
                                        entering});
    const Hit hit = nearest_hit(scene, ray, SphereSides::kSolid);
    const Vec3 c = hit.hit() ? shade(ray, hit, depth, weight, me) : scene.background;
    if (tree) {
      tree->nodes[me].hit = hit;
      tree->nodes[me].color = c;
    }
    return c;
  }

  Vec3 shade(const Ray& ray, const Hit& hit, int depth, double weight, int me) {
    // The hit, moved onto its surface (core/ray_trace.h surface_point): the
    // point shaded and the one new rays leave from.
    const SurfacePoint sp = surface_point(scene, hit.prim, ray, hit.t);
    const Vec3& p = sp.p;
    const Vec3& d = ray.d;
    // How large the surface's coordinates are (the robust offset's scale).
    const double mag =
        settings.offset == Offset::kRobust ? prim_magnitude(scene, hit.prim, Vec3{}) : 0.0;
    const Vec3 n = surface_normal(scene, hit.prim, hit.tri, p, d);  // faces the incoming ray
    // The outward geometric normal: which side the ray comes from, where new rays start.
    const Vec3 ng = outward_normal(scene, hit.prim, p);
    const Material& m = scene.material_of_prim(hit.prim);

    // Local illumination: ambient, plus every light a shadow ray reaches.
    Vec3 color = kAmbient * (m.kd * m.color);
    for (uint32_t k = 0; k < scene.lights.size(); ++k) {
      const LightSample ls = light_at(scene, scene.lights[k], p);
      if (dot(n, ls.l) <= 0) continue;  // the light is behind the surface: nothing to test
      const Vec3 term = phong_light(m, n, -d, ls);
      if (settings.shadows) {
        const Vec3 o = ray_start(p, sp.err, mag, ng, ls.l, settings, Arith::kDouble);
        const Vec3 to_light = scene.lights[k].position - o;
        const double dist = length(to_light);
        const Ray shadow{o, to_light / dist, 0.0, dist};
        rays.add(RayKind::kShadow);
        Hit blocker;
        const bool dark = blocked(scene, shadow, &blocker);
        record(tree, RayNode{RayKind::kShadow, me, depth, shadow.o, shadow.d, dist, blocker, weight,
                             dark ? Vec3{} : term, k, dark});
        if (dark) continue;
      }
      color += term;
    }
    if (depth >= settings.max_depth) return color;

    // Reflection: the mirror direction, weighted by kr.
    const double kr = std::min(1.0, m.ks);
    if (kr > 0 && weight * kr >= settings.cutoff) {
      const Vec3 r = reflect(d, n);
      color += kr * trace(Ray{ray_start(p, sp.err, mag, ng, r, settings, Arith::kDouble), r},
                          RayKind::kReflect, depth + 1, weight * kr, me, false);
    }
    // Refraction: Snell's law, entering or leaving by the side the ray comes from.
    const double kt = std::min(1.0, m.transmittance);
    if (kt > 0 && weight * kt >= settings.cutoff) {
      const bool entering = dot(d, ng) < 0;
      const double eta = entering ? 1.0 / m.ior : m.ior;
      Vec3 t;
      if (refract(d, n, eta, t)) {
        color += kt * trace(Ray{ray_start(p, sp.err, mag, ng, t, settings, Arith::kDouble), t},
                            RayKind::kRefract, depth + 1, weight * kt, me, entering);
      } else {
        record(tree, tir_node(me, depth + 1, p, d, weight * kt, entering));
      }
    }
    return color;
  }
};

// The reference's own offset (core/ray_trace.h: Offset::kOwn) is the fixed eps.
TraceSettings resolved(TraceSettings s) {
  if (s.offset == Offset::kOwn) s.offset = Offset::kFixed;
  return s;
}

Vec3 pixel(const Scene& scene, const TraceSettings& settings, const Camera& camera, int x, int y,
           RayTree* tree, RayCounts* rays) {
  Tracer tracer{scene, settings, tree, {}};
  const Vec3 c = tracer.trace(camera.primary(x, y), RayKind::kPrimary, 1, 1.0, -1, false);
  if (rays) *rays += tracer.rays;
  return c;
}

}  // namespace

Vec3 trace_pixel(const Scene& scene, const TraceSettings& settings, int width, int height, int x,
                 int y, RayTree* tree) {
  return pixel(scene, resolved(settings), Camera::from_view(scene.view, width, height), x, y, tree,
               nullptr);
}

Image trace_render(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  const TraceSettings settings = resolved(trace_settings(opts.params));
  const Camera camera = Camera::from_view(scene.view, opts.width, opts.height);
  Image image(opts.width, opts.height);
  RayCounts rays;
  for (int j = 0; j < opts.height; ++j) {
    for (int i = 0; i < opts.width; ++i)
      image.set(i, j, pixel(scene, settings, camera, i, j, nullptr, &rays));
    if (opts.progress) opts.progress(double(j + 1) / opts.height);
  }
  rays.report(stats);
  if (stats) stats->drop(kNormalLostToRange, range_lost_polygons(scene));
  return image;
}

}  // namespace lockstep::ref
