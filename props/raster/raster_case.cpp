// lockstep props/raster: cases and their generators (see raster_case.h).
#include "props/raster/raster_case.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <cstdio>
#include <sstream>

#include "core/error.h"
#include "io/nff.h"
#include "props/gen/numbers.h"
#include "reference/raster.h"

namespace lockstep::props::raster {

namespace {

constexpr const char* kHeader = "raster_case";

}  // namespace

std::string num(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

std::shared_ptr<const Scene> RasterCase::scene() const {
  return std::make_shared<const Scene>(parse_nff(nff, "<case>"));
}

FrameOptions RasterCase::options() const {
  FrameOptions o;
  o.width = width;
  o.height = height;
  o.threads = 1;
  o.params = params;
  return o;
}

std::string write_case(const RasterCase& c) {
  std::string s = std::string(kHeader) + " " + std::to_string(c.width) + " " + std::to_string(c.height);
  for (const auto& [k, v] : c.params.items) s += " " + k + "=" + v;
  return s + "\n" + c.nff;
}

RasterCase read_case(const std::string& text, const std::string& file) {
  RasterCase c;
  // The case starts at its header line (a counterexample file's comments come first).
  const size_t at = text.starts_with(kHeader) ? 0 : text.find(std::string("\n") + kHeader);
  if (at == std::string::npos) throw InputError(file, 0, std::string("no '") + kHeader + " W H [settings]' line");
  const size_t start = at == 0 ? 0 : at + 1;
  const size_t eol = text.find('\n', start);
  const std::string first = text.substr(start, eol - start);
  if (!first.starts_with(kHeader)) throw InputError(file, 1, std::string("expected '") + kHeader + " W H [settings]'");
  std::istringstream in(first.substr(std::string(kHeader).size()));
  if (!(in >> c.width >> c.height) || c.width < 1 || c.height < 1 || c.width > 4096 || c.height > 4096)
    throw InputError(file, 1, "bad frame size");
  for (std::string kv; in >> kv;) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos) throw InputError(file, 1, "expected name=value, got '" + kv + "'");
    c.params.set(kv.substr(0, eq), kv.substr(eq + 1));
  }
  c.nff = eol == std::string::npos ? "" : text.substr(eol + 1);
  return c;
}

// ---------------------------------------------------------------- generators

namespace {

// A point at eye depth z, at image-plane offset (u, v) in [-1, 1] of the half field of view.
std::string camera_block(int w, int h) {
  return "v\nfrom 0 0 0\nat 0 0 -1\nup 0 1 0\nangle 40\nhither 1\nresolution " + std::to_string(w) + " " +
         std::to_string(h) + "\n";
}

rc::Gen<double> unit_double() { return gen::uniform(0, 1); }

}  // namespace

rc::Gen<RasterCase> triangle_soup() {
  return rc::gen::exec([] {
    RasterCase c;
    c.width = *rc::gen::inRange(8, 49);
    c.height = *rc::gen::inRange(8, 49);
    const int tris = *rc::gen::inRange(1, 7);
    const int lights = *rc::gen::inRange(1, 3);
    std::string s = camera_block(c.width, c.height) + "b 0.1 0.2 0.3\n";
    const double half = std::tan(20.0 * M_PI / 180.0);
    for (int l = 0; l < lights; ++l)
      s += "l " + num(*rc::gen::inRange(-10, 11)) + " " + num(*rc::gen::inRange(-10, 11)) + " " +
           num(*rc::gen::inRange(-5, 6)) + "\n";
    for (int t = 0; t < tris; ++t) {
      const bool two_sided = *rc::gen::inRange(0, 4) == 0;
      s += "f " + num(0.2 + 0.8 * *unit_double()) + " " + num(0.2 + 0.8 * *unit_double()) + " " +
           num(0.2 + 0.8 * *unit_double()) + " 0.8 " + num(0.5 * *unit_double()) + " 8 " + (two_sided ? "0.5" : "0") +
           " 1\np 3\n";
      for (int k = 0; k < 3; ++k) {
        const double z = 2 + 10 * *unit_double();
        const double u = (2.4 * *unit_double() - 1.2) * half * z, v = (2.4 * *unit_double() - 1.2) * half * z;
        s += num(u) + " " + num(v) + " " + num(-z) + "\n";
      }
    }
    c.nff = s;
    c.params.set("shading", "phong");
    return c;
  });
}

}  // namespace lockstep::props::raster

namespace lockstep::props::raster {

rc::Gen<RasterCase> edge_on_soup() {
  return rc::gen::exec([] {
    RasterCase c;
    c.width = *rc::gen::inRange(8, 49);
    c.height = *rc::gen::inRange(8, 49);
    const int tris = *rc::gen::inRange(1, 7);
    std::string s = camera_block(c.width, c.height) + "b 0.1 0.2 0.3\nl 4 5 3\n";
    const double half = std::tan(20.0 * M_PI / 180.0);
    for (int t = 0; t < tris; ++t) {
      s += "f " + num(0.2 + 0.8 * *unit_double()) + " " + num(0.2 + 0.8 * *unit_double()) + " 0.5 0.8 0 1 0 1\np 3\n";
      // Two points in view, a third in the plane through them and the eye
      // (at the origin), then pushed off that plane by a relative offset.
      Vec3 p[3];
      if (*rc::gen::inRange(0, 2) == 0) {
        for (int k = 0; k < 2; ++k) {
          const double z = 2 + 10 * *unit_double();
          p[k] = {(2.2 * *unit_double() - 1.1) * half * z, (2.2 * *unit_double() - 1.1) * half * z, -z};
        }
        // The third on the line through them (extended up to half its length
        // either way) and the eye, at depth 2..12 (in front of the hither plane).
        double a = *gen::uniform(-0.5, 1.5);
        if (-(p[0] + a * (p[1] - p[0])).z < 2) a = std::clamp(a, 0.0, 1.0);
        const Vec3 q = p[0] + a * (p[1] - p[0]);
        p[2] = ((2 + 10 * *unit_double()) / -q.z) * q;
        const Vec3 n = normalize(cross(p[0], p[1]));
        const double off = *gen::log_uniform(1e-9, 1e-1) * (*rc::gen::arbitrary<bool>() ? 1 : -1);
        p[2] += off * length(p[2]) * n;
      } else {
        // A sliver whose snapped side is not its exact side, drawn on screen:
        // v0, v1 within half a snapping step (1/256 px) of the centres of two
        // pixels of one row (or column), so both snap onto it; v2 on the
        // exact line through them extended beyond v1 (or before v0), where it
        // may be more than half a step off the row, then moved a hair
        // (1e-7..1e-3 step) to either side. v2 snaps off the row by a step
        // whatever the hair's side: the snapped triangle owns (top-left rule)
        // or leaves the run of samples between v0 and v1, and half the time
        // world-space facing (the hair's side) and the snapped area disagree.
        const double pitch = 2 * half / double(std::min(c.width, c.height) - 1);
        const bool column = *rc::gen::arbitrary<bool>();
        const int along = column ? c.height : c.width, across = column ? c.width : c.height;
        const int row = *rc::gen::inRange(0, across), i0 = *rc::gen::inRange(0, along);
        const int i1 = i0 + *rc::gen::inRange(1, 9) * (*rc::gen::arbitrary<bool>() ? 1 : -1);
        const double step = 1.0 / kSubpixel;
        const double e0 = *gen::uniform(-0.45, 0.45) * step, e1 = *gen::uniform(-0.45, 0.45) * step;
        const double t = *rc::gen::arbitrary<bool>() ? *gen::uniform(1.3, 4) : -*gen::uniform(0.3, 3);
        const double hair = *gen::log_uniform(1e-7, 1e-3) * step * (*rc::gen::arbitrary<bool>() ? 1 : -1);
        // (along, across) in pixels, pixel centres at k + 0.5.
        const double uv[3][2] = {{i0 + 0.5, row + 0.5 + e0},
                                 {i1 + 0.5, row + 0.5 + e1},
                                 {i0 + 0.5 + t * (i1 - i0), row + 0.5 + e0 + t * (e1 - e0) + hair}};
        for (int k = 0; k < 3; ++k) {
          const double z = 2 + 10 * *unit_double();
          const double sx = column ? uv[k][1] : uv[k][0], sy = column ? uv[k][0] : uv[k][1];
          p[k] = {(sx - 0.5 * c.width) * pitch * z, (0.5 * c.height - sy) * pitch * z, -z};
        }
      }
      for (const Vec3& v : p) s += num(v.x) + " " + num(v.y) + " " + num(v.z) + "\n";
    }
    c.nff = s;
    c.params.set("shading", "flat");
    return c;
  });
}

}  // namespace lockstep::props::raster

namespace lockstep::props::raster {

rc::Gen<RasterCase> shaded_soup() {
  return rc::gen::exec([] {
    RasterCase c;
    c.width = *rc::gen::inRange(8, 49);
    c.height = *rc::gen::inRange(8, 49);
    std::string s = camera_block(c.width, c.height) + "b 0.1 0.2 0.3\n";
    const double half = std::tan(20.0 * M_PI / 180.0);
    // A point in view at eye depth 2..12.
    auto in_view = [&](double spread) {
      const double z = 2 + 10 * *unit_double();
      return Vec3{(2 * spread * *unit_double() - spread) * half * z, (2 * spread * *unit_double() - spread) * half * z,
                  -z};
    };
    auto vec = [](const Vec3& v) { return num(v.x) + " " + num(v.y) + " " + num(v.z); };
    const int lights = *rc::gen::inRange(1, 4);
    for (int l = 0; l < lights; ++l) {
      const Vec3 at{*gen::uniform(-10, 10), *gen::uniform(-10, 10), *gen::uniform(-8, 4)};
      s += "l " + vec(at) + "\n";
      const int kind = *rc::gen::inRange(0, 3);  // 0 point, 1 attenuated, 2 spot
      if (kind == 1)
        s += "#lockstep atten " + num(*gen::uniform(0.2, 1)) + " " + num(*gen::uniform(0, 0.2)) + " " +
             num(*gen::uniform(0, 0.05)) + "\n";
      if (kind == 2) {
        const Vec3 aim = in_view(0.8) - at;
        s += "#lockstep spot " + vec(aim) + " " + num(*gen::uniform(5, 80)) + " " + num(*gen::uniform(0, 20)) + "\n";
      }
    }
    const int objects = *rc::gen::inRange(1, 6);
    for (int t = 0; t < objects; ++t) {
      const bool two_sided = *rc::gen::inRange(0, 4) == 0;
      s += "f " + num(0.2 + 0.8 * *unit_double()) + " " + num(0.2 + 0.8 * *unit_double()) + " " +
           num(0.2 + 0.8 * *unit_double()) + " " + num(*gen::uniform(0.3, 0.9)) + " " + num(*gen::uniform(0, 0.8)) +
           " " + num(*gen::uniform(1, 60)) + " " + (two_sided ? "0.5" : "0") + " 1\n";
      const int kind = *rc::gen::inRange(0, 3);  // 0 flat triangle, 1 pp triangle, 2 pp quad
      Vec3 p[4];
      for (int k = 0; k < 3; ++k) p[k] = in_view(1.2);
      if (*rc::gen::inRange(0, 3) == 0) {
        // On pixel centres (Camera's convention), the first two on one row or
        // column: an edge through samples, where the fill rule decides.
        const double pitch = 2 * half / double(std::min(c.width, c.height) - 1);
        int ij[3][2];
        for (auto& q : ij) q[0] = *rc::gen::inRange(-2, c.width + 2), q[1] = *rc::gen::inRange(-2, c.height + 2);
        const int axis = *rc::gen::inRange(0, 2);
        ij[1][axis] = ij[0][axis];
        for (int k = 0; k < 3; ++k) {
          const double z = 2 + 10 * *unit_double();
          p[k] = {(ij[k][0] + 0.5 - 0.5 * c.width) * pitch * z, (0.5 * c.height - ij[k][1] - 0.5) * pitch * z, -z};
        }
      }
      const int n = kind == 2 ? 4 : 3;
      if (n == 4) p[3] = p[0] + (p[2] - p[1]);  // a parallelogram: planar
      const Vec3 face = normalize(cross(p[1] - p[0], p[2] - p[0]));
      if (kind == 0) {
        s += "p 3\n";
        for (int k = 0; k < 3; ++k) s += vec(p[k]) + "\n";
        continue;
      }
      // Quad order p0 p1 p2 p3 must go round: p3 = p0 + p2 - p1 is opposite p1.
      const int order[4] = {0, 1, 2, 3};
      s += "pp " + std::to_string(n) + "\n";
      for (int k = 0; k < n; ++k) {
        const Vec3 tilt{*gen::uniform(-1.2, 1.2), *gen::uniform(-1.2, 1.2), *gen::uniform(-1.2, 1.2)};
        Vec3 nv = face + tilt;
        if (!(length(nv) > 0.1)) nv = face;
        s += vec(p[order[k]]) + " " + vec(nv) + "\n";
      }
    }
    c.nff = s;
    c.params.set("shading", *rc::gen::element<std::string>("flat", "gouraud", "phong", "phong", "blinn"));
    c.params.set("cull", *rc::gen::element<std::string>("world", "projection"));
    return c;
  });
}

}  // namespace lockstep::props::raster
