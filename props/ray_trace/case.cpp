// lockstep props/ray_trace: the cases' text forms (see case.h).
#include "props/ray_trace/case.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "core/error.h"
#include "io/nff.h"
#include "props/gen/case_text.h"
#include "props/gen/numbers.h"

namespace lockstep::props::ray_trace {

using gen::hex;

// ---------------------------------------------------------------- the case
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

Scene scene_of(const TraceCase& c, bool with_hidden) {
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

// ---------------------------------------------------------------- Laws
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

}  // namespace lockstep::props::ray_trace
