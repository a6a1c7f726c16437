// lockstep props/raster: cases and their generators (see raster_case.h).
#include "props/raster/raster_case.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/error.h"
#include "core/nff.h"
#include "props/gen/numbers.h"

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
      for (int k = 0; k < 2; ++k) {
        const double z = 2 + 10 * *unit_double();
        p[k] = {(2.2 * *unit_double() - 1.1) * half * z, (2.2 * *unit_double() - 1.1) * half * z, -z};
      }
      const double a = *gen::uniform(-0.5, 1.5), b = *gen::uniform(0.2, 1.5);
      p[2] = b * (p[0] + a * (p[1] - p[0]));
      const Vec3 n = normalize(cross(p[0], p[1]));
      const double off = *gen::log_uniform(1e-9, 1e-1) * (*rc::gen::arbitrary<bool>() ? 1 : -1);
      p[2] += off * length(p[2]) * n;
      for (const Vec3& v : p) s += num(v.x) + " " + num(v.y) + " " + num(v.z) + "\n";
    }
    c.nff = s;
    c.params.set("shading", "flat");
    return c;
  });
}

}  // namespace lockstep::props::raster
