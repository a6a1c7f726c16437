// lockstep props/ray_trace: the checks (see checks.h).
#include "props/ray_trace/checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "core/ray_trace.h"
#include "core/shading.h"
#include "props/gen/case_text.h"
#include "props/gen/numbers.h"
#include "props/ray_trace/oracle.h"
#include "reference/ray_cast.h"
#include "reference/ray_polygon.h"
#include "reference/ray_sphere.h"

namespace lockstep::props::ray_trace {

using gen::hex;

namespace {

// gen_scene's lights may be behind the wall: Hidden moves each light whose
// signed distance along `back` (from the origin, away from the eye) is above
// -0.5 to the eye's side of that plane.
std::string lights_to_eye_side(const std::string& nff) {
  std::istringstream s(nff);
  std::string line, out;
  Vec3 from;
  while (std::getline(s, line)) {
    if (line.rfind("from ", 0) == 0) from = read_v3(line.substr(5));
    if (line.rfind("l ", 0) == 0) {
      Vec3 p = read_v3(line.substr(2));
      const Vec3 back = normalize(-from);
      // Mirror a light behind the plane s = 0 (through the origin, normal back) to the front.
      const double sd = dot(p, back);
      if (sd > -0.5) p = p - (sd + 0.5 + std::abs(sd)) * back;
      line = "l " + v3(p);
    }
    out += line + "\n";
  }
  return out;
}

// ---------------------------------------------------------------- helpers
std::string pixel_text(const Image& im, int x, int y) {
  const float* p = im.pixel(x, y);
  char b[100];
  std::snprintf(b, sizeof b, "(%.6g, %.6g, %.6g)", p[0], p[1], p[2]);
  return b;
}

double pixel_err(const Image& a, const Image& b, int x, int y) {
  double e = 0;
  for (int ch = 0; ch < 3; ++ch) {
    const double d = std::abs(double(a.pixel(x, y)[ch]) - double(b.pixel(x, y)[ch]));
    e = std::isnan(d) ? kInfinity : std::max(e, d);
  }
  return e;
}

Image render(const TracerRun& fn, const TraceCase& c, bool with_hidden = false) {
  FrameOptions o;
  o.width = c.width;
  o.height = c.height;
  o.threads = 1;
  o.params = params_of(c);
  return fn.render(scene_of(c, with_hidden), o, nullptr);
}

RayTree tree_of(const TracerRun& fn, const Scene& scene, const TraceCase& c, int x, int y) {
  RayTree t;
  fn.pixel(scene, trace_settings(params_of(c)), c.width, c.height, x, y, &t);
  return t;
}

std::string node_text(const RayNode& n) {
  char b[300];
  std::snprintf(
      b, sizeof b, "%s depth %d o (%a, %a, %a) d (%a, %a, %a) prim %d t %.17g blocked %d tir %d",
      ray_kind_name(n.kind), n.depth, n.origin.x, n.origin.y, n.origin.z, n.direction.x,
      n.direction.y, n.direction.z, n.hit.hit() ? int(n.hit.prim) : -1, n.hit.t, n.blocked, n.tir);
  return b;
}

}  // namespace

// ---------------------------------------------------------------- checks
Verdict check_laws(const LawCase& c) {
  Verdict v;
  Outcome o;
  o.measured = true;
  std::ostringstream why;
  const V3L d(c.d), n(c.n);
  const LD eta = c.eta;
  // Reflection.
  const Vec3 r = reflect(c.d, c.n);
  const V3L ro = d - LD(2) * dot(d, n) * n;
  double err = std::max(std::abs(double(length(V3L(r)) - 1)), double(length(V3L(r) - ro)));
  if (err > 1e-15)
    why << "reflect (" << hex(r.x) << ", " << hex(r.y) << ", " << hex(r.z) << ") error " << err
        << "; ";
  // Refraction.
  const LD cs = -dot(d, n), k = 1 - eta * eta * (1 - cs * cs);
  Vec3 t;
  const bool ok = refract(c.d, c.n, c.eta, t);
  if (ok != (k >= 0)) {
    if (std::abs(double(k)) > 1e-15)
      why << "TIR decided " << !ok << " but the oracle's k = " << double(k) << "; ";
    else
      o.label = "tir_critical", o.kind = Outcome::explained;
  } else if (ok) {
    const V3L to = eta * d + (eta * cs - std::sqrt(k)) * n;
    // k carries a few roundings of eta^2-sized terms; sqrt(k) passes them on
    // divided by 2 sqrt(k) (its condition near the critical angle).
    const double bound = 1e-14 + 1e-15 * c.eta * c.eta / std::sqrt(double(k) + 1e-300);
    const V3L tl(t);
    const double e_dir = double(length(tl - to)), e_len = std::abs(double(length(tl) - 1));
    const double e_snell = std::abs(double(eta * length(cross(d, n)) - length(cross(tl, n))));
    const double e = std::max({e_dir, e_len, e_snell});
    err = std::max(err, e);
    if (e > bound)
      why << "refract error " << e << " > " << bound << " (direction " << e_dir << ", length "
          << e_len << ", Snell " << e_snell << "); ";
  }
  o.err = err;
  if (!why.str().empty()) {
    o.kind = Outcome::unexplained;
    o.label = "law";
    o.detail = why.str() + "d " + v3(c.d) + " n " + v3(c.n) + " eta " + hex(c.eta);
  }
  v.rays.push_back(o);
  return v;
}

// Slab: the leaving ray (the refract node at depth 3) is parallel to the primary.
Verdict check_slab(const TracerRun& fn, const TraceCase& c) {
  Verdict v;
  Outcome o;
  const Scene scene = scene_of(c);
  const RayTree t = tree_of(fn, scene, c, c.px, c.py);
  const RayNode* out = nullptr;
  for (const RayNode& n : t.nodes)
    if (n.kind == RayKind::kRefract && n.depth == 3) out = &n;
  if (!out || out->tir) {
    o.kind = Outcome::unexplained;
    o.label = "no_exit";
    o.detail = "no refracted ray leaves the slab; tree:";
    for (const RayNode& n : t.nodes) o.detail += "\n  " + node_text(n);
  } else {
    o.err = length(out->direction - t.nodes[0].direction);
    o.measured = true;
    if (!(o.err <= 1e-13)) {
      o.kind = Outcome::unexplained;
      o.label = "not_parallel";
      o.detail = "primary " + node_text(t.nodes[0]) + "\nleaving " + node_text(*out) + "\nerror " +
                 std::to_string(o.err) + " > 1e-13";
    }
  }
  v.rays.push_back(o);
  return v;
}

// TIR: the first refract node's tir flag, the reference's, and the oracle's.
Verdict check_tir(const TracerRun& ref, const TracerRun& fn, const TraceCase& c) {
  Verdict v;
  Outcome o;
  const Scene scene = scene_of(c);
  const RayTree a = tree_of(ref, scene, c, c.px, c.py), b = tree_of(fn, scene, c, c.px, c.py);
  auto tir_of = [](const RayTree& t) {
    for (const RayNode& n : t.nodes)
      if (n.kind == RayKind::kRefract && n.depth == 2) return n.tir ? 1 : 0;
    return -1;  // no refracted ray at all
  };
  // The oracle: the primary ray (identical in both: the camera code is shared)
  // against the true normal at the reference's hit, in long double.
  const RayNode& p = a.nodes[0];
  LD k = 0;
  if (p.hit.hit()) {
    const V3L d(p.direction);
    V3L n;
    if (p.hit.prim < scene.sphere_count()) {
      const V3L q = V3L(p.origin) + LD(p.hit.t) * d - V3L(scene.sphere_center[p.hit.prim]);
      n = q / length(q);
    } else {
      n = V3L(scene.poly_plane[p.hit.prim - scene.sphere_count()].n);
    }
    const LD cs = std::abs(dot(d, n)),
             eta = scene.material_of_prim(p.hit.prim).ior;  // leaving: eta = ior
    k = 1 - eta * eta * (1 - cs * cs);
  }
  const int ta = tir_of(a), tb = tir_of(b), truth = k < 0 ? 1 : 0;
  o.err = double(std::abs(k));
  o.cls = "ray";
  if (ta < 0 || tb < 0 || ta != tb || tb != truth) {
    const bool band = std::abs(double(k)) < 1e-12;
    o.kind = band && ta >= 0 && tb >= 0 ? Outcome::explained : Outcome::unexplained;
    o.label = band ? "tir_critical" : "tir_differs";
    o.detail = "reference tir " + std::to_string(ta) + ", implementation " + std::to_string(tb) +
               ", oracle " + std::to_string(truth) + " (k " + std::to_string(double(k)) +
               ")\nreference " + node_text(a.nodes[0]) + "\nimplementation " +
               node_text(b.nodes[0]);
  }
  v.rays.push_back(o);
  return v;
}

// Weights: <= 1 and <= the parent's, along every path of 8 pixels' trees.
Verdict check_weights(const TracerRun& fn, const TraceCase& c) {
  Verdict v;
  const Scene scene = scene_of(c);
  for (int k = 0; k < 8; ++k) {
    const int x = (k * 5) % c.width, y = (k * 7 + 3) % c.height;
    const RayTree t = tree_of(fn, scene, c, x, y);
    for (const RayNode& n : t.nodes) {
      Outcome o;
      o.err = n.weight;
      o.measured = true;
      const double parent = n.parent < 0 ? 1.0 : t.nodes[size_t(n.parent)].weight;
      if (!(n.weight <= 1 && n.weight <= parent)) {
        o.kind = Outcome::unexplained;
        o.label = "weight";
        o.detail = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): " + node_text(n) +
                   " weight " + std::to_string(n.weight) + ", parent's " + std::to_string(parent);
      }
      v.rays.push_back(o);
    }
  }
  return v;
}

// Hidden: the frames with and without the objects behind the wall are equal.
Verdict check_hidden(const TracerRun& fn, const TraceCase& c0) {
  TraceCase c = c0;
  c.nff = lights_to_eye_side(c.nff);
  const Image a = render(fn, c, false), b = render(fn, c, true);
  Verdict v;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      Outcome o;
      o.err = pixel_err(a, b, x, y);
      o.measured = true;
      if (o.err != 0) {
        o.kind = Outcome::unexplained;
        o.label = "hidden_shows";
        o.detail = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): without " +
                   pixel_text(a, x, y) + ", with the hidden objects " + pixel_text(b, x, y);
      }
      v.rays.push_back(o);
    }
  return v;
}

namespace {

// The reference's nearest hit / shadow decision for one node's own ray, in double.
bool reference_agrees_with(const Scene& scene, const RayNode& n) {
  if (n.kind == RayKind::kShadow) {
    for (uint32_t s = 0; s < scene.sphere_count(); ++s) {
      double t0, t1;
      if (ref::sphere_roots<double>(n.origin, n.direction, scene.sphere_center[s],
                                    scene.sphere_radius[s], t0, t1) &&
          ((t0 > 0 && t0 < n.tmax) || (t1 > 0 && t1 < n.tmax)))
        return n.blocked;
    }
    for (uint32_t p = 0; p < scene.polygon_count(); ++p)
      if (ref::ray_polygon_t(Ray{n.origin, n.direction, 0, n.tmax}, scene, p) < n.tmax)
        return n.blocked;
    return !n.blocked;
  }
  // Nearest: spheres as solids, polygons NFF-sided (core/ray_trace.h).
  return ref::nearest_hit(scene, Ray{n.origin, n.direction}, ref::SphereSides::kSolid).prim ==
         n.hit.prim;
}

// Whether the ray (o, d unit) passes within float's rounding of a sphere's
// silhouette, before tmax: the float sphere test's constant term |o - c|^2 -
// r^2 carries about 2^-24 |o - c|^2 of error, which moves the silhouette by
// that over 2r; four times that is the band.
bool grazes_a_sphere(const Scene& scene, const Vec3& o, const Vec3& d, double tmax) {
  for (uint32_t s = 0; s < scene.sphere_count(); ++s) {
    const Vec3 oc = scene.sphere_center[s] - o;
    const double r = std::abs(scene.sphere_radius[s]), along = dot(oc, d);
    const double dist = length(oc - along * d);
    if (along > 0 && along - r < tmax && std::abs(dist - r) <= 4 * 0x1p-24 * dot(oc, oc) / (2 * r))
      return true;
  }
  return false;
}

// Whether the ray of tree node n meets two surfaces within 1e-6 relative of
// each other before its end (the nearest is then decided by rounding), or
// grazes a sphere within float's rounding.
bool float_tie(const Scene& scene, const RayNode& n) {
  const double tmax = n.kind == RayKind::kShadow ? n.tmax : kInfinity;
  if (grazes_a_sphere(scene, n.origin, n.direction, tmax)) return true;
  std::vector<double> ts;
  for (uint32_t s = 0; s < scene.sphere_count(); ++s) {
    double t0, t1;
    if (ref::sphere_roots<double>(n.origin, n.direction, scene.sphere_center[s],
                                  scene.sphere_radius[s], t0, t1))
      for (double t : {t0, t1})
        if (t > 0 && t < tmax) ts.push_back(t);
  }
  for (uint32_t p = 0; p < scene.polygon_count(); ++p)
    if (const double t = ref::ray_polygon_t(Ray{n.origin, n.direction, 0, tmax}, scene, p);
        t < tmax)
      ts.push_back(t);
  std::sort(ts.begin(), ts.end());
  for (size_t k = 1; k < ts.size(); ++k)
    if (ts[k] - ts[k - 1] <= 1e-6 * ts[k]) return true;
  return false;
}

}  // namespace

// Pixel: the frame's pixel equals the one-pixel computation's colour, bit for bit.
Verdict check_pixel(const TracerRun& fn, const TraceCase& c) {
  const Scene scene = scene_of(c);
  const Image frame = render(fn, c);
  Verdict v;
  for (int k = 0; k < 16; ++k) {
    const int x = (k * 5 + k / 4) % c.width, y = (k * 7 + 3) % c.height;
    RayTree t;
    const Vec3 p = fn.pixel(scene, trace_settings(params_of(c)), c.width, c.height, x, y, &t);
    Outcome o;
    const float* f = frame.pixel(x, y);
    o.err = 0;
    for (int ch = 0; ch < 3; ++ch) {
      const double d = std::abs(double(f[ch]) - double(float(p[ch])));
      o.err = std::isnan(d) ? kInfinity : std::max(o.err, d);
    }
    o.measured = true;
    if (o.err != 0) {
      const bool tie = std::any_of(t.nodes.begin(), t.nodes.end(),
                                   [&](const RayNode& n) { return !n.tir && float_tie(scene, n); });
      o.kind = tie ? Outcome::explained : Outcome::unexplained;
      o.label = tie ? "float_tie" : "pixel_differs";
      o.detail = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): frame " +
                 pixel_text(frame, x, y) + ", one pixel (" + std::to_string(p.x) + ", " +
                 std::to_string(p.y) + ", " + std::to_string(p.z) + ")";
    }
    v.rays.push_back(o);
  }
  return v;
}

// ---------------------------------------------------------------- far
// Far: every shadow ray of 16 pixels' trees answers as the exact segment test
// does, at the point the row shades (its hit moved onto the surface, in long
// double: a sphere radially, a polygon onto its plane), with a margin m =
// 1e-3 s (s the scene's scale) for what rounding may decide. textbook: the
// row's primary sphere test is the textbook quadratic (the reference), whose
// hit seen from 10^4..10^7 radii away can be off by more than the sphere
// (cancellation, ray casting's documented failure): a shadow ray from a
// point further than m from the exact first hit of the pixel's ray on that
// sphere is explained as textbook_hit (a wrong primary hit, not a wrong
// shadow answer); for any other row it is unexplained.
Verdict check_far(const TracerRun& fn, const TraceCase& c, bool textbook) {
  const Scene scene = scene_of(c);
  const TraceSettings settings = trace_settings(params_of(c));
  LD scale = 0;
  for (const double r : scene.sphere_radius) scale = std::max<LD>(scale, std::abs(r));
  const LD m = 1e-3L * scale / 0.8L;  // s >= the largest radius / 0.8
  Verdict v;
  for (int k = 0; k < 16; ++k) {
    const int x = (k * 5 + k / 4) % c.width, y = (k * 7 + 3) % c.height;
    RayTree t;
    fn.pixel(scene, settings, c.width, c.height, x, y, &t);
    for (const RayNode& n : t.nodes) {
      if (n.kind != RayKind::kShadow || n.parent < 0) continue;
      const RayNode& hit = t.nodes[size_t(n.parent)];
      const uint32_t prim = hit.hit.prim;
      const V3L o = to_l(hit.origin), d = to_l(hit.direction);
      V3L p = {o.x + LD(hit.hit.t) * d.x, o.y + LD(hit.hit.t) * d.y, o.z + LD(hit.hit.t) * d.z};
      if (prim < scene.sphere_count()) {
        const V3L cc = to_l(scene.sphere_center[prim]), pc = sub(p, cc);
        const LD r = std::abs(scene.sphere_radius[prim]) / std::sqrt(dotl(pc, pc));
        p = {cc.x + r * pc.x, cc.y + r * pc.y, cc.z + r * pc.z};
      } else {
        const Plane& pl = scene.poly_plane[prim - scene.sphere_count()];
        const V3L nn = to_l(pl.n);
        const LD h = dotl(nn, p) + LD(pl.d);
        p = {p.x - h * nn.x, p.y - h * nn.y, p.z - h * nn.z};
      }
      const std::optional<bool> exact =
          exact_blocked(scene, prim, p, to_l(scene.lights[n.light].position), m);
      // Where the pixel's ray meets that sphere first, exactly.
      bool off_hit = false;
      if (prim < scene.sphere_count() && hit.kind == RayKind::kPrimary) {
        const V3L oc = o - V3L(scene.sphere_center[prim]);
        const LD b = dotl(oc, d) / dotl(d, d), r = std::abs(scene.sphere_radius[prim]);
        const V3L near = oc - b * d;
        const LD disc = r * r - dotl(near, near);
        const LD te = -b - std::sqrt(std::max<LD>(disc, 0) / dotl(d, d));
        const V3L pe = o + te * d;
        off_hit = !(disc >= 0) || length(pe - p) > m;
      }
      Outcome out;
      if (off_hit) {
        out.kind = textbook ? Outcome::explained : Outcome::unexplained;
        out.label = "textbook_hit";
        out.detail = "pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                     "): the row's primary hit on sphere " + std::to_string(prim) + " at t " +
                     hex(hit.hit.t) + " is further than the margin from the exact one";
      } else if (!exact) {
        out.kind = Outcome::skipped;
        out.label = "near_boundary";
      } else if (*exact != n.blocked) {
        out.kind = Outcome::unexplained;
        out.label = n.blocked ? "acne" : "leak";
        out.err = 1;
        out.detail = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "), light " +
                     std::to_string(n.light) + ", hit prim " + std::to_string(prim) + " at t " +
                     hex(hit.hit.t) + ": the row says " + (n.blocked ? "blocked" : "reached") +
                     ", the exact segment test " + (*exact ? "blocked" : "reached") +
                     " (shadow ray from " + v3(n.origin) + ")";
      }
      out.measured = out.kind != Outcome::skipped;
      v.rays.push_back(out);
    }
  }
  return v;
}

namespace {

bool same_decisions(const RayNode& a, const RayNode& b) {
  return a.kind == b.kind && a.hit.prim == b.hit.prim && a.blocked == b.blocked && a.tir == b.tir;
}

// The index of the first node where two trees decide differently, or -1 when
// they decide alike everywhere.
long first_divergence(const RayTree& a, const RayTree& b) {
  const size_t n = std::min(a.nodes.size(), b.nodes.size());
  for (size_t k = 0; k < n; ++k)
    if (!same_decisions(a.nodes[k], b.nodes[k])) return long(k);
  return a.nodes.size() == b.nodes.size() ? -1 : long(n);
}

// Why the trees ra (the reference's) and tb (the implementation's) of one
// pixel diverge: "" when it cannot be said. See the header (Agree).
// Whether light lies within 1e-4 (|n.l|) of the tangent plane at the hit of
// the reference's ray `pa`: n.l > 0 (whether to cast a shadow ray at all) is
// then decided on hit points that differ by rounding.
bool grazing_light(const Scene& scene, const RayNode& pa, uint32_t light) {
  const Vec3 p = pa.origin + pa.hit.t * pa.direction;
  const Vec3 n = surface_normal(scene, pa.hit.prim, pa.hit.tri, p, pa.direction);
  return std::abs(dot(n, light_at(scene, scene.lights[light], p).l)) < 1e-4;
}

std::string classify(const Scene& scene, const RayTree& ra, const RayTree& tb,
                     const std::string& known, std::string& where) {
  const long k = first_divergence(ra, tb);
  if (k < 0) return "same_tree";
  const bool a_ends = size_t(k) >= ra.nodes.size(), b_ends = size_t(k) >= tb.nodes.size();
  if (a_ends || b_ends) {
    // One tree is the other plus rays at its end: a last shadow ray on one side only.
    const RayNode& extra = a_ends ? tb.nodes[size_t(k)] : ra.nodes[size_t(k)];
    where = std::string("\n  only the ") + (a_ends ? "implementation" : "reference") + " has " +
            node_text(extra);
    if (extra.kind != RayKind::kShadow || extra.parent < 0) return "";
    return grazing_light(scene, ra.nodes[size_t(extra.parent)], extra.light) ? known : "";
  }
  const RayNode &na = ra.nodes[size_t(k)], &nb = tb.nodes[size_t(k)];
  where = "\n  reference      " + node_text(na) + "\n  implementation " + node_text(nb);
  if (na.kind == nb.kind && na.tir != nb.tir) {
    // k of Snell's law for a refract node, from its parent ray and the normal at its hit.
    auto snell_k = [&scene](const RayTree& t, const RayNode& n) {
      const RayNode& pa = t.nodes[size_t(n.parent)];
      const Vec3 p = pa.origin + pa.hit.t * pa.direction;
      const Vec3 nn = surface_normal(scene, pa.hit.prim, pa.hit.tri, p, pa.direction);
      const Material& m = scene.material_of_prim(pa.hit.prim);
      const double eta = n.entering ? 1 / m.ior : m.ior, cs = -dot(pa.direction, nn);
      return 1 - eta * eta * (1 - cs * cs);
    };
    if (std::abs(snell_k(ra, na)) < 1e-9) return "tir_critical";
    // Replayed in double on the implementation's own incoming ray: its ray
    // arrived elsewhere (earlier bounces' rounding), and decided right for it.
    return (snell_k(tb, nb) < 0) == nb.tir ? known : "";
  }
  // The same decision, replayed by the reference in double on the
  // implementation's own ray: the ray started elsewhere.
  // Or that ray grazes a sphere within float's rounding of its silhouette
  // (Embree decides hit or miss in float; a sphere it hits there and double
  // misses keeps Embree's t, optimized/refine.h).
  if (na.kind == nb.kind && !nb.tir)
    return reference_agrees_with(scene, nb) || grazes_a_sphere(scene, nb.origin, nb.direction, nb.tmax)
               ? known
               : "";
  // A shadow ray in one tree where the other has the parent's next ray.
  const RayNode* shadow = na.kind == RayKind::kShadow   ? &na
                          : nb.kind == RayKind::kShadow ? &nb
                                                        : nullptr;
  if (!shadow || na.parent != nb.parent || na.parent < 0) return "";
  return grazing_light(scene, ra.nodes[size_t(na.parent)], shadow->light) ? known : "";
}

}  // namespace

Verdict check_agree(const TracerRun& ref, const TracerRun& fn, const std::string& known,
                    const TraceCase& c) {
  const Scene scene = scene_of(c);
  const Image a = render(ref, c), b = render(fn, c);
  TraceSettings robust = trace_settings(params_of(c));
  robust.offset = Offset::kRobust;
  Verdict v;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      Outcome o;
      o.cls = "pixel";
      o.err = pixel_err(a, b, x, y);
      o.measured = true;
      if (o.err > 1.0 / 255) {
        const RayTree tb = tree_of(fn, scene, c, x, y);
        // The reference with the implementation's offset method: the same tree?
        RayTree tr;
        ref.pixel(scene, robust, c.width, c.height, x, y, &tr);
        std::string where, label;
        if (first_divergence(tr, tb) < 0) {
          label = "offset_method";
        } else {
          label = classify(scene, tr, tb, known, where);
          if (label.empty()) label = "differs";
        }
        o.kind = label == known || label == "tir_critical" || label == "offset_method"
                     ? Outcome::explained
                     : Outcome::unexplained;
        o.label = label;
        o.detail =
            "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): reference " +
            pixel_text(a, x, y) + ", implementation " + pixel_text(b, x, y) + ", error " +
            std::to_string(o.err) +
            " > 1/255; first diverging rays (reference with the robust offset, implementation):" +
            where;
      }
      v.rays.push_back(o);
    }
  return v;
}

}  // namespace lockstep::props::ray_trace
