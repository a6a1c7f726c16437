// lockstep props/ray_trace: the named case generators (see generators.h).
#include "props/ray_trace/generators.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "props/gen/case_text.h"
#include "props/gen/numbers.h"

namespace lockstep::props::ray_trace {

using gen::hex;

namespace {

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

}  // namespace

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

}  // namespace lockstep::props::ray_trace
