// lockstep io: analytic fields (.field files) sampled to volumes (io/volume_io.h).
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <mutex>
#include <numbers>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.h"
#include "io/text.h"
#include "io/tokenizer.h"
#include "io/volume_io.h"

namespace lockstep {

namespace {

using namespace text;

// ------------------------------------------------------------------ analytic fields

// Coordinates and parameters beyond this are absurd (and their sines are noise).
constexpr double kMaxFieldCoordinate = 1e6;

bool valid_parameters(const FieldSpec& f, std::string& why) {
  auto bad = [&](const std::string& w) {
    why = w;
    return false;
  };
  if (f.n < 2 || f.n > kMaxFieldSize)
    return bad("size " + std::to_string(f.n) + " is out of range (2 .. " + std::to_string(kMaxFieldSize) + ")");
  if (!std::isfinite(f.lo) || !std::isfinite(f.hi) || !(f.lo < f.hi) || !std::isfinite(f.hi - f.lo))
    return bad("bounds must be finite with LO < HI");
  if (std::abs(f.lo) > kMaxFieldCoordinate || std::abs(f.hi) > kMaxFieldCoordinate)
    return bad("bounds must lie within [-1e6, 1e6]");
  if (!std::isfinite(f.a) || !std::isfinite(f.b)) return bad("parameters must be finite");
  if (std::abs(f.a) > kMaxFieldCoordinate || std::abs(f.b) > kMaxFieldCoordinate)
    return bad("parameters must lie within [-1e6, 1e6]");
  switch (f.kind) {
    case FieldKind::kSphere:
      if (!(f.a > 0)) return bad("sphere radius must be > 0");
      break;
    case FieldKind::kTorus:
      if (!(f.a > 0 && f.b > 0)) return bad("torus radii must be > 0");
      break;
    case FieldKind::kGyroid:
      if (!(f.a > 0)) return bad("gyroid periods must be > 0");
      break;
    case FieldKind::kMarschnerLobb:
      if (!(f.a >= 0)) return bad("marschner_lobb alpha must be >= 0");
      if (!(f.b > 0)) return bad("marschner_lobb fm must be > 0");
      break;
  }
  return true;
}


}  // namespace

const char* field_name(FieldKind kind) {
  switch (kind) {
    case FieldKind::kSphere:
      return "sphere";
    case FieldKind::kTorus:
      return "torus";
    case FieldKind::kGyroid:
      return "gyroid";
    case FieldKind::kMarschnerLobb:
      return "marschner_lobb";
  }
  return "?";
}

FieldSpec field_defaults(FieldKind kind) {
  FieldSpec f;
  f.kind = kind;
  switch (kind) {
    case FieldKind::kSphere:
      f.a = 0.5;
      break;
    case FieldKind::kTorus:
      f.a = 0.5, f.b = 0.25;
      break;
    case FieldKind::kGyroid:
      f.a = 2;
      break;
    case FieldKind::kMarschnerLobb:
      f.a = 0.25, f.b = 6;
      break;
  }
  return f;
}

double natural_iso(const FieldSpec& f) {
  switch (f.kind) {
    case FieldKind::kSphere:
      return f.a;
    case FieldKind::kTorus:
      return f.b;
    case FieldKind::kGyroid:
      return 0;
    case FieldKind::kMarschnerLobb:
      return 0.5;
  }
  return 0;
}

double field_value(const FieldSpec& f, const Vec3& p) {
  constexpr double pi = std::numbers::pi;
  switch (f.kind) {
    case FieldKind::kSphere:
      return std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
    case FieldKind::kTorus: {
      const double q = std::sqrt(p.x * p.x + p.y * p.y) - f.a;
      return std::sqrt(q * q + p.z * p.z);
    }
    case FieldKind::kGyroid: {
      const double k = 2 * pi * f.a / (f.hi - f.lo);
      const double x = k * p.x, y = k * p.y, z = k * p.z;
      return std::sin(x) * std::cos(y) + std::sin(y) * std::cos(z) + std::sin(z) * std::cos(x);
    }
    case FieldKind::kMarschnerLobb: {
      const double alpha = f.a, fm = f.b;
      const double r = std::sqrt(p.x * p.x + p.y * p.y);
      const double rho_r = std::cos(2 * pi * fm * std::cos(pi * r / 2));
      return (1 - std::sin(pi * p.z / 2) + alpha * (1 + rho_r)) / (2 * (1 + alpha));
    }
  }
  return 0;
}

Volume sample_field(const FieldSpec& f, std::string source) {
  std::string why;
  if (!valid_parameters(f, why)) throw InputError(source, 0, why);
  Volume v;
  v.nx = v.ny = v.nz = f.n;
  const double step = (f.hi - f.lo) / (f.n - 1);
  v.spacing = {step, step, step};
  v.origin = {f.lo, f.lo, f.lo};
  v.source = std::move(source);
  std::vector<double> coord(size_t(f.n));
  for (int i = 0; i < f.n; ++i) coord[size_t(i)] = i == f.n - 1 ? f.hi : f.lo + (f.hi - f.lo) * i / (f.n - 1);
  v.data.resize(size_t(f.n) * size_t(f.n) * size_t(f.n));
  for (int k = 0; k < f.n; ++k)
    for (int j = 0; j < f.n; ++j)
      for (int i = 0; i < f.n; ++i) {
        const Vec3 p{coord[size_t(i)], coord[size_t(j)], coord[size_t(k)]};
        const float x = float(field_value(f, p));
        if (!std::isfinite(x)) {
          char at[96];
          std::snprintf(at, sizeof at, "(%g, %g, %g)", p.x, p.y, p.z);
          throw InputError(v.source, 0,
                           std::string("the field is not finite at ") + at + " (sample (" + std::to_string(i) + ", " +
                               std::to_string(j) + ", " + std::to_string(k) + "))");
        }
        v.at(i, j, k) = x;
      }
  return v;
}

FieldSpec read_field_spec(const std::string& path) {
  const size_t size = regular_file_size(path, path, 0, "file");
  if (size == 0) throw InputError(path, 0, "file is empty");
  if (size > (size_t(1) << 20)) throw InputError(path, 0, "too large for a .field file (over 1 MiB)");
  const std::string text = read_prefix(path, size);

  struct Entry {
    int line = 0;
    std::vector<double> values;
  };
  int field_line = 0;
  FieldKind kind = FieldKind::kSphere;
  Entry size_e, bounds, radius, radii, periods, alpha, fm;
  const struct {
    const char* key;
    Entry* entry;
    size_t count;
  } keys[] = {{"size", &size_e, 1},     {"bounds", &bounds, 2}, {"radius", &radius, 1}, {"radii", &radii, 2},
              {"periods", &periods, 1}, {"alpha", &alpha, 1},   {"fm", &fm, 1}};

  Tokenizer in(text, path, {.comments = Comments::anywhere});
  while (in.next()) {
    const int line_no = in.line_no();
    const auto& w = in.words();
    const std::string key(w[0]);
    auto fail = [&](const std::string& what) -> void { in.fail(what); };
    if (key == "field") {
      if (field_line) fail("a second 'field' line (the first is on line " + std::to_string(field_line) + ")");
      if (w.size() != 2) fail("'field' takes one name: sphere, torus, gyroid or marschner_lobb");
      if (w[1] == "sphere")
        kind = FieldKind::kSphere;
      else if (w[1] == "torus")
        kind = FieldKind::kTorus;
      else if (w[1] == "gyroid")
        kind = FieldKind::kGyroid;
      else if (w[1] == "marschner_lobb")
        kind = FieldKind::kMarschnerLobb;
      else
        fail("unknown field " + quoted(w[1]) + " (sphere, torus, gyroid or marschner_lobb)");
      field_line = line_no;
      continue;
    }
    const auto* k = std::find_if(std::begin(keys), std::end(keys), [&](const auto& e) { return key == e.key; });
    if (k == std::end(keys))
      fail("unknown key " + quoted(key) + " (field, size, bounds, radius, radii, periods, alpha, fm)");
    if (k->entry->line)
      fail("a second '" + key + "' line (the first is on line " + std::to_string(k->entry->line) + ")");
    if (w.size() != k->count + 1)
      fail("'" + key + "' takes " + std::to_string(k->count) + " value(s), got " + std::to_string(w.size() - 1));
    k->entry->line = line_no;
    for (size_t i = 1; i < w.size(); ++i) {
      double x = 0;
      if (!parse_double(w[i], x)) fail("not a number: " + quoted(w[i]));
      if (!std::isfinite(x)) fail("number out of range (NaN, Inf or overflow): " + quoted(w[i]));
      k->entry->values.push_back(x);
    }
  }
  if (!field_line) throw InputError(path, 0, "no 'field' line (field sphere|torus|gyroid|marschner_lobb)");

  FieldSpec f = field_defaults(kind);
  auto fail_at = [&](int line, const std::string& what) { throw InputError(path, line, what); };
  // Keys of another kind.
  const struct {
    Entry* entry;
    const char* key;
    FieldKind kind;
  } own[] = {{&radius, "radius", FieldKind::kSphere},
             {&radii, "radii", FieldKind::kTorus},
             {&periods, "periods", FieldKind::kGyroid},
             {&alpha, "alpha", FieldKind::kMarschnerLobb},
             {&fm, "fm", FieldKind::kMarschnerLobb}};
  for (const auto& o : own)
    if (o.entry->line && o.kind != kind)
      fail_at(o.entry->line,
              std::string("'") + o.key + "' is for " + field_name(o.kind) + " fields, not " + field_name(kind));
  if (size_e.line) {
    const double n = size_e.values[0];
    if (!(n == std::floor(n)) || n < 2 || n > kMaxFieldSize) {
      char b[32];
      std::snprintf(b, sizeof b, "%g", n);
      fail_at(size_e.line,
              std::string("size ") + b + " is out of range (an integer, 2 .. " + std::to_string(kMaxFieldSize) + ")");
    }
    f.n = int(n);
  }
  if (bounds.line) {
    f.lo = bounds.values[0];
    f.hi = bounds.values[1];
    if (!(f.lo < f.hi) || !std::isfinite(f.hi - f.lo)) fail_at(bounds.line, "bounds: LO must be less than HI");
    if (std::abs(f.lo) > kMaxFieldCoordinate || std::abs(f.hi) > kMaxFieldCoordinate)
      fail_at(bounds.line, "bounds must lie within [-1e6, 1e6]");
  }
  if (radius.line) f.a = radius.values[0];
  if (radii.line) f.a = radii.values[0], f.b = radii.values[1];
  if (periods.line) f.a = periods.values[0];
  if (alpha.line) f.a = alpha.values[0];
  if (fm.line) f.b = fm.values[0];
  std::string why;
  if (!valid_parameters(f, why)) {
    const int line = std::max({radius.line, radii.line, periods.line, alpha.line, fm.line});
    fail_at(line, why);
  }
  return f;
}

}  // namespace lockstep
