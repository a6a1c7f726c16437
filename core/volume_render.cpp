// lockstep core: the volume-rendering contract (see core/volume_render.h).
#include "core/volume_render.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include "core/error.h"

namespace lockstep::vr {

// ---------------------------------------------------------------- settings

std::vector<ParamSpec> params(Mode mode) {
  std::vector<ParamSpec> p;
  if (mode == Mode::kIso) {
    p.push_back({"iso", "a finite number", "", "the iso value: the surface where the interpolant equals it (required)"});
    p.push_back({"tf", "PRESET|FILE.tf", "", "a transfer function: the surface takes its colour at iso (else grey)"});
  } else {
    p.push_back({"tf", "PRESET|FILE.tf", "",
                 "the transfer function (required): a preset (ct-bone, ct-skin, mri, ramp) or a .tf file"});
  }
  if (mode != Mode::kSplat) p.push_back({"step", "DT in (0, 16]", "0.5", "the sampling step along a ray, in voxels"});
  if (mode == Mode::kRaycast)
    p.push_back({"error", "E in (0, 1]", "",
                 "instead of step and eps: the largest step, then eps, whose measured mean error per channel "
                 "over the covered pixels, against step 1/16 without early termination, is at most E"});
  p.push_back({"view", "AZ,EL[,ROLL]", "30,20,0",
               "the camera's azimuth about z, elevation and roll about the view, in degrees (parallel projection)"});
  if (mode != Mode::kIso) {
    p.push_back({"eps", "E in [0, 0.5]", "0.00390625", "a ray stops once its opacity reaches 1 - E (0: never)"});
    p.push_back({"noskip", "", "", "implementations that skip empty space must not (the check that skipping changes nothing)",
                 true});
  }
  return p;
}

namespace {

double number(const std::string& name, const std::string& v, const std::string& source) {
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(v.c_str(), &end);
  if (v.empty() || end != v.c_str() + v.size() || errno == ERANGE || !std::isfinite(x))
    throw InputError(source, 0, name + " must be a finite number, got '" + v + "'");
  return x;
}

}  // namespace

Settings settings(const Params& p, const std::string& source, Mode mode) {
  Settings s;
  const auto specs = params(mode);
  for (const auto& [name, value] : p.items) {
    const bool known = std::any_of(specs.begin(), specs.end(), [&](const ParamSpec& q) { return q.name == name; });
    if (!known) {
      std::string names;
      for (const ParamSpec& q : specs) names += (names.empty() ? "" : ", ") + std::string(q.name);
      throw InputError(source, 0, "volume rendering has no setting '" + name + "' (it takes " + names + ")");
    }
  }
  if (const std::string tf = p.get("tf"); !tf.empty()) {
    s.tf = read_transfer_function(tf);
    s.has_tf = true;
  } else if (mode != Mode::kIso) {
    throw InputError(source, 0, std::string("volume rendering needs tf=PRESET|FILE.tf (presets: ") +
                                    transfer_presets() + ")");
  }
  if (mode == Mode::kIso) {
    const std::string iso = p.get("iso");
    if (iso.empty()) throw InputError(source, 0, "the isosurface needs iso=VALUE (the iso value)");
    s.iso = number("iso", iso, source);
  }
  if (const std::string v = p.get("step"); !v.empty()) {
    s.step = number("step", v, source);
    if (!(s.step > 0 && s.step <= 16)) throw InputError(source, 0, "step must lie in (0, 16] voxels, got " + v);
    // Below this a 512^2 frame of a 256^3 volume would take 10^11 samples.
    if (s.step < 1.0 / 64) throw InputError(source, 0, "step " + v + " is absurdly small (at least 1/64 of a voxel)");
  }
  if (const std::string v = p.get("view"); !v.empty()) {
    const size_t c1 = v.find(','), c2 = c1 == std::string::npos ? c1 : v.find(',', c1 + 1);
    if (c1 == std::string::npos) throw InputError(source, 0, "view is AZ,EL[,ROLL] in degrees, got '" + v + "'");
    s.azimuth = number("view's azimuth", v.substr(0, c1), source);
    s.elevation = number("view's elevation", v.substr(c1 + 1, c2 == std::string::npos ? c2 : c2 - c1 - 1), source);
    if (c2 != std::string::npos) s.roll = number("view's roll", v.substr(c2 + 1), source);
    if (std::abs(s.azimuth) > 3600 || std::abs(s.elevation) > 90 || std::abs(s.roll) > 3600)
      throw InputError(source, 0,
                       "view: the azimuth and roll lie in [-3600, 3600], the elevation in [-90, 90], got '" + v + "'");
  }
  if (const std::string v = p.get("eps"); !v.empty()) {
    s.eps = number("eps", v, source);
    if (!(s.eps >= 0 && s.eps <= 0.5)) throw InputError(source, 0, "eps must lie in [0, 0.5], got " + v);
  }
  if (const std::string v = p.get("error"); !v.empty()) {
    s.error = number("error", v, source);
    if (!(s.error > 0 && s.error <= 1)) throw InputError(source, 0, "error must lie in (0, 1], got " + v);
    if (!p.get("step").empty()) throw InputError(source, 0, "give step or error, not both");
    if (!p.get("eps").empty())
      throw InputError(source, 0, "give eps or error, not both (error chooses the step and eps)");
  }
  s.skip = p.get("noskip").empty() || p.get("noskip") == "0";
  return s;
}

// ---------------------------------------------------------------- the view

View make_view(const Volume& v, const Settings& s, int width, int height) {
  View view;
  view.width = width;
  view.height = height;
  view.lo = v.origin;
  view.hi = v.position(v.nx - 1, v.ny - 1, v.nz - 1);
  const Vec3 centre = 0.5 * (view.lo + view.hi);
  const double radius = std::max(0.5 * length(view.hi - view.lo), 1e-12);

  // The camera sits along `toward` (from the centre), looking back.
  const double az = s.azimuth * std::numbers::pi / 180, el = s.elevation * std::numbers::pi / 180;
  const Vec3 toward{std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
  view.dir = -toward;
  // Image up: world z projected; looking (almost) along z, world y.
  Vec3 right = cross(view.dir, Vec3{0, 0, 1});
  if (length(right) < 1e-6) right = cross(view.dir, Vec3{0, 1, 0});
  right = normalize(right);
  Vec3 up = cross(right, view.dir);
  // Roll turns the image about the viewing direction (counter-clockwise as seen).
  const double roll = s.roll * std::numbers::pi / 180;
  const Vec3 rolled = std::cos(roll) * right + std::sin(roll) * up;
  up = cross(rolled, view.dir);
  right = rolled;

  // The shorter side spans the bounding sphere's diameter.
  const double pixel = 2 * radius / std::min(width, height);
  view.du = pixel * right;
  view.dv = -pixel * up;
  // The start plane lies just outside the bounding sphere.
  const Vec3 start = centre - 1.001 * radius * view.dir;
  view.corner = start - (0.5 * width) * view.du - (0.5 * height) * view.dv;

  const double h = std::min({v.spacing.x, v.spacing.y, v.spacing.z});
  view.dt = s.step * h;
  view.ratio = s.step;
  return view;
}

void ray_samples(const View& view, const Vec3& o, long& k0, long& k1) {
  double t0 = 0, t1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (view.dir[a] == 0) {
      if (o[a] < view.lo[a] || o[a] > view.hi[a]) t0 = t1 + 1;  // parallel to the slab and outside it
      continue;
    }
    double ta = (view.lo[a] - o[a]) / view.dir[a], tb = (view.hi[a] - o[a]) / view.dir[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (!(t0 <= t1)) {
    k0 = 1;
    k1 = 0;
    return;
  }
  k0 = long(std::ceil(t0 / view.dt));
  k1 = long(std::floor(t1 / view.dt));
}

// ---------------------------------------------------------------- sampling

namespace {

// The cell along one axis holding grid coordinate g (clamped to the box), and
// the fraction across it.
inline void cell(double g, int n, int& i, double& f) {
  g = std::clamp(g, 0.0, double(n - 1));
  i = std::min(int(g), n - 2);
  f = g - i;
}

// Central difference at sample (i, j, k) (one-sided at the border).
Vec3 sample_gradient(const Volume& v, int i, int j, int k) {
  auto diff = [&](int n, int c, auto at) {
    const int a = std::max(c - 1, 0), b = std::min(c + 1, n - 1);
    return (at(b) - at(a)) / double(b - a);
  };
  return {diff(v.nx, i, [&](int x) { return double(v.at(x, j, k)); }) / v.spacing.x,
          diff(v.ny, j, [&](int y) { return double(v.at(i, y, k)); }) / v.spacing.y,
          diff(v.nz, k, [&](int z) { return double(v.at(i, j, z)); }) / v.spacing.z};
}

}  // namespace

double trilinear(const Volume& v, const Vec3& p) {
  int i, j, k;
  double fx, fy, fz;
  cell((p.x - v.origin.x) / v.spacing.x, v.nx, i, fx);
  cell((p.y - v.origin.y) / v.spacing.y, v.ny, j, fy);
  cell((p.z - v.origin.z) / v.spacing.z, v.nz, k, fz);
  // Along x on the cell's four x edges, then along y, then along z.
  auto lerp = [](double a, double b, double t) { return a + t * (b - a); };
  const double c00 = lerp(v.at(i, j, k), v.at(i + 1, j, k), fx);
  const double c10 = lerp(v.at(i, j + 1, k), v.at(i + 1, j + 1, k), fx);
  const double c01 = lerp(v.at(i, j, k + 1), v.at(i + 1, j, k + 1), fx);
  const double c11 = lerp(v.at(i, j + 1, k + 1), v.at(i + 1, j + 1, k + 1), fx);
  return lerp(lerp(c00, c10, fy), lerp(c01, c11, fy), fz);
}

Vec3 gradient(const Volume& v, const Vec3& p) {
  int i, j, k;
  double fx, fy, fz;
  cell((p.x - v.origin.x) / v.spacing.x, v.nx, i, fx);
  cell((p.y - v.origin.y) / v.spacing.y, v.ny, j, fy);
  cell((p.z - v.origin.z) / v.spacing.z, v.nz, k, fz);
  Vec3 g{0, 0, 0};
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    const double w = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy) * (dz ? fz : 1 - fz);
    g += w * sample_gradient(v, i + dx, j + dy, k + dz);
  }
  return g;
}

Vec3 iso_shade(const Vec3& base, const Vec3& grad, const Vec3& dir) {
  const double len = length(grad);
  const double diffuse = len > 0 ? std::abs(dot(grad, dir)) / len : 0.0;
  return (0.2 + 0.8 * diffuse) * base;
}

Vec3 iso_base(const Settings& s) {
  if (!s.has_tf) return {0.85, 0.85, 0.85};
  double rgba[4];
  s.tf.eval(s.iso, rgba);
  return {rgba[0], rgba[1], rgba[2]};
}

std::string empty_note(const Volume& v, double iso) {
  if (v.data.empty()) return "the volume has no samples: the image is empty";
  const auto [lo, hi] = std::minmax_element(v.data.begin(), v.data.end());
  if (iso >= double(*lo) && iso <= double(*hi)) return {};
  char buf[200];
  std::snprintf(buf, sizeof buf, "iso %g is outside the volume's values [%g, %g]: no surface, the image is empty", iso,
                double(*lo), double(*hi));
  return buf;
}

// ---------------------------------------------------------------- error=E

CoveredError covered_error(const Image& image, const Image& converged) {
  CoveredError e;
  double sum = 0;
  const size_t n = std::min(image.rgba.size(), converged.rgba.size());
  for (size_t i = 0; i < n; i += 4) {
    e.covered += converged.rgba[i + 3] > 0;
    for (size_t c = 0; c < 4; ++c) sum += std::abs(double(image.rgba[i + c]) - double(converged.rgba[i + c]));
  }
  e.mean = sum / (4.0 * double(std::max<uint64_t>(e.covered, 1)));
  return e;
}

ErrorChoice choose_for_error(double target, const std::function<Image(double step, double eps)>& render) {
  const Image converged = render(kConvergedStep, 0);
  ErrorChoice best;
  for (const double step : kErrorSteps) {
    Image full = render(step, 0);
    const CoveredError e = covered_error(full, converged);
    if (e.mean > target) {
      // Not met: kept as the best achievable so far (the steps go finer).
      if (best.image.rgba.empty() || e.mean <= best.error.mean) {
        best.step = step;
        best.eps = 0;
        best.error = e;
        best.image = std::move(full);
      }
      continue;
    }
    for (const double eps : kErrorEps) {
      Image img = render(step, eps);
      const CoveredError t = covered_error(img, converged);
      if (t.mean <= target) return ErrorChoice{true, step, eps, t, std::move(img)};
    }
    return ErrorChoice{true, step, 0, e, std::move(full)};
  }
  return best;
}

std::string fraction_text(double x) {
  char buf[40];
  if (x > 0 && x < 1) {
    const double inv = 1 / x;
    if (inv == std::round(inv) && inv < 1e9) {
      std::snprintf(buf, sizeof buf, "1/%.0f", inv);
      return buf;
    }
  }
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

}  // namespace lockstep::vr
