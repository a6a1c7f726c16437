// lockstep optimized: an NFF scene in Embree 3, shared by the Embree rows
// (optimized/ray_cast_embree.cpp, optimized/ray_trace_embree.cpp).
//
// build_scene() makes a device, the geometries and the BVH for a scene moved
// into a local frame (simd::Frame, in double, then rounded to float): spheres
// as RTC_GEOMETRY_TYPE_SPHERE_POINT (far ones, relative to their radius, as a
// user geometry running the stable root form in double), the polygons'
// triangulation as RTC_GEOMETRY_TYPE_TRIANGLE, NFF's sidedness as intersection
// filters, cones as a user geometry (optimized/embree_cones.cpp). What each
// choice is for is said at its definition
// (optimized/embree_scene.cpp); the rows' header comments say how they query.
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/scene.h"
#include "optimized/ray_cone.h"
#include "optimized/simd_scene.h"

namespace lockstep::opt::embree {

using simd::Frame;

inline constexpr int kPacket = 8;
// Fixed geometry ids: a hit's geomID says which array primID indexes.
inline constexpr unsigned kSphereGeom = 0, kTriangleGeom = 1, kFarSphereGeom = 2, kPlainSphereGeom = 3;
// NFF cones: a user geometry (optimized/embree_cones.cpp); primID is the scene's cone index.
inline constexpr unsigned kConeGeom = 4;

// What the device reported; the callback may run on Embree's build threads.
struct ErrorLog {
  std::mutex mutex;
  std::string first;  // empty: nothing reported
};

// An Embree device, shared: copies refer to one RTCDevice, released with the
// last copy. Making one costs about as much as a small scene's BVH (tens of
// ms in a fresh process: Embree's start-up, its ISA dispatch and TBB's
// arena; bench/timing/embree_raw.cpp measures it), so a process keeps one and passes
// it to every build (BuildOptions::device): verify, the property binary and
// the benchmarks through the embree rows' sessions, which take the run's one
// device (registry/embree_device.h), the CLI by rendering once per process.
// Default-constructed: no device (build_scene then makes its own, as before).
struct Device {
  struct State {
    ErrorLog log;
    RTCDevice handle = nullptr;
    ~State() {
      if (handle) rtcReleaseDevice(handle);
    }
  };
  std::shared_ptr<State> state;
  RTCDevice handle = nullptr;

  // A new device; throws std::runtime_error when Embree cannot make one.
  static Device create();

  // Throws if the device has reported anything since the last check (or its
  // creation), and forgets it: one bad build does not poison the next.
  void check(const char* during);
};

// Filter data, reached through the geometry's user pointer.
struct SphereData {
  const float* xyzr = nullptr;  // Embree's own vertex buffer: the centres it intersects with
  std::vector<uint8_t> inside;  // radius < 0: only the inside is visible
  std::vector<uint32_t> index;  // Embree primID -> the scene's sphere index
};
// Far spheres (user geometry): centre in the frame and |radius|, in double.
struct FarSphereData {
  std::vector<Vec3> center;
  std::vector<double> radius;
  std::vector<uint8_t> inside;
  std::vector<uint32_t> index;  // Embree primID -> the scene's sphere index
  bool solid = false;           // BuildOptions::solid_spheres: the first root in range, either side
};
struct TriangleData {
  std::vector<Vec3> normal;        // the polygon's plane normal, in the frame
  std::vector<uint8_t> two_sided;  // the polygon's material transmits: no culling
};
// Cones (user geometry, optimized/embree_cones.cpp): every cone of the scene, in the frame.
struct ConeGeomData {
  std::vector<ConeShape> shape;
  bool solid = false;  // BuildOptions::solid_spheres: either side, as spheres
};

// Everything a query needs. Not movable: the geometries point at the filter data.
// Members are destroyed in reverse order: the scene before the device.
struct EmbreeScene {
  Frame frame;
  Device device;
  SphereData spheres;
  SphereData plain_spheres;  // no filter needed: every ray starts outside, before them
  FarSphereData far_spheres;
  TriangleData triangles;
  ConeGeomData cones;
  RTCScene scene = nullptr;
  // Primitives out of float range (simd::float_triangle_limit and
  // float_sphere_limit), left out of Embree's scene and counted by reason.
  std::map<std::string, uint64_t> dropped;

  ~EmbreeScene() {
    if (scene) rtcReleaseScene(scene);
  }
};

struct BuildOptions {
  // >= 0 when every ray starts at the frame's origin and no earlier than this
  // distance from it (ray casting's primary rays): spheres clearly beyond it
  // need no sidedness filter (see attach_spheres).
  double eye_reach = -1;
  // Spheres are solids (ray tracing, core/ray_trace.h): no sidedness filter, a
  // ray meets the first root in range from inside or outside.
  bool solid_spheres = false;
  // The device to build on (a session's, shared across frames); empty: a new one.
  Device device;
};

// Device, geometry and BVH for the scene in the given frame. Builds in the
// calling thread's task arena (Embree's TBB tasking uses the current arena).
std::unique_ptr<EmbreeScene> build_scene(const Scene& scene, const Frame& frame, const BuildOptions& options = {});
// The cones' user geometry (optimized/embree_cones.cpp); build_scene calls it.
void attach_cones(EmbreeScene& es, const Scene& scene, const BuildOptions& options);

// User geometries (far spheres, cones): count primitives over data, with their
// callbacks, committed and attached to es.scene as geom_id; what names it in an error.
void attach_user_geometry(EmbreeScene& es, unsigned count, void* data, RTCBoundsFunction bounds,
                          RTCIntersectFunctionN intersect, RTCOccludedFunctionN occluded, unsigned geom_id,
                          const char* what);
// A user geometry's hit of lane i at t (float: Embree's), with the normal Embree records.
void record_user_hit(const RTCIntersectFunctionNArguments* args, unsigned i, float t, const Vec3& normal,
                     unsigned geom_id);

// A harmless, inactive ray in every lane: all fields set, as Embree asks.
void clear_packet(RTCRayHit8& rh, int valid[kPacket]);
void set_ray(RTCRayHit8& rh, int valid[kPacket], int k, const Vec3& o, const Vec3& d, double tnear, double tfar);
// The scene's primitive (and triangle) of Embree's geomID / primID into h;
// false for RTC_INVALID_GEOMETRY_ID.
bool prim_of(const EmbreeScene& es, const Scene& scene, unsigned geom, unsigned id, Hit& h);
// The lane's hit: prim numbered spheres first, then polygons; t in the lane's
// ray units (frame t / scale + shift).
Hit to_hit(const EmbreeScene& es, const Scene& scene, const RTCRayHit8& rh, int k, double scale, double shift);

}  // namespace lockstep::opt::embree
