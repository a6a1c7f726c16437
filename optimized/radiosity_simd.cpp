// lockstep optimized: radiosity (optimized/radiosity_simd.h).
#include "optimized/radiosity_simd.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/error.h"
#include "optimized/tiling.h"
#include "optimized/zbuffer/zbuffer_simd.h"

namespace lockstep::opt::simd {

namespace {

RasterSettings item_buffer_settings() {
  RasterSettings s;
  s.shading = Shading::kFlat;
  s.cull = CullMode::kNone;
  return s;
}

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

}  // namespace

std::vector<double> radiosity_form_factors_rays(const Scene& scene, const PatchMesh& mesh, int k, int threads,
                                                const embree::Device& device,
                                                const std::function<void(double)>& progress) {
  const size_t n = mesh.patches.size();
  std::vector<double> f(n * n, 0.0);
  if (n == 0) return f;
  Occluders occ;
  build(occ, scene, device);
  embree::Device(device).check("radiosity occluders");
  // Every patch's centre and targets once.
  std::vector<Vec3> centre(n);
  std::vector<std::vector<Vec3>> targets(n);
  for (size_t i = 0; i < n; ++i) {
    centre[i] = mesh.patches[i].centre();
    targets[i] = patch_targets(mesh.patches[i], k);
  }
  parallel_tiles(int(n), 1, 4, 1, threads, progress, [&](int x0, int, int x1, int) {
    std::vector<RTCRay> rays;
    std::vector<uint32_t> to;                      // per ray: the polygon it arrives at
    std::vector<std::pair<uint32_t, double>> row;  // (j, unoccluded factor) of the rays in order
    for (int i = x0; i < x1; ++i) {
      rays.clear();
      to.clear();
      row.clear();
      const Vec3 c = centre[size_t(i)];
      const Vec3 o = c - occ.centre;
      for (size_t j = 0; j < n; ++j) {
        const double unoccluded = centre_form_factor(mesh, size_t(i), j);
        if (!(unoccluded > 0)) continue;
        row.emplace_back(uint32_t(j), unoccluded);
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
  return f;
}

std::vector<double> radiosity_form_factors_hemicube(const PatchMesh& mesh, int res, int threads,
                                                    const std::function<void(double)>& progress) {
  const size_t n = mesh.patches.size();
  std::vector<double> f(n * n, 0.0);
  const HemicubeWeights w = hemicube_weights(res);
  const RasterSettings s = item_buffer_settings();
  const Scene shared = patch_scene(mesh, View{});
  const double near = 1e-2 * std::sqrt(mesh.max_area);
  parallel_tiles(int(n), 1, 4, 1, threads, progress, [&](int x0, int, int x1, int) {
    Scene items = shared;  // each task its own view
    Visibility vis;
    for (int i = x0; i < x1; ++i) {
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
  const std::vector<double> f =
      rs.method == FormFactorMethod::rays
          ? radiosity_form_factors_rays(scene, mesh, rs.rays, opts.threads, device, part(0, 0.8))
          : radiosity_form_factors_hemicube(mesh, rs.hemicube, opts.threads, part(0, 0.8));
  SolveResult solved;
  try {
    solved = solve_radiosity(mesh.patches, f, rs.solver, rs.tolerance, rs.max_iterations);
  } catch (const std::invalid_argument& e) {
    throw InputError(scene.source, 0, e.what());
  }
  const Scene items = patch_scene(mesh, scene.view);
  const RasterSettings s = item_buffer_settings();
  const ScreenMesh screen = view_scene(items, opts.width, opts.height, s, opts.threads);
  Visibility vis;
  zbuffer_visibility(screen, s, opts.threads, vis);
  Image image = radiosity_image(items, mesh, vertex_radiosity(mesh, solved.b), screen, vis, scene.background);
  if (stats) {
    stats->items = uint64_t(n) * n;
    stats->counts = {{"patches", n}, {"iterations", uint64_t(solved.iterations)}};
    radiosity_notes(mesh, solved, rs, *stats);
  }
  if (opts.progress) opts.progress(1.0);
  return image;
}

Image radiosity(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  return radiosity_with(scene, opts, stats, embree::Device::create());
}

}  // namespace lockstep::opt::simd
