#include "props/ray_cast/subjects.h"

#include <cmath>
#include <cstdlib>
#include <memory>
#include <span>
#include <stdexcept>

namespace lockstep::props::ray_cast {

namespace {

constexpr double kF32Eps = 0x1p-24;
constexpr double kF64Eps = 0x1p-53;

template <class Fn>
ImplInfo info_of(const KernelRow<Fn>& p, size_t i) {
  ImplInfo in;
  in.pair = std::string(p.name);
  in.name = std::string(p.impls[i].name);
  in.bound = p.impls[i].accuracy;
  in.eps = p.impls[i].decide_eps > 0 ? p.impls[i].decide_eps : (in.bound > 1e-9 ? kF32Eps : kF64Eps);
  in.refined = p.impls[i].decide_eps > 0 && in.bound <= 1e-9;
  in.is_reference = i == 0;
  in.agree_t_rel = p.impls[i].agree;
  in.known = p.impls[i].known;
  in.mode = (i == 0 || p.impls[i].name.starts_with(p.impls[0].name)) ? Mode::textbook : Mode::robust;
  return in;
}

// t of every ray of the case against one primitive; `call` adapts the row's
// signature. LOCKSTEP_KERNEL_ONE_RAY (diagnostic): one ray per call (no packet
// neighbours).
template <class Call>
std::vector<double> kernel_t(const Case& c, Call call) {
  std::vector<double> t(c.rays.size(), -12345.0);
  static const bool one_ray = [] {
    const char* e = std::getenv("LOCKSTEP_KERNEL_ONE_RAY");
    return e && *e && *e != '0';
  }();
  if (!one_ray) {
    call(std::span<const Ray>(c.rays), std::span<double>(t));
    return t;
  }
  for (size_t i = 0; i < c.rays.size(); ++i) call(std::span<const Ray>(&c.rays[i], 1), std::span<double>(&t[i], 1));
  return t;
}

// A kernel's t as a Hit on its one primitive (prim 0).
std::vector<Hit> as_hits(const std::vector<double>& t) {
  std::vector<Hit> h(t.size());
  for (size_t i = 0; i < t.size(); ++i) {
    h[i].t = t[i];
    h[i].prim = t[i] < kInfinity ? 0 : Hit::kNoHit;
  }
  return h;
}

// The oracle's answer for one primitive, as a trace over that primitive alone.
OracleTrace single(const OracleHit& o) {
  OracleTrace tr;
  tr.best = o;
  tr.per_prim = {o};
  if (o.hit) {
    tr.prim = 0;
    tr.tied = {0};
  }
  return tr;
}

template <class Fn>
void add_row(std::vector<Subject>& out, const KernelRow<Fn>& pair, Kernel kernel,
             std::function<void(Fn, const Case&, uint32_t, std::span<const Ray>, std::span<double>)> call,
             std::function<OracleHit(const Case&, const Ray&)> oracle) {
  for (size_t i = 0; i < pair.impls.size(); ++i) {
    Subject s;
    s.info = info_of(pair, i);
    s.kernel = kernel;
    s.tol = pair.tol;
    const Fn fn = pair.impls[i].fn;
    s.answer = [fn, call](const Case& c) {
      return as_hits(kernel_t(c, [&](std::span<const Ray> r, std::span<double> t) { call(fn, c, c.poly, r, t); }));
    };
    s.oracle = [oracle](const Case& c, const Ray& r) { return single(oracle(c, r)); };
    if (kernel == Kernel::polygon) {
      // Kernels have no culling: the nearest hit over every polygon is the first contact.
      s.answer_polygons = [fn, call](const Case& c) {
        std::vector<Hit> best(c.rays.size());
        for (uint32_t p = 0; p < c.scene.polygon_count(); ++p) {
          const auto tp =
              kernel_t(c, [&](std::span<const Ray> r, std::span<double> t) { call(fn, c, p, r, t); });
          for (size_t i = 0; i < best.size(); ++i)
            if (std::isnan(tp[i]) || tp[i] < best[i].t) {
              best[i].t = tp[i];
              best[i].prim = tp[i] < kInfinity ? c.scene.sphere_count() + p : Hit::kNoHit;
            }
        }
        return best;
      };
    }
    out.push_back(s);
  }
}

std::vector<Subject> build_subjects() {
  std::vector<Subject> out;
  const RayCastRows& t = ray_cast_rows();
  add_row<RaySphereFn>(
      out, t.ray_sphere, Kernel::sphere,
      [](RaySphereFn fn, const Case& c, uint32_t, std::span<const Ray> r, std::span<double> o) { fn(r, c.sphere, o); },
      [](const Case& c, const Ray& r) { return oracle_sphere(r, c.sphere); });
  add_row<RayPlaneFn>(
      out, t.ray_plane, Kernel::plane,
      [](RayPlaneFn fn, const Case& c, uint32_t, std::span<const Ray> r, std::span<double> o) { fn(r, c.plane, o); },
      [](const Case& c, const Ray& r) { return oracle_plane(r, c.plane); });
  add_row<RayPolygonFn>(
      out, t.ray_polygon, Kernel::polygon,
      [](RayPolygonFn fn, const Case& c, uint32_t p, std::span<const Ray> r, std::span<double> o) {
        fn(r, c.scene, p, o);
      },
      [](const Case& c, const Ray& r) { return oracle_polygon(r, c.scene, c.poly); });
  add_row<RayConeFn>(
      out, t.ray_cone, Kernel::cone,
      [](RayConeFn fn, const Case& c, uint32_t, std::span<const Ray> r, std::span<double> o) {
        fn(r, c.scene, c.cone, o);
      },
      [](const Case& c, const Ray& r) { return oracle_cone(r, c.scene, c.cone); });
  for (size_t i = 0; i < t.ray_cast.impls.size(); ++i) {
    Subject s;
    s.info = info_of(t.ray_cast, i);
    s.kernel = Kernel::frame;
    s.tol = t.ray_cast.tol;
    const TraceFn trace = t.ray_cast.impls[i].fn.trace;
    s.answer = [trace](const Case& c) {
      std::vector<Hit> hits(c.rays.size());
      trace(c.scene, c.rays, hits, nullptr);
      return hits;
    };
    s.answer_polygons = s.answer;
    s.oracle = [](const Case& c, const Ray& r) { return oracle_trace(c.scene, r); };
    s.render = t.ray_cast.impls[i].fn.render;
    s.session = t.ray_cast.impls[i].fn.session;
    out.push_back(s);
  }
  return out;
}

}  // namespace

const std::vector<Subject>& all_subjects() {
  static const std::vector<Subject> s = build_subjects();
  return s;
}

Subject with_session(const Subject& s, RunResources& resources) {
  if (!s.session) return s;
  Subject out = s;
  const auto run = std::make_shared<const CasterRun>(s.session(resources));
  out.answer = [run](const Case& c) {
    std::vector<Hit> hits(c.rays.size());
    run->trace(c.scene, c.rays, hits, nullptr);
    return hits;
  };
  out.answer_polygons = out.answer;
  out.render = run->render;
  return out;
}

const Subject& reference_of(const std::string& pair) {
  for (const Subject& x : all_subjects())
    if (x.info.pair == pair && x.info.is_reference) return x;
  throw std::runtime_error("no reference for row " + pair);
}

}  // namespace lockstep::props::ray_cast
