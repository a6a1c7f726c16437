// Ray tracing (Whitted) with Intel Embree 3: every ray through Embree's BVH.
//
// The scene is optimized/embree_scene.h's, built with solid spheres (core/
// ray_trace.h: a refracted ray inside a ball meets its far wall) in a frame
// translated to the eye moved towards the scene: along the view direction by
// t0, the nearest approach of any primitive's bounding sphere to the eye (a
// lower bound of every primary hit's distance), so that from far away the
// coordinates Embree rounds to float are of the scene's size, not of the
// eye's distance (issue #30), and from nearby the frame is the eye's, as it
// was. Every primary ray starts t0 along its line (in double; its t then
// counted from the eye again), inside the frame too. The frame depends on
// nothing but the eye and the nearest primitive: objects hidden behind others
// change no bit of it. A primitive whose bounding sphere holds the eye (a
// ground polygon wider than the eye's distance) keeps t0 = 0: the eye's frame,
// whose float coordinates grow with the eye's distance. Per ray, as the
// reference does it (reference/ray_trace.cpp):
//   * the nearest hit of primary, reflected and refracted rays, its t then
//     recomputed in double for the primitive Embree chose (optimized/
//     refine.h), so hit points are double-accurate and shading (core/
//     shading.h, double) is the reference's;
//   * shadow rays: occlusion queries, which stop at the first blocker and run
//     no intersection filter (every surface blocks from both sides, as in the
//     reference);
//   * the frame traces each tile breadth first (Wavefront below): all primary
//     rays of the tile as one stream (rtcIntersect1M, coherent), then all
//     their shadow rays as one stream (rtcOccluded1M: Embree sorts them by
//     direction octant and traces them in packets), then all the reflected and
//     refracted rays they spawned (rtcIntersect1M, incoherent: packets of 8)
//     and their shadow rays, level by level; colours are summed bottom up in
//     the depth-first order, so the frame is the one-ray-at-a-time tracer's
//     (Tracer below: rtcIntersect1 and rtcOccluded1, depth first, the ray tree
//     of `lockstep trace`) except where Embree's packet and single-ray sphere
//     tests, which round t differently by an ulp, change which of two
//     surfaces within float's rounding is nearest (props Pixel, explained
//     float_tie; one pixel of rt-pov-rings-7, 0.002, where a sphere meets a
//     cylinder);
//   * self-intersection: the hit is moved onto its surface (core/ray_trace.h
//     surface_point) and, by default, offset along the geometric normal to
//     the side the new ray leaves on by the robust offset (core/ray_trace.h
//     robust_offset): 32 float unit roundoffs of the primitive's magnitude
//     in this frame, i.e. the very coordinates Embree traverses with, plus
//     the hit's own bound; the ray counts hits from t = 0. With eps=E, the
//     textbook fixed offset instead (in double, then rounded).
// Pixels are spread over the cores in 16 x 16 tiles by opt::parallel_tiles
// (optimized/tiling.h); the BVH build runs in the same thread count.
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "core/camera.h"
#include "core/shading.h"
#include "core/timer.h"
#include "optimized/embree_scene.h"
#include "optimized/ray_trace_embree.h"
#include "optimized/refine.h"
#include "optimized/tiling.h"

namespace lockstep::opt::embree {

namespace {

// Embree's own offset is the robust one.
TraceSettings resolved(TraceSettings s) {
  if (s.offset == Offset::kOwn) s.offset = Offset::kRobust;
  return s;
}

// The Embree scene in its frame, and what the tracers need beside it: each
// primitive's magnitude in the frame (core/ray_trace.h prim_magnitude: the
// robust offset's scale) and t0, how far along its line every primary ray
// starts.
struct FrameScene {
  std::unique_ptr<EmbreeScene> es;
  std::vector<double> magnitude;
  double t0 = 0;
};

// Where the primary ray of pixel (i, j) starts, in the frame: t0 along its
// line when that is beyond the hither distance, at the eye otherwise. shift:
// the distance from the eye, to be added to hits' t; tnear: the hither
// distance left.
struct PrimaryStart {
  Vec3 o, d;
  double tnear = 0, shift = 0;
};
PrimaryStart primary_start(const FrameScene& fs, const Camera& cam, int i, int j) {
  const Ray r = cam.primary(i, j);
  PrimaryStart s;
  s.d = r.d;
  if (fs.t0 > r.tmin) {
    s.shift = fs.t0;
    s.o = fs.es->frame.point(r.o + fs.t0 * r.d);
  } else {
    s.o = fs.es->frame.point(r.o);
    s.tnear = r.tmin;
  }
  return s;
}

// Rays are held in the scene's frame (world minus its origin), in double;
// world(q) is where a frame point is for shading and lights. What both
// tracers share: the scene, the settings, the ray counts and the shading of a
// hit.
struct Shader {
  const Scene& scene;
  const FrameScene& fs;
  const EmbreeScene& es;
  const TraceSettings& settings;
  RayTree* tree = nullptr;
  RayCounts rays;
  RTCIntersectContext context;

  Shader(const Scene& s, const FrameScene& f, const TraceSettings& t, RayTree* r)
      : scene(s), fs(f), es(*f.es), settings(t), tree(r) {
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

  static void load(RTCRayHit& rh, const Vec3& o, const Vec3& d, double tnear) {
    load(rh.ray, o, d, tnear, kInfinity);
    rh.hit.geomID = rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    for (unsigned& id : rh.hit.instID) id = RTC_INVALID_GEOMETRY_ID;
  }

  // Embree's answer for the frame ray (o, d) as the scene's hit, t refined in double.
  Hit hit_of(const RTCRayHit& rh, const Vec3& o, const Vec3& d) const {
    Hit h;
    if (!prim_of(es, scene, rh.hit.geomID, rh.hit.primID, h)) return h;
    h.t = rh.ray.tfar;
    refine_hit(scene, Ray{world(o), d}, h);
    return h;
  }

  // The shading of the hit of the frame ray (o, d) (core/ray_trace.h), the
  // reference's in double. Returns ambient plus each light's term, in light
  // order, that needs no shadow ray or whose shadow ray shadow(so, dir, dist,
  // k, term) says to add now (true: reached; false: blocked, or deferred by a
  // breadth-first caller that adds the term later itself). Each secondary
  // ray goes to spawn(kind, start, dir, weight, k, entering) (k: its kr or
  // kt); a value it returns is that ray's colour, added times k. me: the
  // node in the ray tree (for a TIR node), if one is kept.
  template <class ShadowFn, class SpawnFn>
  Vec3 shade(const Vec3& o, const Vec3& d, const Hit& hit, int depth, double weight, int me,
             ShadowFn&& shadow, SpawnFn&& spawn) {
    // The hit moved onto its surface (world, double), then in the frame.
    const SurfacePoint sp = surface_point(scene, hit.prim, Ray{world(o), d}, hit.t);
    const Vec3& p = sp.p;
    const Vec3 q = p - es.frame.origin;
    const double mag = fs.magnitude[hit.prim];
    const Vec3 n = surface_normal(scene, hit.prim, hit.tri, p, d);
    const Vec3 ng = outward_normal(scene, hit.prim, p);
    const Material& m = scene.material_of_prim(hit.prim);
    Vec3 color = kAmbient * (m.kd * m.color);
    for (uint32_t k = 0; k < scene.lights.size(); ++k) {
      const LightSample ls = light_at(scene, scene.lights[k], p);
      if (dot(n, ls.l) <= 0) continue;
      const Vec3 term = phong_light(m, n, -d, ls);
      if (settings.shadows) {
        const Vec3 so = ray_start(q, sp.err, mag, ng, ls.l, settings, Arith::kFloat);
        const Vec3 to_light = (scene.lights[k].position - es.frame.origin) - so;
        const double dist = length(to_light);
        rays.add(RayKind::kShadow);
        if (!shadow(so, to_light / dist, dist, k, term)) continue;
      }
      color += term;
    }
    if (depth >= settings.max_depth) return color;
    const double kr = std::min(1.0, m.ks);
    if (kr > 0 && weight * kr >= settings.cutoff) {
      const Vec3 r = reflect(d, n);
      if (const std::optional<Vec3> c =
              spawn(RayKind::kReflect, ray_start(q, sp.err, mag, ng, r, settings, Arith::kFloat), r,
                    weight * kr, kr, false))
        color += kr * *c;
    }
    const double kt = std::min(1.0, m.transmittance);
    if (kt > 0 && weight * kt >= settings.cutoff) {
      const bool entering = dot(d, ng) < 0;
      Vec3 t;
      if (refract(d, n, entering ? 1.0 / m.ior : m.ior, t)) {
        if (const std::optional<Vec3> c =
                spawn(RayKind::kRefract, ray_start(q, sp.err, mag, ng, t, settings, Arith::kFloat),
                      t, weight * kt, kt, entering))
          color += kt * *c;
      } else {
        record(tree, tir_node(me, depth + 1, p, d, weight * kt, entering));
      }
    }
    return color;
  }
};

// Depth first, one ray at a time (rtcIntersect1, rtcOccluded1), recording the
// ray tree: `lockstep trace` and the properties' trees (trace_pixel).
struct Tracer : Shader {
  using Shader::Shader;

  Hit nearest(const Vec3& o, const Vec3& d, double tnear) {
    RTCRayHit rh;
    load(rh, o, d, tnear);
    rtcIntersect1(es.scene, &context, &rh);
    return hit_of(rh, o, d);
  }

  bool occluded(const Vec3& o, const Vec3& d, double tfar) {
    RTCRay r;
    load(r, o, d, 0.0, tfar);
    rtcOccluded1(es.scene, &context, &r);
    return r.tfar < 0;  // Embree's "occluded": tfar = -inf
  }

  // shift: how far o is along the ray from where the tree says it starts
  // (primary rays: from the eye, primary_start).
  Vec3 trace(const Vec3& o, const Vec3& d, double tnear, RayKind kind, int depth, double weight,
             int parent, bool entering, double shift = 0) {
    rays.add(kind);
    const int me = record(tree, RayNode{kind,
                                        parent,
                                        depth,
                                        world(o) - shift * d,
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
    const Vec3 c = hit.hit() ? shade_node(o, d, hit, depth, weight, me) : scene.background;
    if (tree) {
      tree->nodes[me].hit = hit;
      if (hit.hit()) tree->nodes[me].hit.t += shift;
      tree->nodes[me].color = c;
    }
    return c;
  }

  Vec3 shade_node(const Vec3& o, const Vec3& d, const Hit& hit, int depth, double weight, int me) {
    return shade(
        o, d, hit, depth, weight, me,
        [&](const Vec3& so, const Vec3& dir, double dist, uint32_t k, const Vec3& term) {
          const bool dark = occluded(so, dir, dist);
          record(tree, RayNode{RayKind::kShadow,
                               me,
                               depth,
                               world(so),
                               dir,
                               dist,
                               {},
                               weight,
                               dark ? Vec3{} : term,
                               k,
                               dark});
          return !dark;
        },
        [&](RayKind kind, const Vec3& start, const Vec3& dir, double w, double, bool entering) {
          return std::optional<Vec3>(trace(start, dir, 0.0, kind, depth + 1, w, me, entering));
        });
  }

  // Pixel (i, j): the primary ray from the eye, started where primary_start says.
  Vec3 pixel(const Camera& cam, int i, int j) {
    const PrimaryStart s = primary_start(fs, cam, i, j);
    return trace(s.o, s.d, s.tnear, RayKind::kPrimary, 1, 1.0, -1, false, s.shift);
  }
};

// Breadth first over a tile (a wavefront): the primary rays of every pixel
// as one stream (rtcIntersect1M), then all their shadow rays as one stream
// (rtcOccluded1M), then all the reflected and refracted rays they spawned as
// the next stream, and so on down the tree. Every ray is the depth-first
// tracer's, with the same weights and cut-off; each traced ray is a node
// whose local colour (ambient plus the lights its shadow rays reach, added in
// light order) is known once its level's shadow rays are answered, and the
// tile's colours are then summed bottom up, each node's reflected child
// before its refracted one: the same additions in the same order as the
// depth-first recursion, so the frame is bit for bit the same (pixel() of the
// Tracer, the property Pixel checks it).
struct Wavefront : Shader {
  struct Node {
    Vec3 color;               // local, then (summed) the ray's colour
    int child[2] = {-1, -1};  // reflected, refracted: node indices
    double k[2] = {0, 0};     // their kr, kt
  };
  struct Pending {  // a ray of the current level
    Vec3 o, d;
    double tnear = 0, weight = 1;
    int node = -1, depth = 1;
    RayKind kind = RayKind::kPrimary;
  };
  struct Deferred {  // a shadow ray's light term, added if it reaches
    int node;
    Vec3 term;
  };
  std::vector<Node> nodes;
  std::vector<Pending> level, next;
  std::vector<RTCRayHit> hits;
  std::vector<RTCRay> shadow_rays;
  std::vector<Deferred> deferred;

  using Shader::Shader;

  void tile(const Camera& cam, int x0, int y0, int x1, int y1, Image& image) {
    nodes.clear();
    level.clear();
    for (int j = y0; j < y1; ++j)
      for (int i = x0; i < x1; ++i) {
        const PrimaryStart s = primary_start(fs, cam, i, j);
        level.push_back(Pending{s.o, s.d, s.tnear, 1.0, int(nodes.size()), 1, RayKind::kPrimary});
        nodes.emplace_back();
      }
    // Primary rays of a tile are coherent (Embree's stream traversal); the
    // bounces below are not (packets of 8, occlusion sorted by octant).
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    while (!level.empty()) {
      hits.resize(level.size());
      for (size_t r = 0; r < level.size(); ++r)
        load(hits[r], level[r].o, level[r].d, level[r].tnear);
      rtcIntersect1M(es.scene, &context, hits.data(), unsigned(hits.size()), sizeof(RTCRayHit));
      context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
      next.clear();
      shadow_rays.clear();
      deferred.clear();
      for (size_t r = 0; r < level.size(); ++r) {
        const Pending ray = level[r];
        rays.add(ray.kind);
        const Hit hit = hit_of(hits[r], ray.o, ray.d);
        if (!hit.hit()) {
          nodes[ray.node].color = scene.background;
          continue;
        }
        const Vec3 local = shade(
            ray.o, ray.d, hit, ray.depth, ray.weight, -1,
            [&](const Vec3& so, const Vec3& dir, double dist, uint32_t, const Vec3& term) {
              shadow_rays.emplace_back();
              load(shadow_rays.back(), so, dir, 0.0, dist);
              deferred.push_back(Deferred{ray.node, term});
              return false;  // added below, once the stream is answered
            },
            [&](RayKind kind, const Vec3& start, const Vec3& dir, double w, double k, bool) {
              const int child = int(nodes.size());
              nodes.emplace_back();  // may move nodes: index it afresh
              const int slot = kind == RayKind::kReflect ? 0 : 1;
              nodes[ray.node].child[slot] = child;
              nodes[ray.node].k[slot] = k;
              next.push_back(Pending{start, dir, 0.0, w, child, ray.depth + 1, kind});
              return std::optional<Vec3>();
            });
        nodes[ray.node].color = local;
      }
      if (!shadow_rays.empty())
        rtcOccluded1M(es.scene, &context, shadow_rays.data(), unsigned(shadow_rays.size()),
                      sizeof(RTCRay));
      for (size_t s = 0; s < deferred.size(); ++s)
        if (!(shadow_rays[s].tfar < 0)) nodes[deferred[s].node].color += deferred[s].term;
      std::swap(level, next);
    }
    // Children come after their parents: sum from the last node back.
    for (size_t n = nodes.size(); n-- > 0;) {
      Node& me = nodes[n];
      for (int c = 0; c < 2; ++c)
        if (me.child[c] >= 0) me.color += me.k[c] * nodes[me.child[c]].color;
    }
    size_t n = 0;
    for (int j = y0; j < y1; ++j)
      for (int i = x0; i < x1; ++i) image.set(i, j, nodes[n++].color);
  }
};

// t0: the nearest approach of any primitive's bounding sphere to the eye
// (a sphere's own; a polygon's about its vertices' centroid; a cone's about
// its axis' midpoint), less 1e-6 of itself for the rounding of the sums (far
// above it: double's is ~1e-16 relative); 0 when a bounding sphere holds the
// eye or the scene is empty.
double nearest_approach(const Scene& scene, const Vec3& eye) {
  double t = kInfinity;
  auto add = [&](const Vec3& c, double r) { t = std::min(t, length(c - eye) - r); };
  for (uint32_t k = 0; k < scene.sphere_count(); ++k)
    add(scene.sphere_center[k], std::abs(scene.sphere_radius[k]));
  for (uint32_t p = 0; p < scene.polygon_count(); ++p) {
    const uint32_t first = scene.poly_first[p], last = scene.poly_first[p + 1];
    Vec3 c{};
    for (uint32_t v = first; v < last; ++v) c += scene.vertex[v];
    c = c / double(std::max(1u, last - first));
    double r = 0;
    for (uint32_t v = first; v < last; ++v) r = std::max(r, length(scene.vertex[v] - c));
    add(c, r);
  }
  for (uint32_t k = 0; k < scene.cone_count(); ++k)
    add(0.5 * (scene.cone_base[k] + scene.cone_apex[k]),
        0.5 * length(scene.cone_apex[k] - scene.cone_base[k]) +
            std::max(std::abs(scene.cone_r0[k]), std::abs(scene.cone_r1[k])));
  return std::isfinite(t) && t > 0 ? t * (1 - 1e-6) : 0.0;
}

FrameScene build(const Scene& scene, const Camera& cam, int threads,
                 const Device& device = Device()) {
  FrameScene fs;
  fs.t0 = nearest_approach(scene, cam.eye);
  Frame frame;
  frame.origin = cam.eye + fs.t0 * normalize(cam.forward);
  // Embree's TBB tasking builds in the calling thread's arena.
  tbb::task_arena(resolve_threads(threads)).execute([&] {
    fs.es = build_scene(scene, frame, {.solid_spheres = true, .device = device});
  });
  fs.magnitude.resize(scene.prim_count());
  for (uint32_t p = 0; p < scene.prim_count(); ++p)
    fs.magnitude[p] = prim_magnitude(scene, p, frame.origin);
  return fs;
}

}  // namespace

Vec3 trace_pixel(const Scene& scene, const TraceSettings& settings, int width, int height, int x,
                 int y, RayTree* tree) {
  return trace_pixel_with(scene, settings, width, height, x, y, tree, Device());
}

Vec3 trace_pixel_with(const Scene& scene, const TraceSettings& settings, int width, int height,
                      int x, int y, RayTree* tree, const Device& device) {
  const Camera cam = Camera::from_view(scene.view, width, height);
  const FrameScene fs = build(scene, cam, 1, device);
  const TraceSettings s = resolved(settings);
  Tracer tracer(scene, fs, s, tree);
  const Vec3 c = tracer.pixel(cam, x, y);
  fs.es->device.check("rtcIntersect1");
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
  const FrameScene fs = build(scene, cam, opts.threads, device);
  EmbreeScene* es = fs.es.get();
  const double build_seconds = build_timer.seconds();
  Image image(opts.width, opts.height);
  std::atomic<uint64_t> by_kind[4] = {};
  parallel_tiles(opts.width, opts.height, 16, 16, opts.threads, opts.progress,
                 [&](int x0, int y0, int x1, int y1) {
                   Wavefront wave(scene, fs, settings, nullptr);
                   wave.tile(cam, x0, y0, x1, y1, image);
                   for (int k = 0; k < 4; ++k) by_kind[k] += wave.rays.n[k];
                 });
  es->device.check("rtcIntersect1M");
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
