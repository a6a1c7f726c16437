// lockstep core: transfer functions (see core/transfer_function.h).
#include "core/transfer_function.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace lockstep {

void TransferFunction::eval(double v, double out[4]) const {
  auto put = [out](const ControlPoint& p) {
    out[0] = p.r;
    out[1] = p.g;
    out[2] = p.b;
    out[3] = p.a;
  };
  if (v <= points.front().value) return put(points.front());
  if (v >= points.back().value) return put(points.back());
  // The first point above v, and the one before it.
  const auto hi = std::upper_bound(points.begin(), points.end(), v,
                                   [](double x, const ControlPoint& p) { return x < p.value; });
  const ControlPoint& a = hi[-1];
  const ControlPoint& b = *hi;
  const double t = (v - a.value) / (b.value - a.value);
  out[0] = a.r + t * (double(b.r) - a.r);
  out[1] = a.g + t * (double(b.g) - a.g);
  out[2] = a.b + t * (double(b.b) - a.b);
  out[3] = a.a + t * (double(b.a) - a.a);
}

double TransferFunction::max_alpha(double lo, double hi) const {
  double rgba[4];
  eval(lo, rgba);
  double m = rgba[3];
  eval(hi, rgba);
  m = std::max(m, rgba[3]);
  // Piecewise linear: the largest value inside is at a control point.
  for (const ControlPoint& p : points)
    if (p.value > lo && p.value < hi) m = std::max(m, double(p.a));
  return m;
}

const char* transfer_presets() { return "ct-bone|ct-skin|mri|ramp"; }

namespace {

TransferFunction preset(const std::string& name) {
  TransferFunction tf;
  tf.source = name;
  // The CT head's numbers (histogram): air 0-100, soft tissue 900-1100, bone 1500-2300.
  if (name == "ct-bone")
    tf.points = {{0, 0, 0, 0, 0}, {1250, 0.90f, 0.85f, 0.75f, 0}, {1600, 0.95f, 0.90f, 0.80f, 0.4f},
                 {2200, 1, 0.97f, 0.92f, 0.9f}, {3272, 1, 1, 1, 0.95f}};
  else if (name == "ct-skin")
    tf.points = {{0, 0, 0, 0, 0},
                 {400, 0.90f, 0.60f, 0.50f, 0},
                 {700, 0.90f, 0.60f, 0.50f, 0.12f},
                 {950, 0.90f, 0.65f, 0.55f, 0},
                 {1250, 0.90f, 0.85f, 0.75f, 0},
                 {1600, 0.95f, 0.90f, 0.80f, 0.4f},
                 {2200, 1, 0.97f, 0.92f, 0.9f},
                 {3272, 1, 1, 1, 0.95f}};
  else if (name == "mri")
    tf.points = {{0, 0, 0, 0, 0}, {60, 0.8f, 0.6f, 0.5f, 0}, {90, 0.85f, 0.65f, 0.55f, 0.03f},
                 {130, 0.95f, 0.95f, 0.9f, 0.08f}, {255, 1, 1, 1, 0.3f}};
  else if (name == "ramp")
    tf.points = {{0, 1, 1, 1, 0}, {1, 1, 1, 1, 1}};
  return tf;
}

// One number, all of the word, finite.
bool number(const std::string& w, double& out) {
  if (w.empty()) return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtod(w.c_str(), &end);
  return end == w.c_str() + w.size() && errno != ERANGE && std::isfinite(out);
}

}  // namespace

TransferFunction parse_transfer_function(const std::string& text, const std::string& source) {
  TransferFunction tf;
  tf.source = source;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  int prev_line = 0;
  while (std::getline(in, line)) {
    ++line_no;
    auto fail = [&](const std::string& what) { throw InputError(source, line_no, what); };
    if (line.find('\0') != std::string::npos) fail("binary data (NUL byte) in a transfer function");
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string s; words >> s;) w.push_back(s);
    if (w.empty()) continue;
    if (w.size() != 5)
      fail("a control point is five numbers: value r g b alpha (got " + std::to_string(w.size()) + " words)");
    double x[5];
    static const char* const kNames[5] = {"value", "r", "g", "b", "alpha"};
    for (int k = 0; k < 5; ++k)
      if (!number(w[size_t(k)], x[k])) fail(std::string(kNames[k]) + " is not a finite number: '" + w[size_t(k)] + "'");
    for (int k = 1; k < 5; ++k)
      if (x[k] < 0 || x[k] > 1) fail(std::string(kNames[k]) + " must lie in [0, 1], got " + w[size_t(k)]);
    if (!tf.points.empty() && !(x[0] > tf.points.back().value))
      fail("values must increase: " + w[0] + " is not above the value on line " + std::to_string(prev_line));
    if (tf.points.size() == size_t(kMaxControlPoints))
      fail("more than " + std::to_string(kMaxControlPoints) + " control points");
    tf.points.push_back({x[0], float(x[1]), float(x[2]), float(x[3]), float(x[4])});
    prev_line = line_no;
  }
  if (tf.points.empty()) throw InputError(source, 0, "no control points (lines of: value r g b alpha)");
  return tf;
}

TransferFunction read_transfer_function(const std::string& spec) {
  TransferFunction p = preset(spec);
  if (!p.points.empty()) return p;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(spec, ec))
    throw InputError(spec, 0,
                     std::string("not a transfer function preset (") + transfer_presets() + ") nor a readable .tf file");
  const auto size = std::filesystem::file_size(spec, ec);
  if (ec || size > (uintmax_t(1) << 20)) throw InputError(spec, 0, "unreadable or too large for a .tf file (over 1 MiB)");
  std::ifstream f(spec, std::ios::binary);
  if (!f) throw InputError(spec, 0, "cannot open");
  std::ostringstream text;
  text << f.rdbuf();
  return parse_transfer_function(text.str(), spec);
}

}  // namespace lockstep
