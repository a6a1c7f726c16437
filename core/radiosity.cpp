// lockstep core: radiosity's shared definitions (core/radiosity.h).
#include "core/radiosity.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace lockstep {

namespace {

constexpr double kPi = std::numbers::pi;

// The polygon's part where dot(n, p - x) >= 0 (Sutherland-Hodgman, one plane).
std::vector<Vec3> clip_in_front(std::span<const Vec3> poly, const Vec3& x, const Vec3& n) {
  std::vector<Vec3> out;
  const size_t k = poly.size();
  for (size_t i = 0; i < k; ++i) {
    const Vec3& a = poly[i];
    const Vec3& b = poly[(i + 1) % k];
    const double da = dot(n, a - x), db = dot(n, b - x);
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

// Twice the vector area of a polygon (its normal times twice its area).
Vec3 vector_area2(std::span<const Vec3> p) {
  Vec3 s{0, 0, 0};
  for (size_t i = 1; i + 1 < p.size(); ++i) s = s + cross(p[i] - p[0], p[i + 1] - p[0]);
  return s;
}

}  // namespace

Vec3 Patch::normal() const { return normalize(vector_area2(corners())); }

double Patch::area() const { return 0.5 * length(vector_area2(corners())); }

Vec3 Patch::centre() const {
  // The area-weighted centroids of the fan's triangles.
  Vec3 c{0, 0, 0};
  double total = 0;
  for (int i = 1; i + 1 < count; ++i) {
    const double a = 0.5 * length(cross(v[i] - v[0], v[i + 1] - v[0]));
    c = c + (v[0] + v[i] + v[i + 1]) * (a / 3);
    total += a;
  }
  return total > 0 ? c / total : v[0];
}

double point_polygon_form_factor(const Vec3& x, const Vec3& n, std::span<const Vec3> polygon) {
  const std::vector<Vec3> p = clip_in_front(polygon, x, n);
  if (p.size() < 3) return 0;
  // F = 1/(2 pi) sum_i gamma_i n . u_i: gamma_i the angle the edge (p_i,
  // p_i+1) subtends at x, u_i the unit normal of the plane through x and the
  // edge. The sign follows the winding as seen from x: the magnitude is F.
  double sum = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Vec3 r0 = p[i] - x, r1 = p[(i + 1) % p.size()] - x;
    const Vec3 c = cross(r0, r1);
    const double len = length(c);
    if (!(len > 0)) continue;  // an edge through x's line of sight: no area
    const double gamma = std::atan2(len, dot(r0, r1));
    sum += gamma * dot(n, c) / len;
  }
  return std::abs(sum) / (2 * kPi);
}

double patch_form_factor(const Patch& from, const Patch& to, int n) {
  const Vec3 nf = from.normal();
  const double area = from.area();
  if (!(area > 0) || n < 1) return 0;
  double sum = 0;
  if (from.count == 4) {
    // P(s, t) bilinear over the quad; dA = |dP/ds x dP/dt| ds dt.
    const Vec3* v = from.v;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double s = (i + 0.5) / n, t = (j + 0.5) / n;
        const Vec3 p = v[0] * ((1 - s) * (1 - t)) + v[1] * (s * (1 - t)) + v[2] * (s * t) +
                       v[3] * ((1 - s) * t);
        const Vec3 ds = (v[1] - v[0]) * (1 - t) + (v[2] - v[3]) * t;
        const Vec3 dt = (v[3] - v[0]) * (1 - s) + (v[2] - v[1]) * s;
        sum += point_polygon_form_factor(p, nf, to.corners()) * length(cross(ds, dt)) / (n * n);
      }
    return sum / area;
  }
  // A triangle: n^2 congruent triangles (n(n+1)/2 upright, n(n-1)/2 upside
  // down), each at its centroid, each a 1/n^2 of the area.
  const Vec3 e1 = (from.v[1] - from.v[0]) / double(n), e2 = (from.v[2] - from.v[0]) / double(n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i + j < n; ++i) {
      const Vec3 base = from.v[0] + e1 * double(i) + e2 * double(j);
      sum += point_polygon_form_factor(base + (e1 + e2) / 3.0, nf, to.corners());
      if (i + j + 1 < n)
        sum += point_polygon_form_factor(base + (e1 + e2) * (2.0 / 3), nf, to.corners());
    }
  return sum / (n * n);
}

double parallel_rectangles_form_factor(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double x2 = x * x, y2 = y * y;
  const double sx = std::sqrt(1 + x2), sy = std::sqrt(1 + y2);
  return 2 / (kPi * x * y) *
         (0.5 * std::log((1 + x2) * (1 + y2) / (1 + x2 + y2)) + x * sy * std::atan(x / sy) +
          y * sx * std::atan(y / sx) - x * std::atan(x) - y * std::atan(y));
}

double perpendicular_rectangles_form_factor(double l, double w, double h) {
  const double W = w / l, H = h / l;
  const double w2 = W * W, h2 = H * H, s = std::sqrt(w2 + h2);
  const double log_term = std::log((1 + w2) * (1 + h2) / (1 + w2 + h2)) +
                          w2 * std::log(w2 * (1 + w2 + h2) / ((1 + w2) * (w2 + h2))) +
                          h2 * std::log(h2 * (1 + h2 + w2) / ((1 + h2) * (h2 + w2)));
  return (W * std::atan(1 / W) + H * std::atan(1 / H) - s * std::atan(1 / s) + 0.25 * log_term) /
         (kPi * W);
}

double point_rectangle_corner_form_factor(double a, double b, double c) {
  const double A = a / c, B = b / c;
  const double sa = std::sqrt(1 + A * A), sb = std::sqrt(1 + B * B);
  return (A / sa * std::atan(B / sa) + B / sb * std::atan(A / sb)) / (2 * kPi);
}

std::vector<Patch> mesh_polygon(std::span<const Vec3> polygon, const Vec3& rho,
                                const Vec3& emission, double max_area, int polygon_index) {
  if (polygon.size() != 3 && polygon.size() != 4)
    throw std::invalid_argument("mesh_polygon: a patch has 3 or 4 corners");
  if (!(max_area > 0))
    throw std::invalid_argument("mesh_polygon: the largest patch area must be positive");
  std::vector<Patch> out;
  auto add = [&](std::initializer_list<Vec3> corners) {
    Patch p;
    p.count = int(corners.size());
    std::copy(corners.begin(), corners.end(), p.v);
    p.rho = rho;
    p.emission = emission;
    p.polygon = polygon_index;
    out.push_back(p);
  };
  const double area = 0.5 * length(vector_area2(polygon));
  if (polygon.size() == 4) {
    // Pieces about square: counts in proportion to the sides' lengths.
    const double side = std::sqrt(max_area);
    int nu = std::max(1, int(std::ceil(length(polygon[1] - polygon[0]) / side)));
    int nv = std::max(1, int(std::ceil(length(polygon[3] - polygon[0]) / side)));
    while (area / (double(nu) * nv) > max_area) (nu <= nv ? nu : nv) += 1;
    auto at = [&](int i, int j) {
      const double s = double(i) / nu, t = double(j) / nv;
      return polygon[0] * ((1 - s) * (1 - t)) + polygon[1] * (s * (1 - t)) + polygon[2] * (s * t) +
             polygon[3] * ((1 - s) * t);
    };
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) add({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
    return out;
  }
  // A triangle: halve the edges until the pieces are small enough.
  std::vector<std::array<Vec3, 3>> tris{{polygon[0], polygon[1], polygon[2]}};
  for (double a = area; a > max_area; a /= 4) {
    std::vector<std::array<Vec3, 3>> next;
    for (const auto& t : tris) {
      const Vec3 m01 = (t[0] + t[1]) / 2.0, m12 = (t[1] + t[2]) / 2.0, m20 = (t[2] + t[0]) / 2.0;
      next.push_back({t[0], m01, m20});
      next.push_back({m01, t[1], m12});
      next.push_back({m20, m12, t[2]});
      next.push_back({m01, m12, m20});
    }
    tris.swap(next);
  }
  for (const auto& t : tris) add({t[0], t[1], t[2]});
  return out;
}

double radiosity_residual(const std::vector<Patch>& patches, const std::vector<double>& f,
                          const std::vector<Vec3>& b) {
  const size_t n = patches.size();
  double worst = 0;
  for (size_t i = 0; i < n; ++i) {
    Vec3 gathered{0, 0, 0};
    for (size_t j = 0; j < n; ++j) gathered = gathered + b[j] * f[i * n + j];
    const Vec3 r = b[i] - patches[i].emission - mul(patches[i].rho, gathered);
    worst = std::max({worst, std::abs(r.x), std::abs(r.y), std::abs(r.z)});
  }
  return worst;
}

SolveResult solve_radiosity(const std::vector<Patch>& patches, const std::vector<double>& f,
                            RadiositySolver solver, double tolerance, int max_iterations) {
  const size_t n = patches.size();
  if (f.size() != n * n)
    throw std::invalid_argument("solve_radiosity: the form factor matrix is not n x n");
  double e_max = 0;
  for (const Patch& p : patches) {
    for (double r : {p.rho.x, p.rho.y, p.rho.z})
      if (!(r >= 0 && r < 1))
        throw std::invalid_argument("reflectance " + std::to_string(r) +
                                    " is not in [0, 1): B = E + rho F B need not converge");
    for (double e : {p.emission.x, p.emission.y, p.emission.z}) {
      if (!(e >= 0 && std::isfinite(e)))
        throw std::invalid_argument("emission " + std::to_string(e) + " is not finite and >= 0");
      e_max = std::max(e_max, e);
    }
  }
  SolveResult out;
  out.b.resize(n);
  for (size_t i = 0; i < n; ++i) out.b[i] = patches[i].emission;
  const double goal = tolerance * e_max;
  auto gather = [&](size_t i, const std::vector<Vec3>& b) {
    Vec3 g{0, 0, 0};
    for (size_t j = 0; j < n; ++j) g = g + b[j] * f[i * n + j];
    return patches[i].emission + mul(patches[i].rho, g);
  };
  switch (solver) {
    case RadiositySolver::jacobi:
    case RadiositySolver::gauss_seidel: {
      // Jacobi: every B_i from the last sweep's B. Gauss-Seidel: from the
      // newest values, this sweep's where already computed.
      std::vector<Vec3> next = out.b;
      while (out.iterations < max_iterations) {
        out.residual = radiosity_residual(patches, f, out.b);
        if (out.residual <= goal) break;
        for (size_t i = 0; i < n; ++i) {
          if (solver == RadiositySolver::jacobi)
            next[i] = gather(i, out.b);
          else
            out.b[i] = gather(i, out.b);
        }
        if (solver == RadiositySolver::jacobi) out.b.swap(next);
        ++out.iterations;
      }
      break;
    }
    case RadiositySolver::progressive: {
      // Cohen, Chen, Wallace and Greenberg (1988): shoot the patch with the
      // most unshot energy; what j receives from i is rho_j dB_i F_ji, with
      // F_ji = F_ij A_i / A_j by reciprocity (row i of F: i's view).
      std::vector<Vec3> unshot = out.b;
      std::vector<double> area(n);
      double emitted = 0;
      for (size_t i = 0; i < n; ++i) {
        area[i] = patches[i].area();
        emitted += (unshot[i].x + unshot[i].y + unshot[i].z) * area[i];
      }
      while (out.iterations < max_iterations) {
        size_t best = 0;
        double most = -1;
        for (size_t i = 0; i < n; ++i) {
          const double e = (unshot[i].x + unshot[i].y + unshot[i].z) * area[i];
          if (e > most) most = e, best = i;
        }
        if (!(most > tolerance * emitted)) break;
        const Vec3 shot = unshot[best];
        unshot[best] = Vec3{0, 0, 0};
        for (size_t j = 0; j < n; ++j) {
          if (j == best || !(area[j] > 0)) continue;
          const Vec3 got = mul(patches[j].rho, shot) * (f[best * n + j] * area[best] / area[j]);
          out.b[j] = out.b[j] + got;
          unshot[j] = unshot[j] + got;
        }
        ++out.iterations;
      }
      out.residual = radiosity_residual(patches, f, out.b);
      break;
    }
  }
  return out;
}

}  // namespace lockstep
