#include "props/ray_cast/case.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <istream>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "io/nff.h"

namespace lockstep::props::ray_cast {

std::string hex(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}

std::string hex(const Vec3& v) { return hex(v.x) + " " + hex(v.y) + " " + hex(v.z); }

std::string hex(const Ray& r) {
  return "o " + hex(r.o) + " d " + hex(r.d) + " tmin " + hex(r.tmin) + " tmax " + hex(r.tmax);
}

std::string dec(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

std::string to_nff(const Scene& s) {
  std::ostringstream o;
  const View& v = s.view;
  o << "b " << hex(s.background) << "\n";
  o << "v\nfrom " << hex(v.from) << "\nat " << hex(v.at) << "\nup " << hex(v.up) << "\nangle " << hex(v.angle)
    << "\nhither " << hex(v.hither) << "\nresolution " << v.xres << " " << v.yres << "\n";
  for (const Light& l : s.lights) {
    o << "l " << hex(l.position);
    if (l.has_color) o << " " << hex(l.color);
    o << "\n";
    if (l.atten != Vec3{1, 0, 0}) o << "#lockstep atten " << hex(l.atten) << "\n";
    if (l.spot)
      o << "#lockstep spot " << hex(l.spot_dir) << " " << hex(l.spot_cutoff) << " " << hex(l.spot_exponent) << "\n";
  }
  long current = -1;
  auto material = [&](uint32_t m) {
    if (long(m) == current) return;
    const Material& mt = s.materials[m];
    o << "f " << hex(mt.color) << " " << hex(mt.kd) << " " << hex(mt.ks) << " " << hex(mt.shine) << " "
      << hex(mt.transmittance) << " " << hex(mt.ior) << "\n";
    current = long(m);
  };
  for (uint32_t i = 0; i < s.sphere_count(); ++i) {
    material(s.sphere_material[i]);
    o << "s " << hex(s.sphere_center[i]) << " " << hex(s.sphere_radius[i]) << "\n";
  }
  for (uint32_t p = 0; p < s.polygon_count(); ++p) {
    material(s.poly_material[p]);
    const auto vs = s.polygon_vertices(p);
    const bool patch = s.poly_is_patch[p] != 0;
    o << (patch ? "pp " : "p ") << vs.size() << "\n";
    for (size_t k = 0; k < vs.size(); ++k) {
      o << hex(vs[k]);
      if (patch) o << " " << hex(s.vertex_normal[s.poly_first[p] + k]);
      o << "\n";
    }
  }
  for (uint32_t i = 0; i < s.cone_count(); ++i) {
    material(s.cone_material[i]);
    const double sign = s.cone_inside[i] ? -1.0 : 1.0;  // NFF: negative radii, only the inside
    o << "c\n"
      << hex(s.cone_base[i]) << " " << hex(sign * s.cone_r0[i]) << "\n"
      << hex(s.cone_apex[i]) << " " << hex(sign * s.cone_r1[i]) << "\n";
  }
  return o.str();
}

void write_case(std::ostream& out, const Case& c) {
  out << "generator " << c.generator << "\n";
  if (c.has_sphere) out << "sphere " << hex(c.sphere.center) << " " << hex(c.sphere.radius) << "\n";
  if (c.has_plane) out << "plane " << hex(c.plane.n) << " " << hex(c.plane.d) << "\n";
  if (c.has_poly) out << "poly " << c.poly << "\n";
  if (c.render_size > 0) out << "render " << c.render_size << "\n";
  if (c.has_cone) out << "cone " << c.cone << "\n";
  for (const Ray& ray : c.rays)
    out << "ray " << hex(ray.o) << " " << hex(ray.d) << " " << hex(ray.tmin) << " " << hex(ray.tmax) << "\n";
  out << "scene\n" << to_nff(c.scene) << "end\n";
}

std::string case_text(const Case& c) {
  std::ostringstream o;
  write_case(o, c);
  return o.str();
}

Case with_ray(const Case& c, size_t i) {
  Case one = c;
  one.rays = {c.rays[i]};
  return one;
}

namespace {

double num(const std::string& s, const std::string& name, int line) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0')
    throw std::runtime_error(name + ":" + std::to_string(line) + ": not a number: '" + s + "'");
  return v;
}

}  // namespace

Case read_case(const std::string& text_in, const std::string& name) {
  Case c;
  std::istringstream in(text_in);
  std::string line;
  int line_no = 0;
  bool have_scene = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    std::vector<std::string> w;
    for (std::string x; ls >> x;) w.push_back(x);
    auto rest = [&]() {
      const size_t p = line.find(' ');
      return p == std::string::npos ? std::string() : line.substr(p + 1);
    };
    auto need = [&](size_t n) {
      if (w.size() != n)
        throw std::runtime_error(name + ":" + std::to_string(line_no) + ": '" + key + "' wants " +
                                 std::to_string(n) + " fields");
    };
    auto d = [&](size_t i) { return num(w[i], name, line_no); };
    if (key == "generator") c.generator = rest();
    else if (key == "sphere") {
      need(4);
      c.has_sphere = true;
      c.sphere = Sphere{{d(0), d(1), d(2)}, d(3)};
    } else if (key == "plane") {
      need(4);
      c.has_plane = true;
      c.plane = Plane{{d(0), d(1), d(2)}, d(3)};
    } else if (key == "poly") {
      need(1);
      c.has_poly = true;
      c.poly = uint32_t(std::stoul(w[0]));
    } else if (key == "cone") {
      need(1);
      c.has_cone = true;
      c.cone = uint32_t(std::stoul(w[0]));
    } else if (key == "render") {
      need(1);
      c.render_size = std::stoi(w[0]);
    } else if (key == "ray") {
      need(8);
      c.rays.push_back(Ray{{d(0), d(1), d(2)}, {d(3), d(4), d(5)}, d(6), d(7)});
    } else if (key == "scene") {
      std::string text;
      while (std::getline(in, line)) {
        ++line_no;
        if (line == "end") break;
        text += line;
        text += '\n';
      }
      c.scene = parse_nff(text, name);
      have_scene = true;
    } else {
      throw std::runtime_error(name + ":" + std::to_string(line_no) + ": unknown key '" + key + "'");
    }
  }
  if (!have_scene) throw std::runtime_error(name + ": no 'scene' block");
  if (c.has_poly && c.poly >= c.scene.polygon_count())
    throw std::runtime_error(name + ": poly index out of range");
  if (c.has_cone && c.cone >= c.scene.cone_count())
    throw std::runtime_error(name + ": cone index out of range");
  return c;
}

void showValue(const Case& c, std::ostream& os) {
  os << "Case{generator " << c.generator << ", " << c.rays.size() << " rays";
  if (c.has_sphere) os << ", sphere c " << hex(c.sphere.center) << " r " << hex(c.sphere.radius);
  if (c.has_plane) os << ", plane n " << hex(c.plane.n) << " d " << hex(c.plane.d);
  if (c.has_poly) os << ", poly " << c.poly;
  if (c.has_cone) os << ", cone " << c.cone;
  os << ", " << c.scene.sphere_count() << " spheres, " << c.scene.polygon_count() << " polygons, "
     << c.scene.cone_count() << " cones}\n";
  for (size_t i = 0; i < c.rays.size(); ++i) os << "  ray " << i << ": " << hex(c.rays[i]) << "\n";
  if (c.scene.prim_count() > 0 && c.scene.prim_count() < 40) os << to_nff(c.scene);
}

}  // namespace lockstep::props::ray_cast
