// Ray casting, optimized: opt::simd, the contract of core/ray_cast.h on the
// Highway kernels.
//
// The kernels (ray_cast_simd_kernels.cpp) see only float packets in a local
// frame; this file turns the contract's rays and hits into those and back:
//  * ray_sphere / ray_polygon / ray_plane (the kernel rows): one primitive
//    against many rays, each ray in a frame anchored at the primitive (for
//    ray_plane, at the ray's own origin), so its result does not depend on the
//    other rays of its packet;
//  * trace: arbitrary rays against the whole scene (framed at the first ray's
//    origin), packets over the cores with TBB, every hit refined in double;
//  * render: primary rays in the camera's frame, 32 x 8 screen tiles on
//    opt::parallel_tiles (optimized/tiling.h), each tile culled to the
//    primitives its cone of rays can reach (optimized/cone_cull.h), shaded 8 at
//    a time (optimized/shade_simd.h).
// NFF cones ('c') are not in the float kernels: after the packet, the rays are
// tested against every cone in double with the careful root form
// (optimized/ray_cone.h: a bounding-sphere rejection first), and a nearer cone
// replaces the kernel's hit. The cone kernel (ray_cast_simd_kernels.h cone_t)
// runs 4 rays a time on AVX2 with the scalar routine's exact arithmetic;
// render() tests only the cones whose bounding spheres survive the tile's
// culling (trace() tests every cone).
// Preparing the float scene is optimized/simd_scene.cpp.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/camera.h"
#include "optimized/cone_cull.h"
#include "optimized/ray_cast_simd.h"
#include "optimized/ray_cast_simd_kernels.h"
#include "optimized/ray_cone.h"
#include "optimized/refine.h"
#include "optimized/shade_simd.h"
#include "optimized/simd_scene.h"
#include "optimized/tiling.h"

namespace lockstep::opt::simd {

namespace {

// Puts ray k of a packet into the frame: unit direction, t range rescaled.
void load_ray(const Frame& f, const Ray& r, Packet& p, int k, double& scale) {
  const Vec3 o = f.point(r.o);
  const Vec3 d = f.dir(r.d);
  const double len = length(d);
  p.ox[k] = float(o.x), p.oy[k] = float(o.y), p.oz[k] = float(o.z);
  p.dx[k] = float(d.x / len), p.dy[k] = float(d.y / len), p.dz[k] = float(d.z / len);
  p.tmin[k] = float(r.tmin * len);
  p.tmax[k] = r.tmax * len < 3e38 ? float(r.tmax * len) : HUGE_VALF;
  scale = len;
}

void clear_tail(Packet& p) {
  for (int k = p.count; k < kPacket; ++k) {
    p.ox[k] = p.oy[k] = p.oz[k] = 0;
    p.dx[k] = p.dy[k] = 0;
    p.dz[k] = 1;
    p.tmin[k] = 0;
    p.tmax[k] = 0;
  }
}

Hit to_hit(const SimdScene& s, float t, int32_t id, double scale) {
  Hit h;
  if (id < 0) return h;
  h.t = double(t) / scale;
  if (size_t(id) < s.spheres()) {
    h.prim = s.s_prim[size_t(id)];
  } else {
    h.prim = s.t_prim[size_t(id) - s.spheres()];
    h.tri = s.t_tri[size_t(id) - s.spheres()];
  }
  return h;
}

// Traces rays through a prepared scene, packets of 8, serially.
void trace_prepared(const SimdScene& s, const Candidates& cand, std::span<const Ray> rays, std::span<Hit> hits) {
  Packet p;
  PacketHits out;
  double scale[kPacket];
  for (size_t i = 0; i < rays.size(); i += kPacket) {
    p.count = int(std::min<size_t>(kPacket, rays.size() - i));
    for (int k = 0; k < p.count; ++k) load_ray(s.frame, rays[i + size_t(k)], p, k, scale[k]);
    clear_tail(p);
    trace_packet(s, cand, p, out);
    for (int k = 0; k < p.count; ++k) hits[i + size_t(k)] = to_hit(s, out.t[k], out.id[k], scale[k]);
  }
}

// Kernel calls: one primitive against packets of rays with different origins.
// The frame's origin is the primitive's anchor (sphere centre, scene vertex), so
// every ray keeps the precision of "primitive-relative" coordinates (as good as
// camera-relative: the offset between ray origin and primitive is rounded to
// float once) and its result does not depend on the other rays in its packet.
// The scene is built once; only the rays change per packet.
template <class AddPrims>
void kernel(std::span<const Ray> rays, std::span<double> t, const Vec3& anchor, AddPrims add) {
  SimdScene s;
  s.cull = false;
  s.frame.origin = anchor;
  add(s);
  const Candidates cand = all_candidates(s);
  Packet p;
  PacketHits out;
  double scale[kPacket];
  for (size_t i = 0; i < rays.size(); i += kPacket) {
    const size_t n = std::min<size_t>(kPacket, rays.size() - i);
    p.count = int(n);
    for (size_t k = 0; k < n; ++k) load_ray(s.frame, rays[i + k], p, int(k), scale[k]);
    clear_tail(p);
    trace_packet(s, cand, p, out);
    for (size_t k = 0; k < n; ++k) t[i + k] = out.id[k] < 0 ? kInfinity : double(out.t[k]) / scale[k];
  }
}

// Rays in double, structure of arrays, for the cone kernel: n rays padded to a
// multiple of kPacket with empty ranges (tmin = tmax = 0: no hit).
struct ConeBatch {
  std::vector<double> ox, oy, oz, dx, dy, dz, tmin, tmax, t;
  explicit ConeBatch(size_t n) {
    const size_t m = (n + kPacket - 1) / kPacket * kPacket;
    for (auto* v : {&ox, &oy, &oz, &dx, &dy, &dz, &tmin, &tmax, &t}) v->assign(m, 0.0);
  }
  size_t size() const { return t.size(); }
  void set(size_t i, const Vec3& o, const Vec3& d, double t0, double t1) {
    ox[i] = o.x, oy[i] = o.y, oz[i] = o.z, dx[i] = d.x, dy[i] = d.y, dz[i] = d.z, tmin[i] = t0,
    tmax[i] = t1;
  }
  ConeRays rays() const {
    return {ox.data(), oy.data(), oz.data(),   dx.data(),
            dy.data(), dz.data(), tmin.data(), tmax.data()};
  }
};

}  // namespace

// ---------------------------------------------------------------- the contract
void ray_sphere(std::span<const Ray> rays, const Sphere& sphere, std::span<double> t) {
  kernel(rays, t, sphere.center, [&](SimdScene& s) { s.add_sphere(sphere.center, sphere.radius, 0); });
}

void ray_polygon(std::span<const Ray> rays, const Scene& scene, uint32_t poly, std::span<double> t) {
  // The anchor is the scene's first vertex, the same for every polygon of the
  // scene: two polygons sharing an edge then round it to the same floats, which
  // watertightness needs.
  const uint32_t first = scene.poly_tri_first[poly];
  kernel(rays, t, scene.vertex.empty() ? Vec3{0, 0, 0} : scene.vertex[0], [&](SimdScene& s) {
    for (uint32_t k = first; k < scene.poly_tri_first[poly + 1]; ++k) {
      const auto& v = scene.tri_vertex[k];
      s.add_triangle(scene.vertex[v[0]], scene.vertex[v[1]], scene.vertex[v[2]], scene.poly_plane[poly].n,
                     true, 0, k);
    }
  });
}

void ray_plane(std::span<const Ray> rays, const Plane& plane, std::span<double> t) {
  // Each ray in its own frame (origin at the ray's origin): the plane's offset
  // becomes the origin's signed distance n.o + D, computed in double per ray, so
  // a plane far from the world origin costs no precision.
  const float nf[3] = {float(plane.n.x), float(plane.n.y), float(plane.n.z)};
  for (size_t i = 0; i < rays.size(); i += kPacket) {
    const size_t n = std::min<size_t>(kPacket, rays.size() - i);
    Packet p;
    alignas(32) float dist[kPacket] = {};
    double scale[kPacket];
    p.count = int(n);
    for (size_t k = 0; k < n; ++k) {
      Frame f;
      f.origin = rays[i + k].o;
      load_ray(f, rays[i + k], p, int(k), scale[k]);
      dist[k] = float(plane.d + dot(plane.n, rays[i + k].o));
    }
    clear_tail(p);
    alignas(32) float out[kPacket];
    plane_t(p.dx, p.dy, p.dz, p.tmin, p.tmax, nf, dist, out, kPacket);
    for (size_t k = 0; k < n; ++k) t[i + k] = std::isinf(out[k]) ? kInfinity : double(out[k]) / scale[k];
  }
}

void ray_cone(std::span<const Ray> rays, const Scene& scene, uint32_t cone, std::span<double> t) {
  // World coordinates: the careful form moves each ray's origin near the cone itself.
  const ConeShape c = cone_shape(scene.cone_base[cone], scene.cone_r0[cone], scene.cone_apex[cone],
                                 scene.cone_r1[cone], scene.cone_inside[cone] != 0);
  ConeBatch b(rays.size());
  for (size_t i = 0; i < rays.size(); ++i)
    b.set(i, rays[i].o, rays[i].d, rays[i].tmin, rays[i].tmax);
  cone_t(c, b.rays(), b.t.data(), b.size(), true);
  std::copy_n(b.t.begin(), rays.size(), t.begin());
}

void trace(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, FrameStats* stats) {
  Frame f;
  if (!rays.empty()) f.origin = rays[0].o;
  const SimdScene s = prepare_scene(scene, f, true);
  const Candidates all = all_candidates(s);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, (rays.size() + kPacket - 1) / kPacket, 64),
                    [&](const tbb::blocked_range<size_t>& r) {
                      const size_t lo = r.begin() * kPacket, hi = std::min(rays.size(), r.end() * kPacket);
                      trace_prepared(s, all, rays.subspan(lo, hi - lo), hits.subspan(lo, hi - lo));
                    });
  for (size_t i = 0; i < rays.size(); ++i) refine_hit(scene, rays[i], hits[i]);
  // Cones, in double, in world coordinates (the rays' own).
  if (scene.cone_count() > 0) {
    const std::vector<ConeShape> cones = cone_shapes(scene, [](const Vec3& p) { return p; });
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, rays.size(), 512), [&](const tbb::blocked_range<size_t>& r) {
          ConeBatch b(r.size());
          std::vector<bool> usable(r.size());
          for (size_t i = r.begin(); i < r.end(); ++i) {
            const Ray& ray = rays[i];
            usable[i - r.begin()] =
                is_finite(ray.o) && is_finite(ray.d) && length(ray.d) > 0 && !std::isnan(ray.tmin);
            if (usable[i - r.begin()]) b.set(i - r.begin(), ray.o, ray.d, ray.tmin, 0.0);
          }
          for (uint32_t c = 0; c < cones.size(); ++c) {
            for (size_t i = r.begin(); i < r.end(); ++i)
              if (usable[i - r.begin()]) b.tmax[i - r.begin()] = std::min(rays[i].tmax, hits[i].t);
            cone_t(cones[c], b.rays(), b.t.data(), b.size(), false);
            for (size_t i = r.begin(); i < r.end(); ++i) {
              if (!(b.t[i - r.begin()] < kInfinity)) continue;
              Hit& h = hits[i];
              h.t = b.t[i - r.begin()];
              h.prim = scene.cone_first_prim() + c;
              h.tri = Hit::kNoHit;
            }
          }
        });
  }
  if (stats) {
    stats->items = rays.size();
    for (const auto& [why, n] : s.dropped) stats->drop(why, n);
  }
}

Image render(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  const Camera cam = Camera::from_view(scene.view, opts.width, opts.height);
  // The camera's own frame: eye at the origin, x right, y up, z forward.
  const Frame frame{cam.eye, cam.right, cam.up, cam.forward};
  const SimdScene s = prepare_scene(scene, frame, true);
  const ConeBounds cb = cone_bounds(s);
  const ShadeScene shading = prepare_shading(scene, frame);
  // Cones in the camera frame, where the primary rays are (0, unit), and their
  // bounding spheres for the same per-tile culling as the primitives'.
  const std::vector<ConeShape> cones =
      cone_shapes(scene, [&](const Vec3& q) { return frame.point(q); });
  SimdScene cone_balls;
  cone_balls.frame = frame;
  for (uint32_t c = 0; c < scene.cone_count(); ++c)
    cone_balls.add_sphere(0.5 * (scene.cone_base[c] + scene.cone_apex[c]), cones[c].bound, c);
  const ConeBounds cone_cb = cone_bounds(cone_balls);
  Image image(opts.width, opts.height);
  constexpr int kTileW = 32, kTileH = 8;
  // One tile: the scratch lives on the stack of the thread that runs it.
  auto render_tile = [&](int x0, int y0, int x1, int y1) {
    Packet p;
    PacketHits out;
    ShadePacket sp{};
    Candidates cand;
    cull_tile(s, cb, cam, x0, x1, y0, y1, cand);
    Candidates cone_cand;  // .spheres: the cones the tile's rays may meet
    ConeBatch cb(kPacket);  // tail lanes stay empty (tmin = tmax = 0)
    if (!cones.empty()) cull_tile(cone_balls, cone_cb, cam, x0, x1, y0, y1, cone_cand);
    for (int j = y0; j < y1; ++j) {
      for (int i0 = x0; i0 < x1; i0 += kPacket) {
        p.count = std::min(kPacket, opts.width - i0);
        Vec3 unit[kPacket];
        for (int k = 0; k < p.count; ++k) {
          // Camera-space direction (sx, sy, 1), normalised in double then rounded.
          const Vec3 d = cam.camera_dir(i0 + k, j);
          const double len = length(d);
          unit[k] = d / len;
          p.ox[k] = p.oy[k] = p.oz[k] = 0;
          p.dx[k] = float(unit[k].x), p.dy[k] = float(unit[k].y), p.dz[k] = float(unit[k].z);
          p.tmin[k] = float(cam.hither * len);
          p.tmax[k] = HUGE_VALF;
        }
        clear_tail(p);
        trace_packet(s, cand, p, out);
        Hit hk[kPacket];
        for (int k = 0; k < p.count; ++k) hk[k] = to_hit(s, out.t[k], out.id[k], 1.0);
        if (!cone_cand.spheres.empty()) {
          // The packet's rays against each cone the tile may meet, nearest so far as tmax.
          for (int k = 0; k < p.count; ++k)
            cb.set(size_t(k), Vec3{0, 0, 0}, unit[k], double(p.tmin[k]), 0.0);
          for (const uint32_t c : cone_cand.spheres) {
            for (int k = 0; k < p.count; ++k) cb.tmax[size_t(k)] = hk[k].t;
            cone_t(cones[c], cb.rays(), cb.t.data(), kPacket, false);
            for (int k = 0; k < p.count; ++k)
              if (cb.t[size_t(k)] < kInfinity) {
                hk[k].t = cb.t[size_t(k)];
                hk[k].prim = scene.cone_first_prim() + c;
                hk[k].tri = Hit::kNoHit;
              }
          }
        }
        for (int k = 0; k < p.count; ++k) {
          // The same unit ray in world space (t carries over: both are unit length).
          const Vec3& u = unit[k];
          const Ray ray{cam.eye, u.x * cam.right + u.y * cam.up + u.z * cam.forward, 0.0, kInfinity};
          Hit& h = hk[k];
          refine_far_sphere_hit(scene, ray, h);
          fill_lane(scene, frame, ray, h, sp, k);
        }
        for (int k = p.count; k < kPacket; ++k) sp.hit[k] = 0;
        shade_packet(shading, sp);
        for (int k = 0; k < p.count; ++k) image.set(i0 + k, j, Vec3{sp.r[k], sp.g[k], sp.b[k]});
      }
    }
  };
  parallel_tiles(opts.width, opts.height, kTileW, kTileH, opts.threads, opts.progress, render_tile);
  if (stats) {
    stats->items = uint64_t(opts.width) * uint64_t(opts.height);
    for (const auto& [why, n] : s.dropped) stats->drop(why, n);
  }
  return image;
}

}  // namespace lockstep::opt::simd
