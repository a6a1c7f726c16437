// lockstep optimized: radiosity (optimized/radiosity_simd.h).
#include "optimized/radiosity_simd.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>

#include "core/error.h"
#include "core/timer.h"
#include "optimized/radiosity_simd_kernels.h"
#include "optimized/tiling.h"
#include "optimized/zbuffer/zbuffer_simd.h"

namespace lockstep::opt::simd {

namespace {


// The scene's triangles in Embree, moved to be centred on the origin (float
// keeps relative precision near the scene, not near the world origin).
struct Occluders {
  RTCScene scene = nullptr;
  Vec3 centre;
  const uint32_t* tri_poly = nullptr;  // Embree primID -> scene polygon
  ~Occluders() {
    if (scene) rtcReleaseScene(scene);
  }
};

// A query's context: the polygon the rays leave from, and per ray (its id)
// the polygon it arrives at; hits on either are not blockers (as the
// reference's segment_clear).
struct SkipContext {
  RTCIntersectContext base;
  const Occluders* occ = nullptr;
  uint32_t from = 0;
  const uint32_t* to = nullptr;
};

void skip_own_polygons(const RTCFilterFunctionNArguments* args) {
  const auto* ctx = reinterpret_cast<const SkipContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const uint32_t poly = ctx->occ->tri_poly[RTCHitN_primID(args->hit, args->N, i)];
    if (poly == ctx->from || poly == ctx->to[RTCRayN_id(args->ray, args->N, i)]) args->valid[i] = 0;
  }
}

void build(Occluders& o, const Scene& scene, const embree::Device& device) {
  Vec3 lo, hi;
  scene_bounds(scene, lo, hi);
  o.centre = (lo + hi) * 0.5;
  o.scene = rtcNewScene(device.handle);
  RTCGeometry g = rtcNewGeometry(device.handle, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), scene.vertex.size()));
  for (size_t i = 0; i < scene.vertex.size(); ++i) {
    const Vec3 p = scene.vertex[i] - o.centre;
    v[3 * i] = float(p.x), v[3 * i + 1] = float(p.y), v[3 * i + 2] = float(p.z);
  }
  auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                           3 * sizeof(unsigned), scene.tri_vertex.size()));
  for (size_t i = 0; i < scene.tri_vertex.size(); ++i)
    for (int k = 0; k < 3; ++k) t[3 * i + k] = scene.tri_vertex[i][k];
  o.tri_poly = scene.tri_poly.data();
  rtcSetGeometryOccludedFilterFunction(g, skip_own_polygons);
  rtcCommitGeometry(g);
  rtcAttachGeometry(o.scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(o.scene);
}

// An axis-aligned box; overlaps: their interiors meet (boxes that only touch
// hold no segment of one that crosses the other's polygon).
struct Box {
  Vec3 lo{kInfinity, kInfinity, kInfinity}, hi{-kInfinity, -kInfinity, -kInfinity};
  void add(const Vec3& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  bool overlaps(const Box& b) const {
    return lo.x < b.hi.x && b.lo.x < hi.x && lo.y < b.hi.y && b.lo.y < hi.y && lo.z < b.hi.z && b.lo.z < hi.z;
  }
};

// The patches as structure of arrays for lambert_row, padded to 16 lanes.
PatchSoA patch_soa(const PatchMesh& mesh) {
  PatchSoA p;
  p.count = mesh.patches.size();
  p.padded = (p.count + 15) / 16 * 16;
  for (int k = 0; k < 4; ++k) {
    p.x[k].assign(p.padded, 0.0);
    p.y[k].assign(p.padded, 0.0);
    p.z[k].assign(p.padded, 0.0);
  }
  p.nx.assign(p.padded, 0.0);  // padding: a zero normal faces nothing
  p.ny.assign(p.padded, 0.0);
  p.nz.assign(p.padded, 0.0);
  for (size_t j = 0; j < p.count; ++j) {
    const Patch& q = mesh.patches[j];
    for (int k = 0; k < 4; ++k) {
      const Vec3& v = q.v[k < q.count ? k : q.count - 1];
      p.x[k][j] = v.x, p.y[k][j] = v.y, p.z[k][j] = v.z;
    }
    const Vec3 n = q.normal();
    p.nx[j] = n.x, p.ny[j] = n.y, p.nz[j] = n.z;
  }
  return p;
}

}  // namespace

FormFactors radiosity_form_factors_rays(const Scene& scene, const PatchMesh& mesh, int k, int threads,
                                                const embree::Device& device,
                                                const std::function<void(double)>& progress, RayCounts* counts,
                                                FormFactorMethod method) {
  const bool exact = method == FormFactorMethod::exact;
  std::atomic<uint64_t> cast{0}, culled{0};
  const size_t n = mesh.patches.size();
  FormFactors f(n * n);  // each row zeroed by its own task: the first touch spread over the threads
  if (n == 0) return f;
  Occluders occ;
  const Stopwatch building;
  build(occ, scene, device);
  embree::Device(device).check("radiosity occluders");
  if (counts) counts->build_seconds = building.seconds();
  // Every patch's centre and targets once.
  std::vector<Vec3> centre(n);
  std::vector<std::vector<Vec3>> targets(n);
  for (size_t i = 0; i < n; ++i) {
    centre[i] = mesh.patches[i].centre();
    targets[i] = patch_targets(mesh.patches[i], k);
  }
  const PatchSoA soa = patch_soa(mesh);
  // The shaft test's boxes: every scene polygon's, every patch's targets'.
  // Scenes of more than kShaftPolygons polygons skip it (every pair casts).
  constexpr uint32_t kShaftPolygons = 256;
  std::vector<Box> poly_box(scene.polygon_count());
  for (uint32_t p = 0; p < scene.polygon_count(); ++p)
    for (const Vec3& v : scene.polygon_vertices(p)) poly_box[p].add(v);
  std::vector<Box> target_box(n);
  for (size_t j = 0; j < n; ++j)
    for (const Vec3& y : targets[j]) target_box[j].add(y);
  // Whether polygon p lies wholly outside the pyramid from c over patch j
  // (which holds every segment from c to j's targets): beyond j's plane, or
  // beyond a plane through c and one of j's edges. Clearly beyond: by more
  // than 1e-12 of the lengths involved, so rounding never culls a blocker.
  std::vector<Vec3> patch_normal(n);
  for (size_t j = 0; j < n; ++j) patch_normal[j] = mesh.patches[j].normal();
  auto outside_pyramid = [&](const Vec3& c, size_t j, uint32_t p) {
    const Patch& pj = mesh.patches[j];
    const std::span<const Vec3> v = scene.polygon_vertices(p);
    auto all_beyond = [&](const Vec3& origin, const Vec3& m) {
      const double mm = dot(m, m);
      for (const Vec3& q : v) {
        const Vec3 r = q - origin;
        const double h = dot(m, r);
        if (!(h < 0 && h * h > 1e-24 * mm * dot(r, r))) return false;
      }
      return true;
    };
    const Vec3& inside = centre[j];
    if (all_beyond(pj.v[0], patch_normal[j])) return true;  // behind j (c is in front of it)
    for (int e = 0; e < pj.count; ++e) {
      Vec3 m = cross(pj.v[e] - c, pj.v[(e + 1) % pj.count] - c);
      if (dot(m, inside - c) < 0) m = -m;  // pointing into the pyramid
      if (all_beyond(c, m)) return true;
    }
    return false;
  };
  auto may_block = [&](const Vec3& c, Box b, int from, size_t j) {
    if (scene.polygon_count() > kShaftPolygons) return true;
    const int to = mesh.patches[j].polygon;
    b.add(c);
    for (uint32_t p = 0; p < poly_box.size(); ++p)
      if (int(p) != from && int(p) != to && poly_box[p].overlaps(b) && !outside_pyramid(c, j, p))
        return true;
    return false;
  };
  parallel_tiles(int(n), 1, 4, 1, threads, progress, [&](int x0, int, int x1, int) {
    std::vector<double> lambert(soa.padded);
    std::vector<unsigned char> clip(soa.padded);
    std::vector<RTCRay> rays;
    std::vector<uint32_t> to;                      // per ray: the polygon it arrives at
    std::vector<std::pair<uint32_t, double>> row;  // (j, unoccluded factor) of the rays in order
    for (int i = x0; i < x1; ++i) {
      std::fill_n(&f[size_t(i) * n], n, 0.0);
      rays.clear();
      to.clear();
      row.clear();
      const Vec3 c = centre[size_t(i)];
      const Vec3 o = c - occ.centre;
      // Lambert's factors from c to every patch at once; the few patches that
      // reach behind c's tangent plane by the reference's clipping code.
      // (exact: the area-to-area factor, scalar, per pair below).
      if (!exact) lambert_row(soa, c, mesh.patches[size_t(i)].normal(), lambert.data(), clip.data());
      const int from = mesh.patches[size_t(i)].polygon;
      uint64_t spared = 0;
      for (size_t j = 0; j < n; ++j) {
        const double unoccluded = exact     ? exact_form_factor(mesh, size_t(i), j)
                                  : clip[j] ? centre_form_factor(mesh, size_t(i), j)
                                            : lambert[j];
        if (!(unoccluded > 0)) continue;
        // Shaft culling (Haines and Wallace 1994): no polygon but the two
        // patches' own both overlaps the box of c and j's targets and reaches
        // into the pyramid from c over j, so no segment between them can be
        // blocked: every ray arrives.
        if (may_block(c, target_box[j], from, j)) {
          row.emplace_back(uint32_t(j), unoccluded);
        } else {
          f[size_t(i) * n + j] = unoccluded;
          ++spared;
          continue;
        }
        for (const Vec3& y : targets[j]) {
          const Vec3 d = y - c;
          RTCRay r{};
          r.org_x = float(o.x), r.org_y = float(o.y), r.org_z = float(o.z);
          r.dir_x = float(d.x), r.dir_y = float(d.y), r.dir_z = float(d.z);
          r.tnear = float(kSegmentMargin);
          r.tfar = float(1 - kSegmentMargin);
          r.mask = 0xffffffffu;
          r.flags = 0;
          r.id = unsigned(rays.size());
          rays.push_back(r);
          to.push_back(uint32_t(mesh.patches[j].polygon));
        }
      }
      if (!rays.empty()) {
        SkipContext context;
        rtcInitIntersectContext(&context.base);
        context.occ = &occ;
        context.from = uint32_t(mesh.patches[size_t(i)].polygon);
        context.to = to.data();
        rtcOccluded1M(occ.scene, &context.base, rays.data(), unsigned(rays.size()), sizeof(RTCRay));
      }
      cast += rays.size();
      culled += spared;
      // Blocked rays come back with tfar = -inf.
      size_t r = 0;
      for (const auto& [j, unoccluded] : row) {
        const size_t m = targets[j].size();
        int arrived = 0;
        for (size_t q = 0; q < m; ++q, ++r) arrived += rays[r].tfar >= 0 ? 1 : 0;
        f[size_t(i) * n + j] = unoccluded * arrived / double(m);
      }
    }
  });
  if (counts) {
    counts->rays = cast;
    counts->culled_pairs = culled;
  }
  return f;
}

FormFactors radiosity_form_factors_hemicube(const PatchMesh& mesh, int res, int threads,
                                                    const std::function<void(double)>& progress) {
  const size_t n = mesh.patches.size();
  FormFactors f(n * n);  // each row zeroed by its own task: the first touch spread over the threads
  const HemicubeWeights w = hemicube_weights(res);
  const RasterSettings s = radiosity_item_buffer();
  const Scene shared = patch_scene(mesh, View{});
  const double near = hemicube_near(mesh);
  parallel_tiles(int(n), 1, 4, 1, threads, progress, [&](int x0, int, int x1, int) {
    Scene items = shared;  // each task its own view
    Visibility vis;
    for (int i = x0; i < x1; ++i) {
      std::fill_n(&f[size_t(i) * n], n, 0.0);
      const Patch& from = mesh.patches[size_t(i)];
      const Vec3 c = from.centre(), normal = from.normal();
      for (int face = 0; face < 5; ++face) {
        items.view = hemicube_view(c, normal, face, res, near, hemicube_turn(size_t(i)));
        const ScreenMesh screen = view_scene(items, res, res, s, 1);
        zbuffer_visibility(screen, s, 1, vis);
        add_hemicube_face(mesh, items, screen, vis, w, size_t(i), face, &f[size_t(i) * n]);
      }
    }
  });
  return f;
}

Image radiosity_with(const Scene& scene, const FrameOptions& opts, FrameStats* stats, const embree::Device& device) {
  const RadiositySettings rs = radiosity_settings(opts.params, scene.source);
  const PatchMesh mesh = mesh_scene(scene, rs.patch_area);
  const size_t n = mesh.patches.size();
  auto part = [&](double lo, double hi) -> std::function<void(double)> {
    if (!opts.progress) return {};
    return [&opts, lo, hi](double x) { opts.progress(lo + (hi - lo) * x); };
  };
  RayCounts counts;
  const FormFactors f =
      rs.method == FormFactorMethod::hemicube
          ? radiosity_form_factors_hemicube(mesh, rs.hemicube, opts.threads, part(0, 0.8))
          : radiosity_form_factors_rays(scene, mesh, rs.rays, opts.threads, device, part(0, 0.8), &counts, rs.method);
  const SolveResult solved = solve_patches(mesh, f, rs, scene.source);
  const Scene items = patch_scene(mesh, scene.view);
  const RasterSettings s = radiosity_item_buffer();
  const ScreenMesh screen = view_scene(items, opts.width, opts.height, s, opts.threads);
  Visibility vis;
  zbuffer_visibility(screen, s, opts.threads, vis);
  const std::vector<Vec3> vertex_b = vertex_radiosity(mesh, solved.b);
  Image image = radiosity_image(items, mesh, vertex_b, screen, vis, scene.background);
  radiosity_sides(mesh, solved.b, vertex_b, opts, stats);
  if (stats) {
    stats->items = uint64_t(n) * n;
    stats->build_seconds = counts.build_seconds;  // the Embree BVH (rays, exact)
    stats->counts = {{"patches", n}, {"iterations", uint64_t(solved.iterations)}};
    if (rs.method != FormFactorMethod::hemicube)
      stats->counts.insert(stats->counts.end(), {{"rays", counts.rays}, {"shaft_culled_pairs", counts.culled_pairs}});
    radiosity_notes(mesh, solved, rs, *stats);
  }
  if (opts.progress) opts.progress(1.0);
  return image;
}

Image radiosity(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  return radiosity_with(scene, opts, stats, embree::Device::create());
}

}  // namespace lockstep::opt::simd
