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
