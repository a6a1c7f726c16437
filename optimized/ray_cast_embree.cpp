// Ray casting with Intel Embree 3: a BVH built over the scene, packets of 8 rays.
//
// The scene, its geometries, NFF's sidedness filters and the device are
// optimized/embree_scene.h's (shared with ray tracing); queries set every
// RTCRayHit field.
// Primary rays go through rtcIntersect8 in 8-pixel runs of 32 x 8 screen tiles
// spread over the cores by opt::parallel_tiles (optimized/tiling.h), the tiling
// ray_cast_simd.cpp uses.
//
// Where Embree and NFF disagree, and what we do about it:
//  * Sidedness: NFF's, by intersection filters (optimized/embree_scene.cpp).
//  * Precision. Embree works in float. The scene is first moved into a local
//    frame in double (the camera's, or the first ray's origin; simd::Frame) so
//    that a scene far from the world origin loses nothing, and the winning hit's
//    t is recomputed in double afterwards (optimized/refine.h).
//  * Ray ranges. Embree wants 0 <= tnear <= tfar; rays with tmin < 0 start from
//    o + tmin d instead; rays it cannot represent (non-finite values, d = 0,
//    tmin = -inf) miss.
//
// Shading is the one ray_cast_simd.cpp uses (optimized/shade_simd.h), so the
// two optimized renders differ only in how they find the hit.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/camera.h"
#include "optimized/embree_scene.h"
#include "optimized/ray_cast_embree.h"
#include "core/shading.h"
#include "core/timer.h"
#include "optimized/refine.h"
#include "optimized/shade_simd.h"
#include "optimized/simd_scene.h"
#include "optimized/tiling.h"
#include "optimized/ray_cast_simd.h"

namespace lockstep::opt::embree {

namespace {

// Ray i of trace() in the frame: unit direction, range rescaled by scale = |d|.
// Returns false for a ray Embree cannot take (it then misses).
bool load_ray(const Frame& f, const Ray& r, RTCRayHit8& rh, int valid[kPacket], int k,
              double& scale, double& shift) {
  const Vec3 d = f.dir(r.d);
  const double len = length(d);
  if (!(len > 0) || !std::isfinite(len) || !is_finite(r.o) || std::isnan(r.tmin) ||
      std::isnan(r.tmax) || !(r.tmin < r.tmax) || r.tmin == kInfinity || r.tmin == -kInfinity)
    return false;
  // Embree wants tnear >= 0: a range reaching behind the origin starts from o + tmin d.
  shift = r.tmin < 0 ? r.tmin : 0.0;
  const Vec3 o = f.point(r.o + shift * r.d);
  if (!is_finite(o)) return false;
  scale = len;
  set_ray(rh, valid, k, o, d / len, (r.tmin - shift) * len, (r.tmax - shift) * len);
  return true;
}

}  // namespace

// ---------------------------------------------------------------- the contract
namespace {

void trace_on(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, FrameStats* stats,
              const Device& device) {
  const Stopwatch build_timer;
  if (rays.empty()) {  // nothing to build a BVH for
    if (stats) {
      stats->build_seconds = 0;
      stats->items = 0;
    }
    return;
  }
  Frame frame;
  frame.origin = rays[0].o;  // rays from one viewpoint keep "camera-relative" precision
  if (!is_finite(frame.origin)) frame.origin = Vec3{0, 0, 0};
  const auto es = build_scene(scene, frame, {.device = device});
  const double build = build_timer.seconds();
  const size_t packets = (rays.size() + kPacket - 1) / kPacket;
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, packets, 64), [&](const tbb::blocked_range<size_t>& range) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);  // incoherent: arbitrary rays
        RTCRayHit8 rh;
        alignas(32) int valid[kPacket];  // rtcIntersect8 wants it 32-byte aligned, like the packet
        double scale[kPacket], shift[kPacket];
        for (size_t p = range.begin(); p < range.end(); ++p) {
          const size_t i0 = p * kPacket, n = std::min<size_t>(kPacket, rays.size() - i0);
          clear_packet(rh, valid);
          bool any = false;
          for (size_t k = 0; k < n; ++k)
            any |= load_ray(frame, rays[i0 + k], rh, valid, int(k), scale[k], shift[k]);
          if (any) rtcIntersect8(valid, es->scene, &context, &rh);
          for (size_t k = 0; k < n; ++k) {
            Hit h = valid[k] ? to_hit(*es, scene, rh, int(k), scale[k], shift[k]) : Hit{};
            refine_hit(scene, rays[i0 + k], h);
            hits[i0 + k] = h;
          }
        }
      });
  es->device.check("rtcIntersect8");
  if (stats) {
    stats->build_seconds = build;
    stats->items = rays.size();
    for (const auto& [why, n] : es->dropped) stats->drop(why, n);
  }
}

}  // namespace

void trace(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, FrameStats* stats) {
  trace_on(scene, rays, hits, stats, Device());
}

void trace_with(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, FrameStats* stats,
                const Device& device) {
  trace_on(scene, rays, hits, stats, device);
}

namespace {

// The frame; shade = false: the hits only (bench/timing/embree_raw.cpp compares that
// with raw Embree), each pixel's refined t written as its grey level.
Image render_frame(const Scene& scene, const FrameOptions& opts, FrameStats* stats, const Device& device,
                   bool shade) {
  const Camera cam = Camera::from_view(scene.view, opts.width, opts.height);
  // The camera's own frame: eye at the origin, x right, y up, z forward, so a
  // primary ray is (sx, sy, 1) normalised, with its small components exact.
  const Frame frame{cam.eye, cam.right, cam.up, cam.forward};

  const Stopwatch build_timer;
  std::unique_ptr<EmbreeScene> es;
  // Primary rays start at the eye, at hither along the view axis: at most
  // hither * |camera_dir| from it (longest at the image corners).
  double reach = 0;
  for (const auto& [i, j] : {std::pair{0, 0}, {opts.width - 1, 0}, {0, opts.height - 1}, {opts.width - 1, opts.height - 1}})
    reach = std::max(reach, cam.hither * length(cam.camera_dir(i, j)));
  // The BVH build honours opts.threads too: Embree's TBB tasking builds in the
  // calling thread's arena.
  tbb::task_arena(resolve_threads(opts.threads)).execute([&] {
    es = build_scene(scene, frame, {.eye_reach = reach, .device = device});
  });
  const double build = build_timer.seconds();

  const ShadeScene shading = prepare_shading(scene, frame);
  // Every pixel is written below (tiles cover the frame; each row of a tile is
  // whole packets, the last one cut at the image edge): no 16 MB clear first.
  Image image = Image::uninitialized(opts.width, opts.height);
  constexpr int kTileW = 32, kTileH = 8;
  // One tile: the scratch lives on the stack of the thread that runs it.
  //
  // The per-ray work outside Embree is kept small (bench/timing/embree_raw.cpp measures
  // the row against raw Embree): the packet's constant fields are set once per
  // tile, the eight directions are computed side by side (the same double
  // operations, in the same order, as camera_dir / length / divide, so the same
  // bits), and the world-space ray is made only for a lane that needs it (a
  // far sphere's refinement, shading).
  auto render_tile = [&](int x0, int y0, int x1, int y1) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags =
        RTC_INTERSECT_CONTEXT_FLAG_COHERENT;  // neighbouring pixels: one origin, close directions
    RTCRayHit8 rh;
    alignas(32) int valid[kPacket];  // rtcIntersect8 wants it 32-byte aligned, like the packet
    // Origin, time, mask, id, flags: the same for every packet, and Embree only
    // reads them. What it writes (tfar, the hit) is reset per packet below.
    clear_packet(rh, valid);
    ShadePacket sp{};
    const double cx = 0.5 * (cam.width - 1), pitch = cam.pitch;
    for (int j = y0; j < y1; ++j) {
      const double sy = cam.sy(j), sy2 = sy * sy;
      for (int i0 = x0; i0 < x1; i0 += kPacket) {
        const int count = std::min(kPacket, opts.width - i0);
        // Camera-space direction (sx, sy, 1), normalised in double then rounded;
        // the hither plane is a distance along the view axis.
        alignas(32) double ux[kPacket], uy[kPacket], uz[kPacket], len[kPacket];
        for (int k = 0; k < kPacket; ++k) {  // locals only: GCC vectorises it (sqrt and / stay exact)
          const double sx = (double(i0 + k) - cx) * pitch;  // cam.sx(i0 + k)
          len[k] = std::sqrt(sx * sx + sy2 + 1.0 * 1.0);     // length(camera_dir(i0 + k, j))
          ux[k] = sx / len[k];
          uy[k] = sy / len[k];
          uz[k] = 1.0 / len[k];
        }
        for (int k = 0; k < kPacket; ++k) {
          valid[k] = k < count ? -1 : 0;
          rh.ray.dir_x[k] = float(ux[k]), rh.ray.dir_y[k] = float(uy[k]), rh.ray.dir_z[k] = float(uz[k]);
          rh.ray.tnear[k] = float(cam.hither * len[k]);
          rh.ray.tfar[k] = HUGE_VALF;  // set_ray's tfar for kInfinity
          rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
          for (int l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; ++l) rh.hit.instID[l][k] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect8(valid, es->scene, &context, &rh);
        for (int k = 0; k < count; ++k) {
          // The same unit ray in world space (t carries over: both are unit length).
          auto world_ray = [&] {
            return Ray{cam.eye, ux[k] * cam.right + uy[k] * cam.up + uz[k] * cam.forward, 0.0, kInfinity};
          };
          Hit h = to_hit(*es, scene, rh, k, 1.0, 0.0);
          if (!shade) {
            if (needs_far_sphere_refinement(scene, h)) refine_hit(scene, world_ray(), h);
            const double g = h.hit() ? h.t : 0.0;
            image.set(i0 + k, j, Vec3{g, g, g});
            continue;
          }
          const Ray ray = world_ray();
          refine_far_sphere_hit(scene, ray, h);
          fill_lane(scene, frame, ray, h, sp, k);
        }
        if (!shade) continue;
        for (int k = count; k < kPacket; ++k) sp.hit[k] = 0;
        shade_packet(shading, sp);
        for (int k = 0; k < count; ++k) image.set(i0 + k, j, Vec3{sp.r[k], sp.g[k], sp.b[k]});
      }
    }
  };
  parallel_tiles(opts.width, opts.height, kTileW, kTileH, opts.threads, opts.progress, render_tile);
  es->device.check("rtcIntersect8");
  if (stats) {
    stats->build_seconds = build;
    stats->items = uint64_t(opts.width) * uint64_t(opts.height);
    for (const auto& [why, n] : es->dropped) stats->drop(why, n);
  }
  return image;
}

}  // namespace

Image render(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  return render_frame(scene, opts, stats, Device(), true);
}

Image render_with(const Scene& scene, const FrameOptions& opts, FrameStats* stats, const Device& device) {
  return render_frame(scene, opts, stats, device, true);
}

Image render_unshaded(const Scene& scene, const FrameOptions& opts, FrameStats* stats, const Device& device) {
  return render_frame(scene, opts, stats, device, false);
}

}  // namespace lockstep::opt::embree
