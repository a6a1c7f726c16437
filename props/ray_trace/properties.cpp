// lockstep props/ray_trace: the ray-tracing family's properties (core/ray_trace.h).
//
// Cases are small NFF scenes written by the generators with every number as a
// hex float, so a counterexample file (header, then `nff`, then the scene)
// replays bit for bit. The typed row of registry/ray_trace_row.h gives each
// implementation's frame and its one-pixel ray tree (TracePixelFn).
//
//   Laws.ray_trace__reference       (part "laws") reflect() and refract() of
//       core/ray_trace.h, the laws both implementations use, against an
//       oracle in long double from the same double inputs: unit length, the
//       mirror direction, Snell's law (eta |d x n| = |t x n|) and the TIR
//       decision (k = 1 - eta^2 (1 - (d.n)^2) < 0). Directions are drawn
//       anywhere and densely within 1e-12..1e-3 (relative) of the critical
//       angle; a TIR decision that differs from the oracle's is explained only
//       when |k| is below 1e-15 (k's own rounding), and the direction bound
//       1e-14 grows by 1e-15 eta^2 / sqrt(k) near the critical angle (k's
//       rounding through sqrt's conditioning).
//   Slab.ray_trace__<impl>          (part "slab") a glass slab (two parallel
//       transmitting quads of half-size 20, T = 1, Ks = 0, random ior,
//       thickness 1e-2..2, orientation,
//       view direction at up to 78 degrees from its normal): the ray leaving
//       the slab runs parallel to the primary ray, within 1e-13 (measured
//       1e-14 over 3000 cases).
//   Tir.ray_trace__<impl>           (part "tir") the eye inside a glass ball
//       (or under a glass plane) looks out at normal incidence or within
//       1e-12..1e-3 of the critical angle: the implementation's TIR decision
//       equals the reference's and the long-double oracle's, except within
//       the band where the hit normals' rounding (1e-12 relative in k) can
//       decide (explained: tir_critical).
//   Weights.ray_trace__<impl>       (part "weights") random scenes (spheres and
//       a transmitting triangle over a floor, Ks and T in [0, 1]): every ray
//       of the trees of 8 pixels has weight <= 1 and <= its parent's.
//   Hidden.ray_trace__<impl>        (part "hidden") objects behind an opaque
//       wall that covers the view (lights on the eye's side) change no pixel:
//       the frames with and without them are equal, bit for bit.
//   Pixel.ray_trace__<impl>         (part "pixel") the frame against the
//       one-pixel computation (TracePixelFn, whose ray tree `lockstep trace`
//       prints) on 16 pixels of random scenes (gen_scene): equal bit for bit.
//       The embree frame traces a tile breadth first in streams (rtcIntersect1M,
//       rtcOccluded1M: Embree's packet kernels), the pixel depth first one ray
//       at a time (rtcIntersect1): Embree's packet and single-ray sphere tests
//       round t differently (by an ulp, measured), which t's refinement in
//       double erases unless it changes which surface is nearest or whether a
//       sphere is hit at all. A pixel that differs is explained (float_tie)
//       only when its tree has a ray whose two nearest surfaces (the
//       reference's roots, in double) are within 1e-6 relative of each other,
//       or that passes a sphere's silhouette within float's rounding (the
//       band of Agree's diverge); anything else is unexplained.
//   Far.ray_trace__<impl>           (part "far") gen_scene's kind of scene,
//       opaque, at depth 1, scaled by 10^-2..10^2, moved 0 or 10^0..10^7 from
//       the origin and seen from 10^0..10^7 away (a telephoto view: the
//       angle narrowed to frame the same): every shadow ray of 16 pixels'
//       trees (the row's own offset, or robust=1) answers as an exact long
//       double segment test from the point the row shades; answers within
//       1e-3 of the scene's scale of a boundary are skipped (issue #30).
//   Agree.ray_trace__embree         (part "agree") the frame of every
//       non-reference row against the reference's on random scenes (16 x 16),
//       per pixel within the family's 1/255. A pixel over it has diverging
//       ray trees, and is classified:
//         offset_method  the reference traced with the implementation's
//                        offset method (robust) makes every decision the
//                        implementation makes: the two self-intersection
//                        offsets (fixed eps against robust) decide it;
//         diverge        (the row's known failure, capped per pixel) at the
//                        first node where the trees still differ, the
//                        reference replaying the implementation's own ray
//                        in double decides as the implementation did (the
//                        ray started elsewhere: an earlier bounce's float
//                        rounding), or that ray passes a sphere's silhouette
//                        within float's rounding (4 x 2^-24 |o - c|^2 / 2r:
//                        Embree decides the hit in float), or one tree has
//                        a shadow ray the other
//                        does not and that light is within 1e-4 (|n.l|) of
//                        the hit's tangent plane (n.l > 0 decided on hit
//                        points that differ by rounding);
//         tir_critical   TIR decided differently with |k| < 1e-9 (k from the
//                        reference's ray and normal); a TIR decision that
//                        the reference replays on the implementation's own
//                        incoming ray and normal is `diverge`;
//       anything else (the same ray answered otherwise, or the same
//       decisions with another colour) is unexplained.
#include <gtest/gtest.h>
#include <rapidcheck.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#include "core/error.h"
#include "io/nff.h"
#include "core/ray_trace.h"
#include "core/shading.h"
#include "registry/ray_trace_row.h"
#include "props/gen/case_text.h"
#include "props/gen/numbers.h"
#include "props/property.h"
#include "reference/ray_cast.h"
#include "reference/ray_polygon.h"
#include "reference/ray_sphere.h"

namespace lockstep::props::ray_trace {

namespace {

using gen::hex;

// ---------------------------------------------------------------- the case
struct TraceCase {
  int width = 16, height = 16;
  int px = -1, py = -1;  // one pixel (its tree), or -1: the frame
  std::string params;    // "depth=3 shadows=none"
  std::string nff;       // the scene
  std::string hidden;    // Hidden: objects appended behind the wall
};

std::string write_case(const TraceCase& c) {
  std::ostringstream s;
  s << "trace_case size " << c.width << " " << c.height << " pixel " << c.px << " " << c.py << "\n";
  s << "params " << (c.params.empty() ? "-" : c.params) << "\n";
  s << "hidden " << std::count(c.hidden.begin(), c.hidden.end(), '\n') << "\n" << c.hidden;
  s << "nff\n" << c.nff;
  return s.str();
}

TraceCase read_case(const std::string& text, const std::string& file) {
  std::istringstream s(gen::without_comments(text));
  TraceCase c;
  std::string w, sz, px;
  long hidden_lines = 0;
  if (!(s >> w >> sz >> c.width >> c.height >> px >> c.px >> c.py) || w != "trace_case")
    throw InputError(file, 0, "expected 'trace_case size W H pixel X Y'");
  if (!(s >> w) || w != "params") throw InputError(file, 0, "expected 'params'");
  std::getline(s >> std::ws, c.params);
  if (c.params == "-") c.params.clear();
  if (!(s >> w >> hidden_lines) || w != "hidden") throw InputError(file, 0, "expected 'hidden N'");
  std::getline(s, w);
  for (long k = 0; k < hidden_lines && std::getline(s, w);) c.hidden += w + "\n", ++k;
  if (!std::getline(s, w) || w != "nff") throw InputError(file, 0, "expected 'nff'");
  std::ostringstream rest;
  rest << s.rdbuf();
  c.nff = rest.str();
  return c;
}

Params params_of(const TraceCase& c) {
  Params p;
  std::istringstream s(c.params);
  std::string kv;
  while (s >> kv) {
    const size_t eq = kv.find('=');
    p.set(kv.substr(0, eq), eq == std::string::npos ? "1" : kv.substr(eq + 1));
  }
  return p;
}

Scene scene_of(const TraceCase& c, bool with_hidden = false) {
  return parse_nff(c.nff + (with_hidden ? c.hidden : ""), "<case>");
}

// ---------------------------------------------------------------- NFF text
std::string v3(const Vec3& v) { return hex(v.x) + " " + hex(v.y) + " " + hex(v.z); }

std::string view_text(const Vec3& from, const Vec3& at, const Vec3& up, double angle, int w,
                      int h) {
  return "v\nfrom " + v3(from) + "\nat " + v3(at) + "\nup " + v3(up) + "\nangle " + hex(angle) +
         "\nhither 0x1p-10\nresolution " + std::to_string(w) + " " + std::to_string(h) + "\n";
}

std::string material(const Vec3& color, double kd, double ks, double shine, double t, double ior) {
  return "f " + v3(color) + " " + hex(kd) + " " + hex(ks) + " " + hex(shine) + " " + hex(t) + " " +
         hex(ior) + "\n";
}

// A square of half-size r centred on c with normal m (counter-clockwise seen from m's side).
std::string quad(const Vec3& c, const Vec3& m, double r) {
  const Vec3 a = std::abs(m.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 u = normalize(cross(a, m)), v = cross(m, u);  // u x v = m
  return "p 4\n" + v3(c - r * u - r * v) + "\n" + v3(c + r * u - r * v) + "\n" +
         v3(c + r * u + r * v) + "\n" + v3(c - r * u + r * v) + "\n";
}

Vec3 some_up(const Vec3& dir) {
  return std::abs(dir.z) < 0.9 * length(dir) ? Vec3{0, 0, 1} : Vec3{0, 1, 0};
}

// Three numbers (hex floats too, which istream's >> does not read) from text.
Vec3 read_v3(const std::string& text) {
  const char* p = text.c_str();
  char* end = nullptr;
  Vec3 v;
  for (int a = 0; a < 3; ++a, p = end) v[a] = std::strtod(p, &end);
  return v;
}

// ---------------------------------------------------------------- generators
rc::Gen<Vec3> box(double lo, double hi) {
  return rc::gen::exec([lo, hi] {
    return Vec3{*gen::uniform(lo, hi), *gen::uniform(lo, hi), *gen::uniform(lo, hi)};
  });
}

std::string random_material() {
  const Vec3 col = *box(0.1, 1);
  const double ks = *gen::chance(1, 2) ? *gen::uniform(0, 1) : 0.0;
  const double t = *gen::chance(1, 2) ? *gen::uniform(0, 1) : 0.0;
  return material(col, *gen::uniform(0.2, 1), ks, *gen::uniform(1, 100), t, *gen::uniform(1, 2));
}

// Spheres and a transmitting triangle over a floor, 1..3 lights, seen from ~6 away.
rc::Gen<TraceCase> gen_scene(int size) {
  return rc::gen::exec([size] {
    TraceCase c;
    c.width = c.height = size;
    c.params = "depth=" + std::to_string(*gen::int_in(1, 5));
    if (*gen::chance(1, 4)) c.params += " shadows=none";
    Vec3 from = 6.0 * *gen::unit_dir();
    if (from.z < 0.5) from.z = std::abs(from.z) + 0.5;
    std::string s = "b 0x1.999999999999ap-3 0x1.3333333333333p-2 0x1p-1\n" +
                    view_text(from, {0, 0, 0}, some_up(from), 40, size, size);
    const int lights = int(*gen::int_in(1, 3));
    for (int k = 0; k < lights; ++k) s += "l " + v3(*box(-6, 6) + Vec3{0, 0, 8}) + "\n";
    s += material(*box(0.2, 1), 0.8, *gen::chance(1, 2) ? 0.3 : 0.0, 20, 0, 1);
    s += quad({0, 0, -1}, {0, 0, 1}, 4);
    const int spheres = int(*gen::int_in(1, 5));
    for (int k = 0; k < spheres; ++k)
      s += random_material() + "s " + v3(*box(-1.5, 1.5)) + " " + hex(*gen::uniform(0.2, 0.8)) +
           "\n";
    if (*gen::chance(1, 2))
      s += material({0.9, 0.9, 1}, 0.3, 0.2, 30, *gen::uniform(0.3, 1), *gen::uniform(1, 2)) +
           "p 3\n" + v3(*box(-2, 2)) + "\n" + v3(*box(-2, 2)) + "\n" + v3(*box(-2, 2)) + "\n";
    c.nff = s;
    return c;
  });
}

// A glass slab: faces at s = 0 (outward normal -a) and s = h (outward +a), the
// eye 5 before the front face looking along w with w.a >= 0.2; the centre pixel.
rc::Gen<TraceCase> gen_slab() {
  return rc::gen::exec([] {
    TraceCase c;
    c.width = c.height = 9;
    c.px = c.py = 4;
    c.params = "depth=3 shadows=none cutoff=0";
    const Vec3 a = *gen::unit_dir();
    Vec3 w = *gen::unit_dir();
    if (dot(w, a) < 0) w = -w;
    if (dot(w, a) < 0.2) w = normalize(w + (0.2 - dot(w, a) + 0.01) * a);
    // Faces of half-size 20 and thickness >= 1e-2: the embree row holds its
    // triangles in float, whose vertices at 1e3 would move the faces' planes
    // by 1e-4 -- more than a thin slab's thickness. Thickness <= 2: inside,
    // the ray runs at most tan(acos 0.2) ~ 4.9 times the thickness sideways,
    // which must stay on the back face.
    const double h = *gen::log_uniform(1e-2, 2), ior = *gen::uniform(1.01, 2.5);
    const Vec3 p0 = *box(-1, 1);
    c.nff = "b 0 0 0\n" + view_text(p0 - 5.0 * w, p0, some_up(w), 30, 9, 9) +
            material({1, 1, 1}, 0, 0, 1, 1, ior) + quad(p0, -a, 20) + quad(p0 + h * a, a, 20);
    return c;
  });
}

// The eye inside a glass ball (or below a glass plane, its normal away from
// the eye) looking out at incidence angle theta: 0, or the critical angle
// asin(1/ior) times (1 + delta), |delta| in 1e-12..1e-3.
rc::Gen<TraceCase> gen_tir() {
  return rc::gen::exec([] {
    TraceCase c;
    c.width = c.height = 9;
    c.px = c.py = 4;
    c.params = "depth=2 shadows=none cutoff=0";
    const double ior = *gen::uniform(1.05, 2.5);
    double s = 0;  // sin(theta)
    if (!*gen::chance(1, 4)) {
      const double delta = *gen::signed_log_uniform(1e-12, 1e-3);
      s = std::min(0.999, std::sin(std::asin(1 / ior) * (1 + delta)));
    }
    const Vec3 centre = *box(-2, 2);
    const double r = *gen::log_uniform(0.5, 20);
    const Vec3 e1 = *gen::unit_dir();
    const Vec3 e2 = normalize(cross(e1, std::abs(e1.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
    const std::string glass = material({1, 1, 1}, 0, 0, 1, 1, ior);
    if (*gen::chance(1, 2)) {
      // Ball: from centre + r s e1 along e2 the ray meets the sphere at sin(incidence) = s.
      const Vec3 eye = centre + (r * s) * e1;
      c.nff = "b 0 0 0\n" + view_text(eye, eye + e2, some_up(e2), 10, 9, 9) + glass + "s " +
              v3(centre) + " " + hex(r) + "\n";
    } else {
      // Plane through centre with normal e1 (pointing away from the eye): leaving the glass.
      const Vec3 dir = s * e2 + std::sqrt(1 - s * s) * e1;
      const Vec3 eye = centre - r * dir;
      c.nff = "b 0 0 0\n" + view_text(eye, centre, some_up(dir), 10, 9, 9) + glass +
              quad(centre, e1, 1e3);
    }
    return c;
  });
}

// An opaque wall (one-sided, facing the eye) covering the view, lights and a
// few objects on the eye's side, and the hidden objects behind it.
rc::Gen<TraceCase> gen_hidden() {
  return rc::gen::exec([] {
    TraceCase c = *gen_scene(12);
    c.params += " depth=4";
    // The eye looks at the origin from `from`; the wall's plane is 1 behind the origin.
    const Vec3 from = read_v3(c.nff.substr(c.nff.find("from ") + 5));
    const Vec3 back = normalize(-from);
    c.nff += material({0.7, 0.7, 0.7}, 0.8, *gen::chance(1, 2) ? 0.5 : 0.0, 10, 0, 1) +
             quad(2.0 * back, -back, 1e4);
    // Hidden: spheres and a polygon well behind the wall (its plane is 2 from the origin).
    std::string h;
    const int n = int(*gen::int_in(1, 4));
    for (int k = 0; k < n; ++k) {
      const Vec3 side = *box(-3, 3);
      h += random_material() + "s " +
           v3((4.0 + *gen::uniform(0, 3)) * back + (side - dot(side, back) * back)) + " " +
           hex(*gen::uniform(0.2, 1.5)) + "\n";
    }
    // A square of half-size <= 1.5 at 5: it reaches at most 2.2 towards the wall (at 2).
    h += random_material() + quad(5.0 * back, *gen::unit_dir(), *gen::uniform(0.5, 1.5));
    c.hidden = h;
    return c;
  });
}

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

// ---------------------------------------------------------------- checks
// Laws: a case is (d, n, eta) in the scene-free text "laws dx dy dz nx ny nz eta".
struct LawCase {
  Vec3 d, n;
  double eta = 1;
};

std::string write_law(const LawCase& c) {
  return "laws " + v3(c.d) + " " + v3(c.n) + " " + hex(c.eta) + "\n";
}

LawCase read_law(const std::string& text, const std::string& file) {
  std::istringstream s(gen::without_comments(text));
  std::string w;
  LawCase c;
  if (!(s >> w) || w != "laws") throw InputError(file, 0, "expected 'laws'");
  double v[7];
  for (double& x : v) {
    if (!(s >> w)) throw InputError(file, 0, "the case ends early");
    x = std::strtod(w.c_str(), nullptr);
  }
  c.d = {v[0], v[1], v[2]};
  c.n = {v[3], v[4], v[5]};
  c.eta = v[6];
  return c;
}

rc::Gen<LawCase> gen_laws() {
  return rc::gen::exec([] {
    LawCase c;
    c.n = *gen::unit_dir();
    const bool critical = *gen::chance(1, 2);
    const double ior = *gen::uniform(1.01, 2.5);
    c.eta = *gen::chance(1, 2) ? ior : 1 / ior;
    if (critical) {
      c.eta = ior;  // leaving: TIR exists
      const double delta = *gen::signed_log_uniform(1e-12, 1e-3);
      const double theta = std::min(1.5, std::asin(1 / ior) * (1 + delta));
      const Vec3 a = std::abs(c.n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
      const Vec3 u = normalize(cross(a, c.n));
      c.d = normalize(std::sin(theta) * u - std::cos(theta) * c.n);
    } else {
      c.d = *gen::unit_dir();
      if (dot(c.d, c.n) > 0) c.d = -c.d;
    }
    return c;
  });
}

using LD = long double;
using V3L = Vec3T<LD>;

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
// gen_scene's kind of scene (a floor, 1..5 spheres, maybe a triangle, 1..3
// lights), opaque and at depth 1, scaled by s (10^-2 .. 10^2), moved by D
// (0, or 10^0 .. 10^7) along a random direction, and seen from a random
// direction at eye distance L (10^0 .. 10^7, at least 3 s) with the view
// angle narrowed so that the frame shows what it shows from 6 s: the
// dimensions a user varies (issue #30: the eye's distance beside the
// scene's offset and scale).
rc::Gen<TraceCase> gen_far() {
  return rc::gen::exec([] {
    TraceCase c;
    c.width = c.height = 12;
    c.params = "depth=1";
    if (*gen::chance(1, 2)) c.params += " robust=1";
    const double s = std::pow(10.0, *gen::uniform(-2, 2));
    const double d = *gen::chance(1, 4) ? 0.0 : std::pow(10.0, *gen::uniform(0, 7));
    const double eye = std::max(3 * s, std::pow(10.0, *gen::uniform(0, 7)));
    const Vec3 shift = d * *gen::unit_dir();
    const auto at = [&](const Vec3& local) { return s * local + shift; };
    Vec3 dir = *gen::unit_dir();
    if (dir.z < 0.3) dir.z = std::abs(dir.z) + 0.3;
    dir = normalize(dir);
    const double angle = 2 * std::atan(std::tan(20 * M_PI / 180) * 6 * s / eye) * 180 / M_PI;
    std::string t = "b 0x1.999999999999ap-3 0x1.3333333333333p-2 0x1p-1\n" +
                    view_text(shift + eye * dir, shift, some_up(dir), angle, c.width, c.height);
    const int lights = int(*gen::int_in(1, 3));
    for (int k = 0; k < lights; ++k) t += "l " + v3(at(*box(-6, 6) + Vec3{0, 0, 8})) + "\n";
    t += material(*box(0.2, 1), 0.8, 0.3, 20, 0, 1);
    const Vec3 fu{4, 0, 0}, fv{0, 4, 0}, f0{0, 0, -1};
    t += "p 4\n" + v3(at(f0 - fu - fv)) + "\n" + v3(at(f0 + fu - fv)) + "\n" +
         v3(at(f0 + fu + fv)) + "\n" + v3(at(f0 - fu + fv)) + "\n";
    const int spheres = int(*gen::int_in(1, 5));
    for (int k = 0; k < spheres; ++k)
      t += material(*box(0.1, 1), 0.8, 0.3, 20, 0, 1) + "s " + v3(at(*box(-1.5, 1.5))) + " " +
           hex(s * *gen::uniform(0.2, 0.8)) + "\n";
    if (*gen::chance(1, 2))
      t += material({0.9, 0.9, 1}, 0.6, 0.2, 30, 0, 1) + "p 3\n" + v3(at(*box(-2, 2))) + "\n" +
           v3(at(*box(-2, 2))) + "\n" + v3(at(*box(-2, 2))) + "\n";
    c.nff = t;
    return c;
  });
}

V3L sub(const V3L& a, const V3L& b) { return a - b; }
LD dotl(const V3L& a, const V3L& b) { return dot(a, b); }
V3L crossl(const V3L& a, const V3L& b) { return cross(a, b); }
V3L to_l(const Vec3& v) { return V3L(v); }

// The exact shadow answer for the segment from p (on primitive own) to the
// light, in long double: blocked by any other sphere or polygon (both sides,
// core/ray_trace.h). Ambiguous (nullopt) when the segment passes within m of
// another sphere's surface, crosses a polygon's plane within m of one of its
// edges, or within m of either end: rounding may decide those either way.
std::optional<bool> exact_blocked(const Scene& scene, uint32_t own, const V3L& p, const V3L& light,
                                  LD m) {
  const V3L seg = sub(light, p);
  const LD len2 = dotl(seg, seg), len = std::sqrt(len2);
  bool blocked = false;
  for (uint32_t k = 0; k < scene.sphere_count(); ++k) {
    if (k == own) continue;
    const V3L pc = sub(to_l(scene.sphere_center[k]), p);
    LD u = dotl(pc, seg) / len2;
    u = u < 0 ? 0 : u > 1 ? 1 : u;
    const V3L q = {pc.x - u * seg.x, pc.y - u * seg.y, pc.z - u * seg.z};
    const LD dist = std::sqrt(dotl(q, q)), r = std::abs(scene.sphere_radius[k]);
    if (std::abs(dist - r) < m) return std::nullopt;
    blocked = blocked || dist < r;
  }
  for (uint32_t poly = 0; poly < scene.polygon_count(); ++poly) {
    if (scene.sphere_count() + poly == own) continue;
    const uint32_t first = scene.poly_first[poly], n = scene.poly_first[poly + 1] - first;
    const V3L a = to_l(scene.vertex[first]);
    V3L nrm{};
    for (uint32_t i = 0; i < n; ++i) {  // Newell's normal, in long double
      const V3L u = to_l(scene.vertex[first + i]), v = to_l(scene.vertex[first + (i + 1) % n]);
      nrm.x += (u.y - v.y) * (u.z + v.z), nrm.y += (u.z - v.z) * (u.x + v.x),
          nrm.z += (u.x - v.x) * (u.y + v.y);
    }
    const LD nl = std::sqrt(dotl(nrm, nrm));
    if (!(nl > 0)) continue;
    nrm = {nrm.x / nl, nrm.y / nl, nrm.z / nl};
    const LD h0 = dotl(nrm, sub(p, a)), h1 = dotl(nrm, sub(light, a));
    if ((h0 > 0) == (h1 > 0)) continue;  // both ends on one side
    const LD u = h0 / (h0 - h1);
    if (u * len < m || (1 - u) * len < m) return std::nullopt;
    const V3L x = {p.x + u * seg.x, p.y + u * seg.y, p.z + u * seg.z};
    // Inside the (convex) polygon: on the inner side of every edge, by more than m.
    bool inside = true;
    for (uint32_t i = 0; i < n; ++i) {
      const V3L u0 = to_l(scene.vertex[first + i]), u1 = to_l(scene.vertex[first + (i + 1) % n]);
      const V3L e = sub(u1, u0);
      const LD el = std::sqrt(dotl(e, e));
      const LD side = dotl(crossl(e, sub(x, u0)), nrm) / el;
      if (std::abs(side) < m) return std::nullopt;
      inside = inside && side > 0;
    }
    blocked = blocked || inside;
  }
  return blocked;
}

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

// ---------------------------------------------------------------- properties
template <class Case>
Property property(const Family& f, std::string_view impl, std::string suite, std::string check,
                  std::string generator, rc::Gen<Case> gen, double bound,
                  std::function<Verdict(const Case&)> judge, std::string (*write)(const Case&),
                  Case (*read)(const std::string&, const std::string&),
                  std::string units = "pixels") {
  Property p;
  p.family = std::string(f.name);
  p.check = std::move(check);
  p.suite = std::move(suite);
  p.name = std::string(f.name) + "__" + std::string(impl);
  p.generator = std::move(generator);
  p.pair = "ray_trace";
  p.impl = std::string(impl);
  p.bound = bound;
  p.unit = "error";
  p.units = std::move(units);
  set_case_runner<Case>(p, std::move(gen), std::move(judge), write, read);
  return p;
}

}  // namespace

FamilyProperties properties(const Family& family, RunResources& run) {
  FamilyProperties out;
  const KernelRow<TracerFns>& row = ray_trace_row();
  // Each row's run, shared by its properties (the embree row: the process's
  // one device, also the ray_cast embree row's, released with the properties).
  const auto ref_run = std::make_shared<const TracerRun>(start_run(row.impls.front().fn, run));
  if (family.has_property("laws")) {
    Property p = property<LawCase>(family, "reference", "Laws", "laws", "directions", gen_laws(),
                                   1e-14, check_laws, write_law, read_law, "cases");
    p.unit = "direction error";
    out.properties.push_back(std::move(p));
  }
  for (const Impl<TracerFns>& impl : row.impls) {
    const auto fn_run =
        &impl == &row.impls.front() ? ref_run
                                    : std::make_shared<const TracerRun>(start_run(impl.fn, run));
    const std::string name(impl.name);
    if (family.has_property("slab"))
      out.properties.push_back(property<TraceCase>(
          family, impl.name, "Slab", "slab", "glass_slab", gen_slab(), 1e-13,
          [fn_run](const TraceCase& c) { return check_slab(*fn_run, c); }, write_case, read_case, "cases"));
    if (family.has_property("tir"))
      out.properties.push_back(property<TraceCase>(
          family, impl.name, "Tir", "tir", "critical_angle", gen_tir(), 0,
          [ref_run, fn_run](const TraceCase& c) { return check_tir(*ref_run, *fn_run, c); }, write_case, read_case,
          "cases"));
    if (family.has_property("weights"))
      out.properties.push_back(property<TraceCase>(
          family, impl.name, "Weights", "weights", "scenes", gen_scene(16), 1,
          [fn_run](const TraceCase& c) { return check_weights(*fn_run, c); }, write_case, read_case,
          "rays"));
    if (family.has_property("hidden"))
      out.properties.push_back(property<TraceCase>(
          family, impl.name, "Hidden", "hidden", "behind_wall", gen_hidden(), 0,
          [fn_run](const TraceCase& c) { return check_hidden(*fn_run, c); }, write_case, read_case));
    if (family.has_property("far"))
      out.properties.push_back(property<TraceCase>(
          family, impl.name, "Far", "far", "far_views", gen_far(), 0,
          [fn_run, textbook = &impl == &row.impls.front()](const TraceCase& c) {
            return check_far(*fn_run, c, textbook);
          },
          write_case, read_case, "shadow rays"));
    if (family.has_property("pixel"))
      out.properties.push_back(property<TraceCase>(
          family, impl.name, "Pixel", "pixel", "scenes", gen_scene(16), 0,
          [fn_run](const TraceCase& c) { return check_pixel(*fn_run, c); }, write_case, read_case));
    if (family.has_property("agree") && &impl != &row.impls.front()) {
      const std::string known = known_label(name, impl.known);
      Property p = property<TraceCase>(
          family, impl.name, "Agree", "agree", "scenes", gen_scene(16), family.tol.abs,
          [ref_run, fn_run, known](const TraceCase& c) { return check_agree(*ref_run, *fn_run, known, c); },
          write_case, read_case);
      p.known = impl.known;
      out.properties.push_back(std::move(p));
    }
  }
  return out;
}

}  // namespace lockstep::props::ray_trace
