// Ray tracing (Whitted) with Intel Embree 3: every ray through Embree's BVH.
//
// The scene is optimized/embree_scene.h's, built with solid spheres (core/
// ray_trace.h: a refracted ray inside a ball meets its far wall) in a frame
// translated to the eye, so that coordinates Embree rounds to float are
// eye-relative. Per pixel, as the reference does it (reference/ray_trace.cpp):
//   * the nearest hit of primary, reflected and refracted rays: rtcIntersect1
//     (scalar: after the first bounce neighbouring pixels' rays go apart), its
//     t then recomputed in double for the primitive Embree chose
//     (optimized/refine.h), so hit points are double-accurate and shading
//     (core/shading.h, double) is the reference's;
//   * shadow rays: rtcOccluded1, which stops at the first blocker and runs no
//     intersection filter (every surface blocks from both sides, as in the
//     reference);
//   * self-intersection: by default the robust offset of Waechter and Binder
//     (Ray Tracing Gems ch. 6; core/ray_trace.h offset_robust) on the float
//     hit point in the eye frame, i.e. the very coordinates Embree traverses
//     with: 256 n_i ulps of each coordinate along the geometric normal, to
//     the side the new ray leaves on, and the ray counts hits from t = 0.
//     With eps=E, the textbook fixed offset instead (in double, then rounded).
// Pixels are spread over the cores in 16 x 16 tiles by opt::parallel_tiles
// (optimized/tiling.h); the BVH build runs in the same thread count.
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>

#include "core/camera.h"
#include "core/shading.h"
#include "core/timer.h"
#include "optimized/embree_scene.h"
#include "optimized/ray_trace.h"
#include "optimized/refine.h"
#include "optimized/tiling.h"

namespace lockstep::opt::embree {

namespace {

// Embree's own offset is the robust one.
TraceSettings resolved(TraceSettings s) {
  if (s.offset == Offset::kOwn) s.offset = Offset::kRobust;
  return s;
}

// Rays are held in the eye frame (world minus the eye), in double; world(q)
// is where a frame point is for shading and lights.
struct Tracer {
  const Scene& scene;
  const EmbreeScene& es;
  const TraceSettings& settings;
  RayTree* tree = nullptr;
  RayCounts rays;
  RTCIntersectContext context;

  Tracer(const Scene& s, const EmbreeScene& e, const TraceSettings& t, RayTree* r)
      : scene(s), es(e), settings(t), tree(r) {
    rtcInitIntersectContext(&context);
  }

  Vec3 world(const Vec3& q) const { return q + es.frame.origin; }

  static void load(RTCRay& r, const Vec3& o, const Vec3& d, double tnear, double tfar) {
    r.org_x = float(o.x), r.org_y = float(o.y), r.org_z = float(o.z);
    r.dir_x = float(d.x), r.dir_y = float(d.y), r.dir_z = float(d.z);
    r.tnear = float(tnear);
    r.tfar = tfar < 3e38 ? float(tfar) : HUGE_VALF;
    r.time = 0;
    r.mask = 0xffffffffu;
    r.id = 0;
    r.flags = 0;
  }

  // Nearest hit of the frame ray (o, d), t refined in double.
  Hit nearest(const Vec3& o, const Vec3& d, double tnear) {
    RTCRayHit rh;
    load(rh.ray, o, d, tnear, kInfinity);
    rh.hit.geomID = rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    for (unsigned& id : rh.hit.instID) id = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(es.scene, &context, &rh);
    Hit h;
    if (!prim_of(es, scene, rh.hit.geomID, rh.hit.primID, h)) return h;
    h.t = rh.ray.tfar;
    refine_hit(scene, Ray{world(o), d}, h);
    return h;
  }

  bool occluded(const Vec3& o, const Vec3& d, double tfar) {
    RTCRay r;
    load(r, o, d, 0.0, tfar);
    rtcOccluded1(es.scene, &context, &r);
    return r.tfar < 0;  // Embree's "occluded": tfar = -inf
  }

  Vec3 trace(const Vec3& o, const Vec3& d, double tnear, RayKind kind, int depth, double weight,
             int parent, bool entering) {
    rays.add(kind);
    const int me = record(tree, RayNode{kind,
                                        parent,
                                        depth,
                                        world(o),
                                        d,
                                        kInfinity,
                                        {},
                                        weight,
                                        {},
                                        0,
                                        false,
                                        false,
                                        entering});
    const Hit hit = nearest(o, d, tnear);
    const Vec3 c = hit.hit() ? shade(o, d, hit, depth, weight, me) : scene.background;
    if (tree) {
      tree->nodes[me].hit = hit;
      tree->nodes[me].color = c;
    }
    return c;
  }

  Vec3 shade(const Vec3& o, const Vec3& d, const Hit& hit, int depth, double weight, int me) {
    const Vec3 q = o + hit.t * d;  // frame
    const Vec3 p = world(q);
    const Vec3 n = surface_normal(scene, hit.prim, hit.tri, p, d);
    const Vec3 ng = outward_normal(scene, hit.prim, p);
    const Material& m = scene.material_of_prim(hit.prim);
    Vec3 color = kAmbient * (m.kd * m.color);
    for (uint32_t k = 0; k < scene.lights.size(); ++k) {
      const LightSample ls = light_at(scene, scene.lights[k], p);
      if (dot(n, ls.l) <= 0) continue;
      const Vec3 term = phong_light(m, n, -d, ls);
      if (settings.shadows) {
        const Vec3 so = ray_start(q, ng, ls.l, settings, Arith::kFloat);
        const Vec3 to_light = (scene.lights[k].position - es.frame.origin) - so;
        const double dist = length(to_light);
        rays.add(RayKind::kShadow);
        const bool dark = occluded(so, to_light / dist, dist);
        record(tree, RayNode{RayKind::kShadow,
                             me,
                             depth,
                             world(so),
                             to_light / dist,
                             dist,
                             {},
                             weight,
                             dark ? Vec3{} : term,
                             k,
                             dark});
        if (dark) continue;
      }
      color += term;
    }
    if (depth >= settings.max_depth) return color;
    const double kr = std::min(1.0, m.ks);
    if (kr > 0 && weight * kr >= settings.cutoff) {
      const Vec3 r = reflect(d, n);
      color += kr * trace(ray_start(q, ng, r, settings, Arith::kFloat), r, 0.0, RayKind::kReflect,
                          depth + 1, weight * kr, me, false);
    }
    const double kt = std::min(1.0, m.transmittance);
    if (kt > 0 && weight * kt >= settings.cutoff) {
      const bool entering = dot(d, ng) < 0;
      Vec3 t;
      if (refract(d, n, entering ? 1.0 / m.ior : m.ior, t))
        color += kt * trace(ray_start(q, ng, t, settings, Arith::kFloat), t, 0.0, RayKind::kRefract,
                            depth + 1, weight * kt, me, entering);
      else
        record(tree, tir_node(me, depth + 1, p, d, weight * kt, entering));
    }
    return color;
  }

  // Pixel (i, j): the primary ray from the eye (the frame's origin).
  Vec3 pixel(const Camera& cam, int i, int j) {
    const Ray r = cam.primary(i, j);
    return trace(Vec3{0, 0, 0}, r.d, r.tmin, RayKind::kPrimary, 1, 1.0, -1, false);
  }
};

std::unique_ptr<EmbreeScene> build(const Scene& scene, const Camera& cam, int threads,
                                   const Device& device = Device()) {
  Frame frame;
  frame.origin = cam.eye;
  std::unique_ptr<EmbreeScene> es;
  // Embree's TBB tasking builds in the calling thread's arena.
  tbb::task_arena(resolve_threads(threads)).execute([&] {
    es = build_scene(scene, frame, {.solid_spheres = true, .device = device});
  });
  return es;
}

}  // namespace

Vec3 trace_pixel(const Scene& scene, const TraceSettings& settings, int width, int height, int x,
                 int y, RayTree* tree) {
  const Camera cam = Camera::from_view(scene.view, width, height);
  const auto es = build(scene, cam, 1);
  const TraceSettings s = resolved(settings);
  Tracer tracer(scene, *es, s, tree);
  const Vec3 c = tracer.pixel(cam, x, y);
  es->device.check("rtcIntersect1");
  return c;
}

Image trace_render(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  return trace_render_with(scene, opts, stats, Device());
}

Image trace_render_with(const Scene& scene, const FrameOptions& opts, FrameStats* stats,
                        const Device& device) {
  const TraceSettings settings = resolved(trace_settings(opts.params));
  const Camera cam = Camera::from_view(scene.view, opts.width, opts.height);
  const Stopwatch build_timer;
  const auto es = build(scene, cam, opts.threads, device);
  const double build_seconds = build_timer.seconds();
  Image image(opts.width, opts.height);
  std::atomic<uint64_t> by_kind[4] = {};
  parallel_tiles(opts.width, opts.height, 16, 16, opts.threads, opts.progress,
                 [&](int x0, int y0, int x1, int y1) {
                   Tracer tracer(scene, *es, settings, nullptr);
                   for (int j = y0; j < y1; ++j)
                     for (int i = x0; i < x1; ++i) image.set(i, j, tracer.pixel(cam, i, j));
                   for (int k = 0; k < 4; ++k) by_kind[k] += tracer.rays.n[k];
                 });
  es->device.check("rtcIntersect1");
  RayCounts rays;
  for (int k = 0; k < 4; ++k) rays.n[k] = by_kind[k];
  rays.report(stats);
  if (stats) {
    stats->build_seconds = build_seconds;
    for (const auto& [why, n] : es->dropped) stats->drop(why, n);
  }
  return image;
}

}  // namespace lockstep::opt::embree
