// The embree rows against raw Embree (issue #22, "The Embree path, measured
// against raw Embree"). Built by default; bench/run.sh runs it (step embree_raw).
//
//   lockstep_embree_raw [--size N] [--reps R] [--clock wall|cpu] SCENE.nff...
//
// For each scene (the balls scenes: spheres and a ground polygon), one thread,
// N x N (default 1024) primary rays, medians of R (default 7) runs, in turn
// (raw, row, raw, row ...) so that the machine's load falls on both alike:
//   raw: what Embree gives with nothing of lockstep around it: the spheres as
//        RTC_GEOMETRY_TYPE_SPHERE_POINT (float4 centre + radius, moved into the
//        eye's frame), the polygons' triangles as RTC_GEOMETRY_TYPE_TRIANGLE
//        (no sidedness filter), default build quality and scene flags, rtcCommitScene
//        timed alone (build_ms); primary rays in 8-ray packets (rows of 8
//        pixels, RTC_INTERSECT_CONTEXT_FLAG_COHERENT) through rtcIntersect8,
//        and one at a time through rtcIntersect1; no shading: the hit's geomID
//        is summed so that nothing is optimized away;
//   raw robust: the same with RTC_SCENE_FLAG_ROBUST, which the row sets on any
//        scene with triangles (watertight shared edges, a property the row is
//        tested for; optimized/embree_scene.cpp): raw Embree doing the row's job;
//   row: opt::embree::render_unshaded (optimized/ray_cast_embree.h: the ray_cast
//        embree row's own traversal, hits refined as it does, shading off; its
//        BVH build timed inside, FrameStats::build_seconds) and the shaded
//        opt::embree::render, both with one device made before (a session's),
//        and the one-shot cost: a fresh process's first render, device
//        included (first_ms, measured once per scene at the start).
// The figures: Mrays/s = N^2 / (frame time - build time); build_ms; and the
// device's creation alone (device_ms). CSV on stdout; bench/scripts/embree_raw_table.py
// writes bench/results/embree_raw.json.
// --clock cpu times the traces (raw's and the row's frames, the one-shot render)
// by the thread's CPU time instead of the wall clock: on a machine shared with other builds the
// wall clock counts the time the thread waited for a core, which swamps a 10%
// difference. The row's build is still FrameStats' wall-clock figure, so its
// rate is slightly favoured when the machine is loaded; that is below 0.5% of
// the frame on balls-1 and balls-3 (build 0.1-0.4 ms), not on balls-5 (~20 ms).
// The default (wall) is what bench/results/embree_raw.json reports.
#include <embree3/rtcore.h>
#include <tbb/task_arena.h>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "core/camera.h"
#include "io/nff.h"
#include "core/timer.h"
#include "optimized/embree_scene.h"
#include "optimized/ray_cast_embree.h"

using namespace lockstep;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// The traces' clock: the wall clock, or the calling thread's CPU time (--clock cpu).
struct Clock {
  bool cpu = false;
  double now() const {
    if (!cpu) return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
  }
};

struct Raw {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  double build_ms = 0;
  ~Raw() {
    if (scene) rtcReleaseScene(scene);
  }
};

// The spheres in the eye's frame (world minus the eye, in double, then float).
void raw_build(Raw& r, const Scene& s, const Camera& cam, bool robust) {
  if (r.scene) rtcReleaseScene(r.scene);
  r.scene = rtcNewScene(r.device);
  if (robust) rtcSetSceneFlags(r.scene, RTC_SCENE_FLAG_ROBUST);
  RTCGeometry g = rtcNewGeometry(r.device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  const unsigned n = s.sphere_count();
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0,
                                                        RTC_FORMAT_FLOAT4, 4 * sizeof(float), n));
  for (unsigned k = 0; k < n; ++k) {
    const Vec3 c = s.sphere_center[k] - cam.eye;
    v[4 * k + 0] = float(c.x), v[4 * k + 1] = float(c.y), v[4 * k + 2] = float(c.z);
    v[4 * k + 3] = float(std::abs(s.sphere_radius[k]));
  }
  rtcCommitGeometry(g);
  rtcAttachGeometry(r.scene, g);
  rtcReleaseGeometry(g);
  // The polygons' triangles (the balls scenes' ground), as they come: no filter.
  if (const unsigned nt = s.triangle_count()) {
    RTCGeometry t = rtcNewGeometry(r.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* tv = static_cast<float*>(rtcSetNewGeometryBuffer(
        t, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), s.vertex.size()));
    auto* ti = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        t, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nt));
    for (size_t k = 0; k < s.vertex.size(); ++k) {
      const Vec3 p = s.vertex[k] - cam.eye;
      tv[3 * k + 0] = float(p.x), tv[3 * k + 1] = float(p.y), tv[3 * k + 2] = float(p.z);
    }
    for (unsigned k = 0; k < nt; ++k)
      for (int a = 0; a < 3; ++a) ti[3 * k + a] = s.tri_vertex[k][a];
    rtcCommitGeometry(t);
    rtcAttachGeometry(r.scene, t);
    rtcReleaseGeometry(t);
  }
  const Stopwatch w;
  rtcCommitScene(r.scene);
  r.build_ms = 1e3 * w.seconds();
}

// Primary rays through rtcIntersect8 (rows of 8 pixels) or rtcIntersect1; returns ms.
double raw_trace(const Raw& r, const Camera& cam, int size, bool packets, const Clock& clock, uint64_t& sum) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  const double start = clock.now();
  for (int j = 0; j < size; ++j) {
    for (int i0 = 0; i0 < size; i0 += 8) {
      if (packets) {
        alignas(32) int valid[8];
        RTCRayHit8 rh;
        for (int k = 0; k < 8; ++k) {
          const Vec3 d0 = cam.camera_dir(i0 + k, j);
          const Vec3 d = normalize(d0.x * cam.right + d0.y * cam.up + d0.z * cam.forward);
          valid[k] = i0 + k < size ? -1 : 0;
          rh.ray.org_x[k] = rh.ray.org_y[k] = rh.ray.org_z[k] = 0;
          rh.ray.dir_x[k] = float(d.x), rh.ray.dir_y[k] = float(d.y), rh.ray.dir_z[k] = float(d.z);
          rh.ray.tnear[k] = float(cam.hither), rh.ray.tfar[k] = HUGE_VALF;
          rh.ray.time[k] = 0, rh.ray.mask[k] = ~0u, rh.ray.id[k] = 0, rh.ray.flags[k] = 0;
          rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
          rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect8(valid, r.scene, &ctx, &rh);
        for (int k = 0; k < 8; ++k) sum += valid[k] ? rh.hit.geomID[k] + 1 : 0;
      } else {
        for (int k = 0; k < 8 && i0 + k < size; ++k) {
          const Vec3 d0 = cam.camera_dir(i0 + k, j);
          const Vec3 d = normalize(d0.x * cam.right + d0.y * cam.up + d0.z * cam.forward);
          RTCRayHit rh;
          rh.ray.org_x = rh.ray.org_y = rh.ray.org_z = 0;
          rh.ray.dir_x = float(d.x), rh.ray.dir_y = float(d.y), rh.ray.dir_z = float(d.z);
          rh.ray.tnear = float(cam.hither), rh.ray.tfar = HUGE_VALF;
          rh.ray.time = 0, rh.ray.mask = ~0u, rh.ray.id = 0, rh.ray.flags = 0;
          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect1(r.scene, &ctx, &rh);
          sum += rh.hit.geomID + 1;
        }
      }
    }
  }
  return 1e3 * (clock.now() - start);
}

}  // namespace

int main(int argc, char** argv) {
  int size = 1024, reps = 7;
  Clock clock;
  bool bad = false;
  std::vector<std::string> scenes;
  for (int a = 1; a < argc; ++a) {
    if (std::strcmp(argv[a], "--size") == 0 && a + 1 < argc)
      size = std::atoi(argv[++a]);
    else if (std::strcmp(argv[a], "--reps") == 0 && a + 1 < argc)
      reps = std::atoi(argv[++a]);
    else if (std::strcmp(argv[a], "--clock") == 0 && a + 1 < argc) {
      const std::string c = argv[++a];
      clock.cpu = c == "cpu";
      bad |= c != "cpu" && c != "wall";
    } else
      scenes.push_back(argv[a]);
  }
  if (bad || scenes.empty() || size < 8 || reps < 1) {
    std::fprintf(stderr, "usage: lockstep_embree_raw [--size N] [--reps R] [--clock wall|cpu] SCENE.nff...\n");
    return 2;
  }
  tbb::task_arena arena(1);
  int rc = 0;
  arena.execute([&] {
    try {
      std::printf(
          "scene,spheres,size,device_ms,first_ms,raw_build_ms,row_build_ms,raw8_mrays,raw1_mrays,"
          "row_unshaded_mrays,row_shaded_ms,row_shaded_mrays,raw8_robust_mrays\n");
      // The one-shot cost: the first render of the process, its device included.
      std::vector<double> first(scenes.size());
      {
        const Scene s = read_nff(scenes[0]);
        FrameOptions o;
        o.width = o.height = size;
        o.threads = 1;
        const double start = clock.now();
        opt::embree::render(s, o, nullptr);
        first[0] = 1e3 * (clock.now() - start);
      }
      std::vector<double> device_ms;
      for (int r = 0; r < reps; ++r) {
        const Stopwatch w;
        opt::embree::Device d = opt::embree::Device::create();
        device_ms.push_back(1e3 * w.seconds());
      }
      const opt::embree::Device device = opt::embree::Device::create();
      for (size_t si = 0; si < scenes.size(); ++si) {
        const Scene s = read_nff(scenes[si]);
        const Camera cam = Camera::from_view(s.view, size, size);
        FrameOptions o;
        o.width = o.height = size;
        o.threads = 1;
        Raw raw, robust;
        raw.device = robust.device = device.handle;
        std::vector<double> rb, r8, r1, bb, ru, rs, r8r;
        uint64_t sum = 0;
        for (int r = 0; r < reps; ++r) {
          raw_build(raw, s, cam, false);
          rb.push_back(raw.build_ms);
          r8.push_back(raw_trace(raw, cam, size, true, clock, sum));
          r1.push_back(raw_trace(raw, cam, size, false, clock, sum));
          FrameStats st;
          const double start = clock.now();
          opt::embree::render_unshaded(s, o, &st, device);
          const double ms = 1e3 * (clock.now() - start);
          bb.push_back(1e3 * st.build_seconds);
          ru.push_back(ms - 1e3 * st.build_seconds);
          const double shaded_start = clock.now();
          opt::embree::render_with(s, o, &st, device);
          rs.push_back(1e3 * (clock.now() - shaded_start));
          raw_build(robust, s, cam, true);
          r8r.push_back(raw_trace(robust, cam, size, true, clock, sum));
        }
        const double rays = double(size) * size;
        std::printf("%s,%u,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f\n",
                    scenes[si].substr(scenes[si].find_last_of('/') + 1).c_str(), s.sphere_count(),
                    size, median(device_ms), si == 0 ? first[0] : NAN, median(rb), median(bb),
                    rays / median(r8) / 1e3, rays / median(r1) / 1e3, rays / median(ru) / 1e3,
                    median(rs), rays / median(rs) / 1e3, rays / median(r8r) / 1e3);
        std::fflush(stdout);
        if (sum == 42) std::printf("#\n");
      }
    } catch (const std::exception& e) {
      std::fprintf(stderr, "lockstep_embree_raw: %s\n", e.what());
      rc = 2;
    }
  });
  return rc;
}
