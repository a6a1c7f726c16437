// lockstep core: the ray-tracing family's settings (core/ray_trace.h), read
// from Params (CLI `--depth 3 --robust`, corpus `depth=3 robust=1`).
#include "core/ray_trace.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "core/error.h"
#include "core/shading.h"

namespace lockstep {

namespace {

double number_in(const std::string& source, const std::string& name, const std::string& value,
                 double lo, double hi) {
  char* end = nullptr;
  const double x = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(x) || x < lo || x > hi)
    throw InputError(source, 0,
                     name + ": '" + value + "' is not a number in [" + std::to_string(lo) + ", " +
                         std::to_string(hi) + "]");
  return x;
}

}  // namespace

std::vector<ParamSpec> trace_params() {
  return {
      {"depth", "N in 1..32", "5", "ray-tree depth: 1 = primary rays and their shadow rays only"},
      {"shadows", "rays|none", "rays",
       "rays: a shadow ray per light at every hit; none: every light reaches"},
      {"eps", "E in (0, 1]", "",
       "fixed self-intersection offset along the normal, world units (default: the reference 1e-6, "
       "embree robust)"},
      {"robust", "", "",
       "Waechter-Binder integer-ulp offset (Ray Tracing Gems ch. 6) in every implementation, in "
       "the ulps of its own arithmetic (reference: double; embree: float)", true},
      {"cutoff", "W in [0, 1]", "0.00390625",
       "rays whose accumulated weight is below W are not traced"},
  };
}

TraceSettings trace_settings(const Params& params, const std::string& source) {
  TraceSettings s;
  bool eps = false, robust = false;
  for (const auto& [name, value] : params.items) {
    if (name == "depth") {
      s.max_depth = int(number_in(source, name, value, 1, 32));
      if (s.max_depth != number_in(source, name, value, 1, 32))
        throw InputError(source, 0, "depth: '" + value + "' is not a whole number");
    } else if (name == "shadows") {
      if (value != "rays" && value != "none")
        throw InputError(source, 0, "shadows: '" + value + "' is not one of rays|none");
      s.shadows = value == "rays";
    } else if (name == "eps") {
      s.eps = number_in(source, name, value, 0, 1);
      if (!(s.eps > 0)) throw InputError(source, 0, "eps: must be above 0");
      eps = true;
    } else if (name == "robust") {
      if (value != "0" && value != "1")
        throw InputError(source, 0, "robust: '" + value + "' is not one of 0|1");
      robust = value == "1";
    } else if (name == "cutoff") {
      s.cutoff = number_in(source, name, value, 0, 1);
    } else {
      throw InputError(
          source, 0,
          "'" + name + "' is not a ray-tracing setting (depth, shadows, eps, robust, cutoff)");
    }
  }
  if (eps && robust) throw InputError(source, 0, "give eps or robust, not both");
  s.offset = eps ? Offset::kFixed : robust ? Offset::kRobust : Offset::kOwn;
  return s;
}

Vec3 outward_normal(const Scene& scene, uint32_t prim, const Vec3& p) {
  if (prim < scene.sphere_count()) return normalize(p - scene.sphere_center[prim]);
  if (prim >= scene.cone_first_prim()) return cone_outward_normal(scene, prim - scene.cone_first_prim(), p);
  return scene.poly_plane[prim - scene.sphere_count()].n;
}

SurfacePoint surface_point(const Scene& scene, uint32_t prim, const Ray& ray, double t) {
  constexpr double kUnit = 0x1p-53;
  const Vec3 p = ray.o + t * ray.d;
  if (prim < scene.sphere_count()) {
    // Radially onto the sphere: c + |r| (p - c) / |p - c|, good to a few
    // ulps of |c| and r (the division and the sum round once each).
    const Vec3& c = scene.sphere_center[prim];
    const double r = std::abs(scene.sphere_radius[prim]);
    const Vec3 v = p - c;
    const double len = length(v);
    if (!(len > 0) || !std::isfinite(len)) return {p, kUnit * (max_abs_component(p) + r)};
    return {c + (r / len) * v, 8 * kUnit * (max_abs_component(c) + r)};
  }
  if (prim >= scene.cone_first_prim())
    return {p, 32 * kUnit * (max_abs_component(ray.o) + std::abs(t) * max_abs_component(ray.d))};
  // Along the plane's unit normal onto n.x + d = 0 (the plane every row's
  // polygon test uses): good to a few ulps of |p| and |d|.
  const Plane& pl = scene.poly_plane[prim - scene.sphere_count()];
  const Vec3 q = p - (dot(pl.n, p) + pl.d) * pl.n;
  return {q, 8 * kUnit * (max_abs_component(q) + std::abs(pl.d))};
}

double prim_magnitude(const Scene& scene, uint32_t prim, const Vec3& frame_origin) {
  if (prim < scene.sphere_count())
    return max_abs_component(scene.sphere_center[prim] - frame_origin) +
           std::abs(scene.sphere_radius[prim]);
  if (prim >= scene.cone_first_prim()) {
    const uint32_t c = prim - scene.cone_first_prim();
    return std::max(max_abs_component(scene.cone_base[c] - frame_origin),
                    max_abs_component(scene.cone_apex[c] - frame_origin)) +
           std::max(std::abs(scene.cone_r0[c]), std::abs(scene.cone_r1[c]));
  }
  const uint32_t poly = prim - scene.sphere_count();
  // The plane offset in this frame: |d + n.origin|.
  double m = std::abs(scene.poly_plane[poly].d + dot(scene.poly_plane[poly].n, frame_origin));
  for (uint32_t v = scene.poly_first[poly]; v < scene.poly_first[poly + 1]; ++v)
    m = std::max(m, max_abs_component(scene.vertex[v] - frame_origin));
  return m;
}

const char* ray_kind_name(RayKind k) {
  switch (k) {
    case RayKind::kPrimary:
      return "primary";
    case RayKind::kShadow:
      return "shadow";
    case RayKind::kReflect:
      return "reflect";
    case RayKind::kRefract:
      return "refract";
  }
  return "?";
}

}  // namespace lockstep
