#include "props/ray_cast/checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "core/camera.h"

namespace lockstep::props {

namespace {

constexpr double kF32Eps = 0x1p-24;
constexpr double kF64Eps = 0x1p-53;

template <class Fn>
ImplInfo info_of(const Pair<Fn>& p, size_t i) {
  ImplInfo in;
  in.pair = std::string(p.name);
  in.name = std::string(p.impls[i].name);
  in.bound = p.impls[i].accuracy;
  in.eps = p.impls[i].decide_eps > 0 ? p.impls[i].decide_eps : (in.bound > 1e-9 ? kF32Eps : kF64Eps);
  in.refined = p.impls[i].decide_eps > 0 && in.bound <= 1e-9;
  in.is_reference = i == 0;
  in.agree_t_rel = p.impls[i].agree;
  in.known_failure = std::string(p.impls[i].known.label);
  in.known_max_rate = p.impls[i].known.max_rate;
  in.known_per = std::string(p.impls[i].known.per);
  in.mode = (i == 0 || p.impls[i].name.starts_with(p.impls[0].name)) ? Mode::textbook : Mode::robust;
  return in;
}

template <class F>
auto guarded(F&& f) {
  try {
    return f();
  } catch (const std::logic_error& e) {
    if (std::string(e.what()) == "todo") throw Placeholder("placeholder implementation (std::logic_error(\"todo\"))");
    throw;
  }
}

// One Subject per implementation of a kernel pair; `call` adapts the pair's
// function signature to (case, polygon, out).
template <class Fn, class Call>
void add_kernel_subjects(std::vector<Subject>& out, const Pair<Fn>& pair, Kernel kernel, Call call) {
  for (size_t i = 0; i < pair.impls.size(); ++i) {
    Subject s;
    s.info = info_of(pair, i);
    s.kernel = kernel;
    s.tol = pair.tol;
    const Fn fn = pair.impls[i].fn;
    s.run_kernel = [fn, call](const Case& c, uint32_t poly, std::span<double> t) {
      guarded([&] { call(fn, c, poly, t); return 0; });
    };
    out.push_back(s);
  }
}

std::vector<Subject> build_subjects() {
  std::vector<Subject> out;
  const RayCastRows& t = ray_cast_rows();
  add_kernel_subjects(out, t.ray_sphere, Kernel::sphere,
                      [](RaySphereFn fn, const Case& c, uint32_t, std::span<double> r) { fn(c.rays, c.sphere, r); });
  add_kernel_subjects(out, t.ray_plane, Kernel::plane,
                      [](RayPlaneFn fn, const Case& c, uint32_t, std::span<double> r) { fn(c.rays, c.plane, r); });
  add_kernel_subjects(out, t.ray_polygon, Kernel::polygon, [](RayPolygonFn fn, const Case& c, uint32_t poly,
                                                              std::span<double> r) { fn(c.rays, c.scene, poly, r); });
  for (size_t i = 0; i < t.ray_cast.impls.size(); ++i) {
    Subject s;
    s.info = info_of(t.ray_cast, i);
    s.kernel = Kernel::frame;
    s.tol = t.ray_cast.tol;
    s.trace = t.ray_cast.impls[i].fn.trace;
    s.render = t.ray_cast.impls[i].fn.render;
    out.push_back(s);
  }
  return out;
}

std::string t_text(double t) { return hex(t) + " (" + dec(t) + ")"; }

std::string prim_text(const Hit& h) {
  return h.hit() ? "prim " + std::to_string(h.prim) + " t " + t_text(h.t) : "miss (prim none, t " + hex(h.t) + ")";
}

const Conditioning& view_of(const OracleHit& o, Mode m) { return m == Mode::textbook ? o.textbook : o.local; }
double band_of(const ImplInfo& im) { return (im.mode == Mode::textbook ? kTextbookBand : kRobustBand) * im.eps; }

// The conditioning of t in the frame the implementation computes t in (a hit's
// OracleHit: root >= 0 for spheres). Textbook: world plus its own cancellation.
// Robust kernels: relative to the ray/primitive (local). Traces that refine in
// double: the sphere's stable form works relative to its centre (local), the
// polygon's plane equation n.o + d in world coordinates (world).
const Conditioning& t_view(const OracleHit& o, const ImplInfo& im) {
  if (im.mode == Mode::textbook) return o.textbook;
  if (im.refined && o.root < 0) return o.world;
  return o.local;
}

std::vector<double> run_kernel(const Subject& s, const Case& c, uint32_t poly) {
  std::vector<double> t(c.rays.size(), -12345.0);
  static const bool one_ray = [] {
    const char* e = std::getenv("LOCKSTEP_KERNEL_ONE_RAY");
    return e && *e && *e != '0';
  }();
  if (!one_ray) {
    s.run_kernel(c, poly, t);
    return t;
  }
  // Diagnostic: every ray in a call of its own (no packet neighbours).
  for (size_t i = 0; i < c.rays.size(); ++i) {
    Case one = c;
    one.rays = {c.rays[i]};
    s.run_kernel(one, poly, std::span<double>(&t[i], 1));
  }
  return t;
}

std::vector<Hit> run_trace(const Subject& s, const Case& c) {
  std::vector<Hit> hits(c.rays.size());
  guarded([&] {
    s.trace(c.scene, c.rays, hits, nullptr);
    return 0;
  });
  return hits;
}

OracleHit oracle_kernel(Kernel k, const Case& c, const Ray& r, uint32_t poly) {
  switch (k) {
    case Kernel::sphere: return oracle_sphere(r, c.sphere);
    case Kernel::plane: return oracle_plane(r, c.plane);
    default: return oracle_polygon(r, c.scene, poly);
  }
}

std::string ray_line(const Case& c, size_t i) { return "ray " + std::to_string(i) + ": " + hex(c.rays[i]); }

// Judges one kernel answer against the oracle with the implementation's conditioning view.
Outcome judge(const OracleHit& o, double t, const ImplInfo& im) {
  Outcome out;
  const Conditioning& c = view_of(o, im.mode);
  const double band = band_of(im);
  if (std::isnan(t)) {
    out.kind = Outcome::unexplained;
    out.label = "nan";
    out.err = kInfinity;
    return out;
  }
  const bool hit = t < kInfinity;
  if (hit != o.hit) {
    out.err = kInfinity;
    if (c.margin <= band) {
      out.kind = Outcome::explained;
      out.label = c.margin_why;
    } else {
      out.kind = Outcome::unexplained;
      out.label = hit ? "false_hit" : "false_miss";
    }
    return out;
  }
  if (!hit) return out;
  out.both_hit = true;
  out.err = rel_error(t, o.t);
  if (out.err <= im.bound) return out;
  // A refined implementation keeps its kernel's t where double sees no hit at all
  // (optimized/refine.h): only where that decision is within the band, and then
  // with as many ulps of the decisions' arithmetic as the bound has of double.
  // (Polygons: refine always recomputes t from the plane unless it is parallel.)
  const bool kernel_t = im.refined && o.root >= 0 && c.margin <= band;
  const Conditioning& tr = t_view(o, im);
  const double allowed_refined = im.bound * std::max(1.0, tr.kappa / kWellKappa);
  const double allowed_kernel = im.bound * (im.eps / kF64Eps) * std::max(1.0, o.local.kappa / kWellKappa);
  const bool use_kernel = kernel_t && allowed_kernel > allowed_refined;
  const Conditioning& tc = use_kernel ? o.local : tr;
  const double allowed = use_kernel ? allowed_kernel : allowed_refined;
  const std::string why = c.margin_why;
  if (out.err <= allowed) {
    out.kind = Outcome::explained;
    out.label = tc.kappa_why[0] ? tc.kappa_why : "ill_conditioned";
  } else if (o.root >= 0 && c.margin <= band && (why == "near_tmin" || why == "near_tmax")) {
    // A sphere root within the band of tmin/tmax: the implementation may take the
    // other root. Nothing else excuses a t error: a polygon hit near an edge has
    // one t, and it must be within the bound.
    out.kind = Outcome::explained;
    out.label = c.margin_why;
  } else {
    out.kind = Outcome::unexplained;
    out.label = "t_error";
  }
  return out;
}

Outcome judge_trace(const OracleTrace& o, const Hit& h, const ImplInfo& im) {
  Outcome out;
  const Conditioning& c = view_of(o.best, im.mode);
  const double band = band_of(im);
  if (std::isnan(h.t) || (h.hit() && h.prim >= o.per_prim.size())) {
    out.kind = Outcome::unexplained;
    out.label = std::isnan(h.t) ? "nan" : "bad_prim";
    out.err = kInfinity;
    return out;
  }
  if (h.hit() != o.best.hit) {
    out.err = kInfinity;
    if (c.margin <= band) {
      out.kind = Outcome::explained;
      out.label = c.margin_why;
    } else {
      out.kind = Outcome::unexplained;
      out.label = h.hit() ? "false_hit" : "false_miss";
    }
    return out;
  }
  if (!h.hit()) return out;
  const bool tied = std::find(o.tied.begin(), o.tied.end(), h.prim) != o.tied.end();
  if (!tied) {
    out.err = kInfinity;
    if (c.margin <= band) {
      out.kind = Outcome::explained;
      out.label = c.margin_why;
    } else {
      out.kind = Outcome::unexplained;
      out.label = "wrong_prim";
    }
    return out;
  }
  // t against the oracle's answer for the prim it chose: the same primitive has
  // one t (or, for a sphere root at tmin, two), whatever the other decisions' margins.
  return judge(o.per_prim[h.prim], h.t, im);
}

std::string oracle_trace_text(const OracleTrace& o) {
  std::string s = "oracle: ";
  s += o.best.hit ? "prim " + std::to_string(o.prim) + " " : "";
  s += describe(o.best);
  return s;
}

}  // namespace

// ---------------------------------------------------------------- frames and rates

std::string known_label(const ImplInfo& im) { return "known_" + im.name + "_" + im.known_failure; }

bool well_in_frame(const OracleHit& o, const ImplInfo& im) { return ill_why(o, im).empty(); }

std::string ill_why(const OracleHit& o, const ImplInfo& im) {
  if (im.mode == Mode::textbook) {
    if (well_conditioned(o)) return "";
    return o.world.margin < kWellMargin ? o.world.margin_why : o.world.kappa_why;
  }
  const Conditioning& tc = o.hit ? t_view(o, im) : o.local;
  if (o.local.margin < kWellMargin) return o.local.margin_why[0] ? o.local.margin_why : "margin";
  if (!(tc.kappa <= kWellKappa)) return tc.kappa_why[0] ? tc.kappa_why : "kappa";
  return "";
}

long known_failure_cap(long n, double max_rate) {
  if (n <= 0 || max_rate <= 0) return 0;
  if (max_rate >= 1) return n;
  // Upper tail of Binomial(n, p), summed from the pmf in log space.
  const double p = max_rate, lq = std::log1p(-p), lp = std::log(p);
  auto log_pmf = [&](long k) {
    return std::lgamma(double(n) + 1) - std::lgamma(double(k) + 1) - std::lgamma(double(n - k) + 1) + double(k) * lp +
           double(n - k) * lq;
  };
  // P(X >= k+1) < 1e-6: the smallest such k is the cap.
  double tail = 0;
  std::vector<double> pmf(size_t(n) + 1);
  for (long k = 0; k <= n; ++k) pmf[size_t(k)] = std::exp(log_pmf(k));
  for (long k = n; k >= 0; --k) {
    if (tail + pmf[size_t(k)] >= 1e-6) return k;  // P(X >= k) >= 1e-6, P(X >= k+1) < 1e-6
    tail += pmf[size_t(k)];
  }
  return 0;
}

// ---------------------------------------------------------------- subjects

std::vector<Subject> all_subjects() {
  static const std::vector<Subject> s = build_subjects();
  return s;
}

const Subject* find_subject(const std::string& pair, const std::string& impl) {
  static const std::vector<Subject> s = build_subjects();
  for (const Subject& x : s)
    if (x.info.pair == pair && x.info.name == impl) return &x;
  return nullptr;
}

const Subject& reference_of(const std::string& pair) {
  static const std::vector<Subject> s = build_subjects();
  for (const Subject& x : s)
    if (x.info.pair == pair && x.info.is_reference) return x;
  throw std::runtime_error("no reference for pair " + pair);
}

void probe(const Subject& s) {
  Case c;
  add_sphere(c.scene, {0, 0, -5}, 1, add_material(c.scene, Material{}));
  c.sphere = Sphere{{0, 0, -5}, 1};
  c.plane = Plane{{0, 0, 1}, 5};
  const Vec3 tri[3] = {{-1, -1, -5}, {1, -1, -5}, {0, 1, -5}};
  add_polygon(c.scene, tri, {}, 0);
  c.rays = {Ray{{0, 0, 0}, {0, 0, -1}, 0, kInfinity}};
  if (s.kernel == Kernel::frame) {
    run_trace(s, c);
    FrameOptions opts;
    opts.width = opts.height = 2;
    opts.threads = 1;
    guarded([&] { return s.render(c.scene, opts, nullptr); });
  } else {
    run_kernel(s, c, 0);
  }
}

Case with_ray(const Case& c, size_t i) {
  Case one = c;
  one.rays = {c.rays[i]};
  return one;
}

// ---------------------------------------------------------------- checks

Verdict check_accuracy(const Subject& s, const Case& c) {
  Verdict v;
  const ImplInfo& im = s.info;
  if (s.kernel != Kernel::frame) {
    const auto t = run_kernel(s, c, c.poly);
    for (size_t i = 0; i < c.rays.size(); ++i) {
      const OracleHit o = oracle_kernel(s.kernel, c, c.rays[i], c.poly);
      Outcome out;
      if (!well_in_frame(o, im)) {
        out.kind = Outcome::skipped;
        out.label = "ill:" + ill_why(o, im);
      } else if (std::isnan(t[i]) || (t[i] < kInfinity) != o.hit) {
        out.kind = Outcome::unexplained;
        out.label = std::isnan(t[i]) ? "nan" : (o.hit ? "false_miss" : "false_hit");
        out.err = kInfinity;
      } else if (o.hit) {
        out.both_hit = true;
        out.err = rel_error(t[i], o.t);
        if (!(out.err <= im.bound)) {
          out.kind = Outcome::unexplained;
          out.label = "t_error";
        }
      }
      out.detail = ray_line(c, i) + "; " + im.name + " t " + t_text(t[i]) + "; oracle " + describe(o) +
                   "; rel error " + dec(out.err) + " (bound " + dec(im.bound) + ")";
      v.rays.push_back(out);
    }
    return v;
  }
  const auto hits = run_trace(s, c);
  for (size_t i = 0; i < c.rays.size(); ++i) {
    const OracleTrace o = oracle_trace(c.scene, c.rays[i]);
    Outcome out;
    const Hit& h = hits[i];
    if (!well_in_frame(o.best, im)) {
      out.kind = Outcome::skipped;
      out.label = "ill:" + ill_why(o.best, im);
    } else if (std::isnan(h.t) || h.hit() != o.best.hit) {
      out.kind = Outcome::unexplained;
      out.label = std::isnan(h.t) ? "nan" : (o.best.hit ? "false_miss" : "false_hit");
      out.err = kInfinity;
    } else if (h.hit()) {
      if (std::find(o.tied.begin(), o.tied.end(), h.prim) == o.tied.end()) {
        out.kind = Outcome::unexplained;
        out.label = "wrong_prim";
        out.err = kInfinity;
      } else {
        out.both_hit = true;
        out.err = rel_error(h.t, o.per_prim[h.prim].t);
        if (!(out.err <= im.bound)) {
          out.kind = Outcome::unexplained;
          out.label = "t_error";
        }
      }
    }
    out.detail = ray_line(c, i) + "; " + im.name + " " + prim_text(h) + "; " + oracle_trace_text(o) +
                 "; rel error " + dec(out.err) + " (bound " + dec(im.bound) + ")";
    v.rays.push_back(out);
  }
  return v;
}

Verdict check_agreement(const Subject& s, const Case& c) {
  Verdict v;
  const Subject& ref = reference_of(s.info.pair);
  const double tol = s.info.agree_t_rel > 0 ? s.info.agree_t_rel : s.tol.t_rel;
  auto rel = [](double a, double b) {
    if (std::isinf(a) && std::isinf(b)) return 0.0;
    return std::abs(a - b) / std::abs(b);
  };
  if (s.kernel != Kernel::frame) {
    const auto t = run_kernel(s, c, c.poly);
    const auto tr = run_kernel(ref, c, c.poly);
    for (size_t i = 0; i < c.rays.size(); ++i) {
      const OracleHit o = oracle_kernel(s.kernel, c, c.rays[i], c.poly);
      Outcome out;
      if (!well_in_frame(o, s.info) || !well_in_frame(o, ref.info)) {
        out.kind = Outcome::skipped;
        out.label = "ill";
      } else if (std::isnan(t[i]) || (t[i] < kInfinity) != (tr[i] < kInfinity)) {
        out.kind = Outcome::unexplained;
        out.label = std::isnan(t[i]) ? "nan" : "hit_miss_differs";
        out.err = kInfinity;
      } else if (t[i] < kInfinity) {
        out.both_hit = true;
        out.err = rel(t[i], tr[i]);
        if (!(out.err <= tol)) {
          out.kind = Outcome::unexplained;
          out.label = "t_differs";
        }
      }
      out.detail = ray_line(c, i) + "; " + s.info.name + " t " + t_text(t[i]) + "; " + ref.info.name + " t " +
                   t_text(tr[i]) + "; oracle " + describe(o) + "; rel difference " + dec(out.err) + " (tol " +
                   dec(tol) + ")";
      v.rays.push_back(out);
    }
    return v;
  }
  const auto hits = run_trace(s, c);
  const auto ref_hits = run_trace(ref, c);
  for (size_t i = 0; i < c.rays.size(); ++i) {
    const OracleTrace o = oracle_trace(c.scene, c.rays[i]);
    Outcome out;
    const Hit& h = hits[i];
    const Hit& r = ref_hits[i];
    auto is_tied = [&](uint32_t p) { return std::find(o.tied.begin(), o.tied.end(), p) != o.tied.end(); };
    if (!well_in_frame(o.best, s.info) || !well_in_frame(o.best, ref.info)) {
      out.kind = Outcome::skipped;
      out.label = "ill";
    } else if (std::isnan(h.t) || h.hit() != r.hit()) {
      out.kind = Outcome::unexplained;
      out.label = std::isnan(h.t) ? "nan" : "hit_miss_differs";
      out.err = kInfinity;
    } else if (h.hit()) {
      if (h.prim != r.prim && !(is_tied(h.prim) && is_tied(r.prim))) {
        out.kind = Outcome::unexplained;
        out.label = "prim_differs";
        out.err = kInfinity;
      } else {
        out.both_hit = true;
        out.err = rel(h.t, r.t);
        if (!(out.err <= tol)) {
          out.kind = Outcome::unexplained;
          out.label = "t_differs";
        }
      }
    }
    out.detail = ray_line(c, i) + "; " + s.info.name + " " + prim_text(h) + "; " + ref.info.name + " " +
                 prim_text(r) + "; " + oracle_trace_text(o) + "; rel difference " + dec(out.err) + " (tol " +
                 dec(tol) + ")";
    v.rays.push_back(out);
  }
  return v;
}

Verdict check_stability(const Subject& s, const Case& c) {
  Verdict v;
  if (s.kernel != Kernel::frame) {
    const auto t = run_kernel(s, c, c.poly);
    for (size_t i = 0; i < c.rays.size(); ++i) {
      const OracleHit o = oracle_kernel(s.kernel, c, c.rays[i], c.poly);
      Outcome out = judge(o, t[i], s.info);
      out.detail = ray_line(c, i) + "; " + s.info.name + " t " + t_text(t[i]) + "; oracle " + describe(o) +
                   "; rel error " + dec(out.err) + " (bound " + dec(s.info.bound) + "); " +
                   (out.kind == Outcome::ok ? "ok" : out.label);
      v.rays.push_back(out);
    }
    return v;
  }
  const auto hits = run_trace(s, c);
  for (size_t i = 0; i < c.rays.size(); ++i) {
    const OracleTrace o = oracle_trace(c.scene, c.rays[i]);
    Outcome out = judge_trace(o, hits[i], s.info);
    out.detail = ray_line(c, i) + "; " + s.info.name + " " + prim_text(hits[i]) + "; " + oracle_trace_text(o) +
                 "; rel error " + dec(out.err) + " (bound " + dec(s.info.bound) + "); " +
                 (out.kind == Outcome::ok ? "ok" : out.label);
    v.rays.push_back(out);
  }
  return v;
}

Verdict check_watertight(const Subject& s, const Case& c) {
  Verdict v;
  std::vector<double> t(c.rays.size(), kInfinity);
  std::vector<Hit> hits;
  if (s.kernel == Kernel::frame) {
    hits = run_trace(s, c);
    for (size_t i = 0; i < hits.size(); ++i) t[i] = hits[i].t;
  } else {
    // Kernels have no culling: the nearest hit over every polygon is the first contact.
    for (uint32_t p = 0; p < c.scene.polygon_count(); ++p) {
      const auto tp = run_kernel(s, c, p);
      for (size_t i = 0; i < t.size(); ++i)
        if (std::isnan(tp[i]) || tp[i] < t[i]) t[i] = tp[i];
    }
  }
  for (size_t i = 0; i < c.rays.size(); ++i) {
    const OracleContact o = oracle_contact(c.scene, c.rays[i]);
    Outcome out;
    const bool hit = t[i] < kInfinity;
    std::string touching;
    for (uint32_t p : o.touching) touching += " " + std::to_string(p);
    if (o.contact && o.transversal)
      out.cls = o.touching.size() >= 3 ? "vertex" : (o.touching.size() == 2 ? "edge" : "face");
    if (std::isnan(t[i])) {
      out.kind = Outcome::unexplained;
      out.label = "nan";
    } else if (!o.contact || !o.transversal) {
      out.label = o.contact ? "silhouette" : "no_contact";  // tangent: either answer is right
    } else if (!hit || (t[i] > double(o.t) && rel_error(t[i], o.t) > 1e-3)) {
      // No hit, or a hit clearly beyond the first contact (through the surface to the far side).
      out.err = rel_error(t[i], o.t);
      out.label = o.touching.size() >= 3 ? "leak_vertex" : (o.touching.size() == 2 ? "leak_edge" : "leak_face");
      // The textbook crossings test works on a rounded hit point per polygon, so at a
      // point shared by several polygons it may see it outside all of them.
      out.kind = (s.info.mode == Mode::textbook && o.touching.size() >= 2) ? Outcome::explained : Outcome::unexplained;
      // A library's known failure (pair table, Impl::known_failure) is reported
      // under its own label; any other leak still fails.
      if (out.kind == Outcome::unexplained && !s.info.known_failure.empty() && out.label == s.info.known_failure) {
        out.kind = Outcome::explained;
        out.label = known_label(s.info);
      }
    } else {
      out.both_hit = true;
      out.err = rel_error(t[i], o.t);
      const bool prim_ok = s.kernel != Kernel::frame ||
                           std::find(o.touching.begin(), o.touching.end(), hits[i].prim) != o.touching.end();
      // t within the bound, scaled by the condition number of the worst polygon at
      // the contact (in the frame the implementation computes t in), as in Stability.
      double kappa = 1;
      std::string why = "ill_conditioned";
      for (uint32_t p : o.touching) {
        const OracleHit op = oracle_polygon(c.rays[i], c.scene, p - c.scene.sphere_count());
        const Conditioning& tc = t_view(op, s.info);
        if (tc.kappa > kappa) kappa = tc.kappa, why = tc.kappa_why[0] ? tc.kappa_why : "ill_conditioned";
      }
      const double allowed = s.info.bound * std::max(1.0, kappa / kWellKappa);
      if (!prim_ok) {
        out.kind = Outcome::unexplained;
        out.label = "wrong_prim";
      } else if (!(out.err <= allowed)) {
        out.kind = Outcome::unexplained;
        out.label = "t_error";
      } else if (out.err > s.info.bound) {
        out.kind = Outcome::explained;
        out.label = why;
      }
    }
    out.detail = ray_line(c, i) + "; " + s.info.name + " " +
                 (s.kernel == Kernel::frame ? prim_text(hits[i]) : "min t over polygons " + t_text(t[i])) +
                 "; oracle contact " + (o.contact ? "t " + hex128(o.t) + " (" + dec(double(o.t)) + ")" : "none") +
                 " touching" + touching + (o.transversal ? " transversal" : " not transversal") + "; rel error " +
                 dec(out.err) + "; " + (out.kind == Outcome::ok ? "ok" : out.label);
    v.rays.push_back(out);
  }
  return v;
}

Verdict check_degenerate(const Subject& s, const Case& c) {
  Verdict v;
  if (s.kernel == Kernel::frame) {
    const auto hits = run_trace(s, c);
    for (size_t i = 0; i < c.rays.size(); ++i) {
      const OracleTrace o = oracle_trace(c.scene, c.rays[i]);
      const Hit& h = hits[i];
      Outcome out;
      const bool zero = h.hit() && h.prim >= c.scene.sphere_count() && h.prim < c.scene.prim_count() &&
                        oracle_zero_area(c.scene, h.prim - c.scene.sphere_count());
      if (std::isnan(h.t)) {
        out.kind = Outcome::unexplained;
        out.label = "nan";
      } else if (zero) {
        out.kind = Outcome::unexplained;
        out.label = "hit_zero_area";
      } else {
        out = judge_trace(o, h, s.info);
      }
      out.detail = ray_line(c, i) + "; " + s.info.name + " " + prim_text(h) + "; " + oracle_trace_text(o) +
                   "; " + (out.kind == Outcome::ok ? "ok" : out.label);
      v.rays.push_back(out);
    }
    return v;
  }
  const auto t = run_kernel(s, c, c.poly);
  const bool zero = oracle_zero_area(c.scene, c.poly);
  for (size_t i = 0; i < c.rays.size(); ++i) {
    const OracleHit o = oracle_kernel(Kernel::polygon, c, c.rays[i], c.poly);
    Outcome out;
    if (std::isnan(t[i])) {
      out.kind = Outcome::unexplained;
      out.label = "nan";
    } else if (zero && t[i] < kInfinity) {
      out.kind = Outcome::unexplained;
      out.label = "hit_zero_area";
    } else {
      out = judge(o, t[i], s.info);
    }
    out.detail = ray_line(c, i) + "; " + s.info.name + " t " + t_text(t[i]) + "; oracle " + describe(o) +
                 (zero ? " (zero area)" : "") + "; " + (out.kind == Outcome::ok ? "ok" : out.label);
    v.rays.push_back(out);
  }
  return v;
}

Verdict check_render(const Subject& s, const Case& c) {
  Verdict v;
  const Subject& ref = reference_of(s.info.pair);
  FrameOptions opts;
  opts.width = opts.height = c.render_size;
  opts.threads = 1;
  const Image a = guarded([&] { return s.render(c.scene, opts, nullptr); });
  const Image b = ref.render(c.scene, opts, nullptr);
  const Camera cam = Camera::from_view(c.scene.view, opts.width, opts.height);
  const double band = band_of(s.info);
  std::vector<Outcome> bad;
  size_t total = 0;
  for (int y = 0; y < opts.height; ++y) {
    for (int x = 0; x < opts.width; ++x) {
      ++total;
      const float* pa = a.pixel(x, y);
      const float* pb = b.pixel(x, y);
      double err = 0;
      for (int k = 0; k < 4; ++k) err = std::max(err, std::abs(double(pa[k]) - double(pb[k])));
      if (!(err > s.tol.color_abs)) continue;
      // A pixel whose primary ray sits on a decision boundary (a silhouette, two
      // surfaces at the same depth) may legitimately differ: ask the oracle.
      const Ray ray = cam.primary(x, y);
      const OracleTrace o = oracle_trace(c.scene, ray);
      Outcome out;
      out.err = err;
      out.kind = view_of(o.best, s.info.mode).margin <= band ? Outcome::explained : Outcome::unexplained;
      out.label = out.kind == Outcome::explained ? view_of(o.best, s.info.mode).margin_why : "pixel";
      char buf[256];
      std::snprintf(buf, sizeof buf, "pixel (%d, %d): %s rgba %.9g %.9g %.9g %.9g; %s rgba %.9g %.9g %.9g %.9g; error %.3g (tol %.3g); ",
                    x, y, s.info.name.c_str(), pa[0], pa[1], pa[2], pa[3], ref.info.name.c_str(), pb[0], pb[1], pb[2],
                    pb[3], err, s.tol.color_abs);
      out.detail = buf + ("primary " + hex(ray)) + "; " + oracle_trace_text(o);
      bad.push_back(out);
    }
  }
  // Pixels not explained by the oracle count against the pair's pixel_fraction.
  const size_t allowed = size_t(std::floor((1.0 - s.tol.pixel_fraction) * double(total) + 1e-9));
  size_t unexplained = 0;
  for (const Outcome& o : bad) unexplained += o.kind == Outcome::unexplained;
  for (Outcome& o : bad) {
    if (o.kind == Outcome::unexplained && unexplained <= allowed) {
      o.kind = Outcome::explained;
      o.label = "pixel_fraction";
    }
  }
  Outcome summary;
  summary.label = "image";
  summary.detail = std::to_string(total - bad.size()) + "/" + std::to_string(total) + " pixels within " +
                   dec(s.tol.color_abs) + ", " + std::to_string(unexplained) + " unexplained (allowed " +
                   std::to_string(allowed) + ")";
  v.rays.push_back(summary);
  for (Outcome& o : bad) v.rays.push_back(o);
  return v;
}

Verdict run_check(const std::string& check, const Subject& s, const Case& c) {
  if (check == "accuracy") return check_accuracy(s, c);
  if (check == "agreement") return check_agreement(s, c);
  if (check == "stability") return check_stability(s, c);
  if (check == "watertight") return check_watertight(s, c);
  if (check == "degenerate") return check_degenerate(s, c);
  if (check == "render") return check_render(s, c);
  throw std::runtime_error("unknown check '" + check + "'");
}

}  // namespace lockstep::props
