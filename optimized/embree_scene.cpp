// lockstep optimized: an NFF scene in Embree 3 (see optimized/embree_scene.h).
//
// The set-up follows Embree's tutorials/minimal/minimal.cpp: a device with an
// error callback, one scene, geometries filled through rtcSetNewGeometryBuffer,
// rtcCommitScene. A scene with triangles is RTC_SCENE_FLAG_ROBUST (no
// traversal shortcuts that may miss an edge).
//
// Where Embree and NFF disagree, and what we do about it:
//  * Sidedness. Embree reports every surface from both sides; NFF sees spheres
//    only from outside (inside for r < 0) and polygons only from their front
//    unless they transmit (core/shading.h visible_side). An intersection filter
//    per geometry (rtcSetGeometryIntersectFilterFunction) rejects hits on the
//    invisible side, so traversal carries on behind them. It uses our own data
//    (sphere centres, the polygons' plane normals), not Embree's Ng, whose
//    orientation convention for triangles is the opposite winding rule. For a
//    sphere Embree offers the entering hit first and, if the filter rejects it,
//    the leaving one: that is what makes r < 0 (far wall only) come out right.
//    Occlusion queries (rtcOccluded) run no intersection filter: they see
//    every surface from both sides, which is what shadow rays want.
//  * Precision. Embree works in float. The scene is moved into a local frame in
//    double first (the rows choose it: the camera's, or the first ray's origin)
//    so that a scene far from the world origin loses nothing.
#include "optimized/embree_scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "optimized/refine.h"

namespace lockstep::opt::embree {

namespace {

// Spheres further from the frame's origin (the eye) than kFarRatio radii go
// into a user geometry that runs the stable form of Ray Tracing Gems ch. 7 in
// double; all others stay RTC_GEOMETRY_TYPE_SPHERE_POINT. The ratio was 256,
// on the assumption that Embree's float test is the textbook quadratic (C =
// |o - c|^2 - r^2 losing eps * ratio^2 of r^2). Measured with Embree 3.13.5
// (issue #22): with every sphere built in, whatever its distance, every embree
// test passes -- Stability far_small_spheres (distance / radius log-uniform in
// 10 .. 1e6), far_translated, the corpus cases far-sphere (1e8 radii, exact
// disk) and far-sphere-translated, Agreement, Render, the ray-tracing
// properties. At 256 the user geometry took nearly all of balls-4 and balls-5
// (6561 of 7381, 65610 of 66430 spheres): a BVH build 1.8x raw Embree's on
// balls-5 and slower traversal (bench/timing/embree_raw.cpp). So the double path is
// kept only beyond what the properties cover.
constexpr double kFarRatio = 1e6;

const char* error_name(RTCError e) {
  switch (e) {
    case RTC_ERROR_NONE:
      return "no error";
    case RTC_ERROR_UNKNOWN:
      return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION:
      return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "unsupported CPU";
    case RTC_ERROR_CANCELLED:
      return "cancelled";
  }
  return "error";
}


void on_error(void* user, RTCError code, const char* what) {
  auto& log = *static_cast<ErrorLog*>(user);
  std::lock_guard<std::mutex> lock(log.mutex);
  if (log.first.empty())
    log.first = std::string(error_name(code)) + (what ? std::string(": ") + what : "");
}


// A geometry being set up; released once attached (the scene keeps its own reference).
struct Geometry {
  RTCGeometry handle;
  Geometry(RTCDevice d, RTCGeometryType type) : handle(rtcNewGeometry(d, type)) {}
  ~Geometry() {
    if (handle) rtcReleaseGeometry(handle);
  }
  Geometry(const Geometry&) = delete;
  Geometry& operator=(const Geometry&) = delete;
};

}  // namespace

Device Device::create() {
  Device d;
  d.state = std::make_shared<State>();
  // No "threads=N" config: with TBB tasking Embree would turn it into a
  // process-wide tbb::global_control. Builds run in the caller's task arena.
  d.state->handle = rtcNewDevice(nullptr);
  if (!d.state->handle)
    throw std::runtime_error(std::string("embree: cannot create device: ") + error_name(rtcGetDeviceError(nullptr)));
  rtcSetDeviceErrorFunction(d.state->handle, on_error, &d.state->log);
  d.handle = d.state->handle;
  // LOCKSTEP_EMBREE_DEVICES=1: one line per device made, so that a test can
  // count them (tests/CMakeLists.txt: verify and the property binary make
  // one per process, shared by both embree rows, not one per row or frame).
  if (const char* e = std::getenv("LOCKSTEP_EMBREE_DEVICES"); e && e[0] == '1')
    std::fprintf(stderr, "lockstep: new Embree device\n");
  return d;
}

void Device::check(const char* during) {
  if (!state) return;
  std::lock_guard<std::mutex> lock(state->log.mutex);
  if (!state->log.first.empty()) {
    const std::string what = std::move(state->log.first);
    state->log.first.clear();
    throw std::runtime_error(std::string("embree: ") + during + ": " + what);
  }
}

namespace {


// Spheres: keep the hit when its side is the visible one. With P = o + t d,
// d.(P - c) < 0 where the ray enters and > 0 where it leaves. It is evaluated in
// double from the very floats Embree intersected with (its centre, the ray), so
// only a ray grazing the sphere to within float rounding can be misjudged, and
// there the two roots coincide anyway.
void sphere_filter(const RTCFilterFunctionNArguments* args) {
  const auto& data = *static_cast<const SphereData*>(args->geometryUserPtr);
  const unsigned n = args->N;
  for (unsigned i = 0; i < n; ++i) {
    if (!args->valid[i]) continue;
    const unsigned prim = RTCHitN_primID(args->hit, n, i);
    const float* c = data.xyzr + 4 * size_t(prim);
    const double t = RTCRayN_tfar(args->ray, n, i);  // the candidate hit's distance
    const double dx = RTCRayN_dir_x(args->ray, n, i), dy = RTCRayN_dir_y(args->ray, n, i),
                 dz = RTCRayN_dir_z(args->ray, n, i);
    const double px = double(RTCRayN_org_x(args->ray, n, i)) - c[0] + t * dx;
    const double py = double(RTCRayN_org_y(args->ray, n, i)) - c[1] + t * dy;
    const double pz = double(RTCRayN_org_z(args->ray, n, i)) - c[2] + t * dz;
    const double s = dx * px + dy * py + dz * pz;
    const bool visible = data.inside[prim] ? s > 0 : s < 0;
    if (!visible) args->valid[i] = 0;
  }
}

// Far spheres: bounds for the BVH, padded by a few float ulps of the centre's
// magnitude so that rounding the box to float cannot cut the sphere.
void far_sphere_bounds(const RTCBoundsFunctionArguments* args) {
  const auto& data = *static_cast<const FarSphereData*>(args->geometryUserPtr);
  const Vec3& c = data.center[args->primID];
  const double r = data.radius[args->primID];
  const double pad = r + 4e-7 * (std::abs(c.x) + std::abs(c.y) + std::abs(c.z)) + 1e-30;
  RTCBounds* b = args->bounds_o;
  b->lower_x = float(c.x - pad), b->lower_y = float(c.y - pad), b->lower_z = float(c.z - pad);
  b->upper_x = float(c.x + pad), b->upper_y = float(c.y + pad), b->upper_z = float(c.z + pad);
}

// Far spheres: the stable roots in double, from the float ray Embree traces;
// the visible root is the entering one (the leaving one for r < 0), as the
// sphere filter decides for the built-in spheres. False when it is not in the
// ray's (tnear, tfar); else t in float and the hit point relative to the centre.
bool far_sphere_hit(const FarSphereData& data, unsigned prim, RTCRayN* ray, unsigned n, unsigned i, float& tf,
                    Vec3& p) {
  const Vec3 o{RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i), RTCRayN_org_z(ray, n, i)};
  const Vec3 d{RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i), RTCRayN_dir_z(ray, n, i)};
  double t0, t1;
  if (!stable_sphere_roots(o, d, data.center[prim], data.radius[prim], t0, t1)) return false;
  // Solid: the first root in range; else the visible one (entering, or leaving for r < 0).
  const double t = data.solid ? (float(t0) > RTCRayN_tnear(ray, n, i) ? t0 : t1) : data.inside[prim] ? t1 : t0;
  tf = float(t);
  p = o + t * d - data.center[prim];
  return tf > RTCRayN_tnear(ray, n, i) && tf < RTCRayN_tfar(ray, n, i);
}

void far_sphere_intersect(const RTCIntersectFunctionNArguments* args) {
  const auto& data = *static_cast<const FarSphereData*>(args->geometryUserPtr);
  const unsigned n = args->N, prim = args->primID;
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, n);
  for (unsigned i = 0; i < n; ++i) {
    float tf;
    Vec3 p;
    if (args->valid[i] && far_sphere_hit(data, prim, ray, n, i, tf, p)) record_user_hit(args, i, tf, p, kFarSphereGeom);
  }
}

// Occlusion (ray tracing's shadow rays): the same root as an intersection.
void far_sphere_occluded(const RTCOccludedFunctionNArguments* args) {
  const auto& data = *static_cast<const FarSphereData*>(args->geometryUserPtr);
  const unsigned n = args->N, prim = args->primID;
  for (unsigned i = 0; i < n; ++i) {
    float tf;
    Vec3 p;
    if (args->valid[i] && far_sphere_hit(data, prim, args->ray, n, i, tf, p))
      RTCRayN_tfar(args->ray, n, i) = -HUGE_VALF;  // Embree's "occluded"
  }
}

// Triangles: one-sided ones are seen only by rays against the plane normal.
void triangle_filter(const RTCFilterFunctionNArguments* args) {
  const auto& data = *static_cast<const TriangleData*>(args->geometryUserPtr);
  const unsigned n = args->N;
  for (unsigned i = 0; i < n; ++i) {
    if (!args->valid[i]) continue;
    const unsigned prim = RTCHitN_primID(args->hit, n, i);
    if (data.two_sided[prim]) continue;
    const Vec3& nn = data.normal[prim];
    const double s = RTCRayN_dir_x(args->ray, n, i) * nn.x + RTCRayN_dir_y(args->ray, n, i) * nn.y +
                     RTCRayN_dir_z(args->ray, n, i) * nn.z;
    if (!(s < 0)) args->valid[i] = 0;
  }
}


// Built-in spheres, one geometry. With a filter, the invisible side is skipped;
// without, Embree's first root is taken as it comes.
void attach_point_spheres(EmbreeScene& es, const Scene& scene, const std::vector<uint32_t>& ids,
                          SphereData& data, unsigned geom_id, bool filter) {
  if (ids.empty()) return;  // Embree rejects empty buffers
  const auto n = uint32_t(ids.size());
  Geometry g(es.device.handle, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g.handle, RTC_BUFFER_TYPE_VERTEX, 0,
                                                        RTC_FORMAT_FLOAT4, 4 * sizeof(float), n));
  es.device.check("sphere buffer");
  data.inside.resize(n);
  data.index = ids;
  for (uint32_t k = 0; k < n; ++k) {
    const Vec3 c = es.frame.point(scene.sphere_center[ids[k]]);  // in double, then rounded
    const double r = scene.sphere_radius[ids[k]];
    v[4 * k + 0] = float(c.x);
    v[4 * k + 1] = float(c.y);
    v[4 * k + 2] = float(c.z);
    v[4 * k + 3] = float(std::abs(r));
    data.inside[k] = r < 0;
  }
  data.xyzr = v;
  rtcSetGeometryUserData(g.handle, &data);
  if (filter) rtcSetGeometryIntersectFilterFunction(g.handle, sphere_filter);
  rtcCommitGeometry(g.handle);
  rtcAttachGeometryByID(es.scene, g.handle, geom_id);
  es.device.check("spheres");
}

// eye_reach >= 0 when every ray starts at the frame's origin and no earlier than
// eye_reach from it (render: the hither distance along the longest primary ray).
// A sphere with r > 0 whose surface is clearly beyond that reach is then entered
// by every ray that meets it, so Embree's first root is always the visible one
// and the sphere needs no filter callback (balls-4: about 1.4x faster).
// Solid spheres (options.solid_spheres) need no filter either.
void attach_spheres(EmbreeScene& es, const Scene& scene, const BuildOptions& options) {
  const double eye_reach = options.eye_reach;
  es.far_spheres.solid = options.solid_spheres;
  // Split: far spheres for the stable user geometry; near ones for Embree's own
  // test, with or without the sidedness filter.
  std::vector<uint32_t> filtered, plain;
  for (uint32_t i = 0; i < scene.sphere_count(); ++i) {
    const Vec3 c = es.frame.point(scene.sphere_center[i]);
    const double r = std::abs(scene.sphere_radius[i]);
    if (const std::string why = simd::float_sphere_limit(c, r); !why.empty()) {
      ++es.dropped[why];  // its float bounds (or Embree's own test) would overflow or vanish
      continue;
    }
    if (length(c) > kFarRatio * r) {
      es.far_spheres.center.push_back(c);
      es.far_spheres.radius.push_back(r);
      es.far_spheres.inside.push_back(scene.sphere_radius[i] < 0);
      es.far_spheres.index.push_back(i);
    } else if (options.solid_spheres ||
               (eye_reach >= 0 && scene.sphere_radius[i] > 0 && length(c) - r > 2 * eye_reach + 1e-4 * r)) {
      plain.push_back(i);
    } else {
      filtered.push_back(i);
    }
  }
  attach_point_spheres(es, scene, filtered, es.spheres, kSphereGeom, true);
  attach_point_spheres(es, scene, plain, es.plain_spheres, kPlainSphereGeom, false);
  if (!es.far_spheres.index.empty())
    attach_user_geometry(es, unsigned(es.far_spheres.index.size()), &es.far_spheres, far_sphere_bounds,
                         far_sphere_intersect, far_sphere_occluded, kFarSphereGeom, "far spheres");
}

void attach_triangles(EmbreeScene& es, const Scene& scene, const BuildOptions& options) {
  const uint32_t n = scene.triangle_count();
  if (n == 0) return;
  Geometry g(es.device.handle, RTC_GEOMETRY_TYPE_TRIANGLE);
  const size_t nv = scene.vertex.size();
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g.handle, RTC_BUFFER_TYPE_VERTEX, 0,
                                                        RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      g.handle, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
  es.device.check("triangle buffers");
  for (size_t i = 0; i < nv; ++i) {
    const Vec3 p = es.frame.point(scene.vertex[i]);
    v[3 * i + 0] = float(p.x);
    v[3 * i + 1] = float(p.y);
    v[3 * i + 2] = float(p.z);
  }
  es.triangles.normal.resize(n);
  es.triangles.two_sided.resize(n);
  // When every ray starts at the frame's origin (eye_reach >= 0: ray casting's
  // primary rays), a plane's visible side is the same for all of them: the
  // side the origin is on. If the origin is clearly in front of every one-sided
  // triangle, no hit can be on a back face and the filter is not needed (the
  // balls scenes' ground: about 1.3x on balls-1, bench/timing/embree_raw.cpp).
  bool filter = options.eye_reach < 0;
  for (uint32_t k = 0; k < n; ++k) {
    for (int a = 0; a < 3; ++a) idx[3 * k + a] = scene.tri_vertex[k][a];
    const auto& t = scene.tri_vertex[k];
    if (const std::string why = simd::float_triangle_limit(es.frame.point(scene.vertex[t[0]]),
                                                           es.frame.point(scene.vertex[t[1]]),
                                                           es.frame.point(scene.vertex[t[2]]));
        !why.empty()) {
      ++es.dropped[why];
      for (int a = 0; a < 3; ++a) idx[3 * k + a] = t[0];  // zero area: Embree never reports it
    }
    const uint32_t poly = scene.tri_poly[k];
    es.triangles.normal[k] = es.frame.dir(scene.poly_plane[poly].n);
    es.triangles.two_sided[k] = scene.materials[scene.poly_material[poly]].two_sided();
    if (!filter && !es.triangles.two_sided[k]) {
      const Vec3 v0 = es.frame.point(scene.vertex[scene.tri_vertex[k][0]]);
      const double front = -dot(es.triangles.normal[k], v0);  // the origin's signed distance
      filter = !(front > 1e-6 * (length(v0) + options.eye_reach));
    }
  }
  rtcSetGeometryUserData(g.handle, &es.triangles);
  if (filter) rtcSetGeometryIntersectFilterFunction(g.handle, triangle_filter);
  rtcCommitGeometry(g.handle);
  rtcAttachGeometryByID(es.scene, g.handle, kTriangleGeom);
  es.device.check("triangles");
}

}  // namespace

void attach_user_geometry(EmbreeScene& es, unsigned count, void* data, RTCBoundsFunction bounds,
                          RTCIntersectFunctionN intersect, RTCOccludedFunctionN occluded, unsigned geom_id,
                          const char* what) {
  Geometry g(es.device.handle, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(g.handle, count);
  rtcSetGeometryUserData(g.handle, data);
  rtcSetGeometryBoundsFunction(g.handle, bounds, nullptr);
  rtcSetGeometryIntersectFunction(g.handle, intersect);
  rtcSetGeometryOccludedFunction(g.handle, occluded);
  rtcCommitGeometry(g.handle);
  rtcAttachGeometryByID(es.scene, g.handle, geom_id);
  es.device.check(what);
}

void record_user_hit(const RTCIntersectFunctionNArguments* args, unsigned i, float t, const Vec3& normal,
                     unsigned geom_id) {
  const unsigned n = args->N;
  RTCRayN_tfar(RTCRayHitN_RayN(args->rayhit, n), n, i) = t;
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, n);
  RTCHitN_Ng_x(hit, n, i) = float(normal.x);
  RTCHitN_Ng_y(hit, n, i) = float(normal.y);
  RTCHitN_Ng_z(hit, n, i) = float(normal.z);
  RTCHitN_u(hit, n, i) = 0;
  RTCHitN_v(hit, n, i) = 0;
  RTCHitN_primID(hit, n, i) = args->primID;
  RTCHitN_geomID(hit, n, i) = geom_id;
  RTCHitN_instID(hit, n, i, 0) = args->context->instID[0];
}

std::unique_ptr<EmbreeScene> build_scene(const Scene& scene, const Frame& frame, const BuildOptions& options) {
  auto es = std::make_unique<EmbreeScene>();
  es->frame = frame;
  es->device = options.device.handle ? options.device : Device::create();
  es->scene = rtcNewScene(es->device.handle);
  es->device.check("rtcNewScene");
  if (!es->scene) throw std::runtime_error("embree: cannot create scene");
  // Robust traversal (no shortcuts that may miss a shared edge) matters for
  // triangle meshes' watertightness; spheres-only scenes go without it, as raw
  // Embree does by default (bench/timing/embree_raw.cpp).
  if (scene.triangle_count() > 0) rtcSetSceneFlags(es->scene, RTC_SCENE_FLAG_ROBUST);
  attach_spheres(*es, scene, options);
  attach_triangles(*es, scene, options);
  attach_cones(*es, scene, options);
  if (const uint64_t n = range_lost_polygons(scene)) es->dropped[kNormalLostToRange] += n;
  rtcCommitScene(es->scene);  // an empty scene is fine: every ray misses
  es->device.check("rtcCommitScene");
  return es;
}

void clear_packet(RTCRayHit8& rh, int valid[kPacket]) {
  for (int k = 0; k < kPacket; ++k) {
    valid[k] = 0;
    rh.ray.org_x[k] = rh.ray.org_y[k] = rh.ray.org_z[k] = 0;
    rh.ray.dir_x[k] = rh.ray.dir_y[k] = 0;
    rh.ray.dir_z[k] = 1;
    rh.ray.tnear[k] = 0;
    rh.ray.tfar[k] = 0;
    rh.ray.time[k] = 0;
    rh.ray.mask[k] = 0xffffffffu;
    rh.ray.id[k] = unsigned(k);
    rh.ray.flags[k] = 0;
    rh.hit.Ng_x[k] = rh.hit.Ng_y[k] = rh.hit.Ng_z[k] = 0;
    rh.hit.u[k] = rh.hit.v[k] = 0;
    rh.hit.primID[k] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    for (int l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; ++l)
      rh.hit.instID[l][k] = RTC_INVALID_GEOMETRY_ID;
  }
}

void set_ray(RTCRayHit8& rh, int valid[kPacket], int k, const Vec3& o, const Vec3& d, double tnear,
             double tfar) {
  valid[k] = -1;
  rh.ray.org_x[k] = float(o.x), rh.ray.org_y[k] = float(o.y), rh.ray.org_z[k] = float(o.z);
  rh.ray.dir_x[k] = float(d.x), rh.ray.dir_y[k] = float(d.y), rh.ray.dir_z[k] = float(d.z);
  rh.ray.tnear[k] = float(tnear);
  rh.ray.tfar[k] = tfar < 3e38 ? float(tfar) : HUGE_VALF;
}

bool prim_of(const EmbreeScene& es, const Scene& scene, unsigned geom, unsigned id, Hit& h) {
  if (geom == RTC_INVALID_GEOMETRY_ID) return false;
  if (geom == kSphereGeom) {
    h.prim = es.spheres.index[id];
  } else if (geom == kPlainSphereGeom) {
    h.prim = es.plain_spheres.index[id];
  } else if (geom == kFarSphereGeom) {
    h.prim = es.far_spheres.index[id];
  } else if (geom == kConeGeom) {
    h.prim = scene.cone_first_prim() + id;
  } else {
    h.prim = scene.sphere_count() + scene.tri_poly[id];
    h.tri = id;
  }
  return true;
}

Hit to_hit(const EmbreeScene& es, const Scene& scene, const RTCRayHit8& rh, int k, double scale, double shift) {
  Hit h;
  if (!prim_of(es, scene, rh.hit.geomID[k], rh.hit.primID[k], h)) return h;
  h.t = double(rh.ray.tfar[k]) / scale + shift;
  return h;
}

}  // namespace lockstep::opt::embree
