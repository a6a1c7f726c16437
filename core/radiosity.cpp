// lockstep core: radiosity's shared definitions (core/radiosity.h).
#include "core/radiosity.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <tuple>
#include <numbers>
#include <stdexcept>

#include "core/error.h"
#include "core/param_values.h"

namespace lockstep {

namespace {

constexpr double kPi = std::numbers::pi;

// The polygon's part where dot(n, p - x) >= 0 (Sutherland-Hodgman, one
// plane), into out (room for poly.size() + 1 corners); returns its count.
size_t clip_in_front(std::span<const Vec3> poly, const Vec3& x, const Vec3& n, Vec3* out) {
  size_t m = 0;
  const size_t k = poly.size();
  for (size_t i = 0; i < k; ++i) {
    const Vec3& a = poly[i];
    const Vec3& b = poly[(i + 1) % k];
    const double da = dot(n, a - x), db = dot(n, b - x);
    if (da >= 0) out[m++] = a;
    if ((da >= 0) != (db >= 0)) out[m++] = a + (b - a) * (da / (da - db));
  }
  return m;
}
std::vector<Vec3> clip_in_front(std::span<const Vec3> poly, const Vec3& x, const Vec3& n) {
  std::vector<Vec3> out(poly.size() + 1);
  out.resize(clip_in_front(poly, x, n, out.data()));
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
  // Patches have 3 or 4 corners: their clipped copy on the stack.
  Vec3 small[8];
  std::vector<Vec3> large;
  if (polygon.size() + 1 > std::size(small)) large.resize(polygon.size() + 1);
  Vec3* buffer = large.empty() ? small : large.data();
  const std::span<const Vec3> p(buffer, clip_in_front(polygon, x, n, buffer));
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

namespace {

// Int_{s0}^{s1} ln(sqrt(s^2 + h^2) / r0) ds: the integral of ln(r / r0) along
// a line at distance h from the point, s along the line. Its antiderivative
// is s ln(r / r0) - s + h atan(s / h); the last two cancel to -s^3 / (3 h^2)
// for s << h, summed by series there (else the contour sum loses digits).
double log_distance_integral(double s0, double s1, double h, double r0_squared) {
  auto g = [h, r0_squared](double s) {
    const double q = s * s + h * h;
    const double t = s == 0 ? 0 : 0.5 * s * std::log(q / r0_squared);  // s ln s -> 0 at 0
    if (h == 0) return t - s;
    const double x = s / h;
    if (std::abs(x) < 1e-2) {
      const double x2 = x * x;
      return t + s * x2 * (-1.0 / 3 + x2 * (1.0 / 5 + x2 * (-1.0 / 7 + x2 / 9)));
    }
    return t + (h * std::atan(x) - s);
  };
  return g(s1) - g(s0);
}

// One Gauss-Kronrod panel (7 / 15 points) of Int_a^b f: the Kronrod value,
// its error estimate |K - G|, and the integral of |f| (for rounding's floor).
struct Panel {
  double a, b, value, error, magnitude;
};

template <class F>
Panel gauss_kronrod_panel(const F& f, double a, double b) {
  static constexpr double xk[8] = {0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
                                   0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
                                   0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
                                   0.207784955007898467600689403773245, 0.0};
  static constexpr double wk[8] = {0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
                                   0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
                                   0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
                                   0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
  static constexpr double wg[4] = {0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                                   0.381830050505118944950369775488975, 0.417959183673469387755102040816327};
  const double c = 0.5 * (a + b), hl = 0.5 * (b - a);
  const double fc = f(c);
  double kronrod = wk[7] * fc, gauss = wg[3] * fc, magnitude = wk[7] * std::abs(fc);
  for (int i = 0; i < 7; ++i) {
    const double f0 = f(c - hl * xk[i]), f1 = f(c + hl * xk[i]);
    kronrod += wk[i] * (f0 + f1);
    magnitude += wk[i] * (std::abs(f0) + std::abs(f1));
    if (i % 2 == 1) gauss += wg[i / 2] * (f0 + f1);
  }
  return {a, b, kronrod * hl, std::abs(kronrod - gauss) * hl, magnitude * hl};
}

// Int_a^b f by globally adaptive Gauss-Kronrod (QUADPACK's QAG): the panel
// of largest error is halved until the errors total at most tol, or each is
// at rounding's floor (1e-14 of its integral of |f|: the integrand is itself
// a difference, log_distance_integral), or max_panels are in use. Bounded
// work whatever f does: a singularity or noise costs panels, not time.
template <class F>
double gauss_kronrod(const F& f, double a, double b, double tol, int max_panels) {
  std::vector<Panel> panels = {gauss_kronrod_panel(f, a, b)};
  auto open = [](const Panel& p) { return p.error > 1e-14 * p.magnitude; };
  auto worse = [&](const Panel& x, const Panel& y) { return (open(x) ? x.error : 0) < (open(y) ? y.error : 0); };
  double error = panels[0].error;
  while (error > tol && int(panels.size()) < max_panels) {
    std::pop_heap(panels.begin(), panels.end(), worse);
    const Panel worst = panels.back();
    if (!open(worst)) break;  // every panel is at its floor (this one stays, at the back)
    panels.pop_back();
    const double c = 0.5 * (worst.a + worst.b);
    panels.push_back(gauss_kronrod_panel(f, worst.a, c));
    std::push_heap(panels.begin(), panels.end(), worse);
    panels.push_back(gauss_kronrod_panel(f, c, worst.b));
    std::push_heap(panels.begin(), panels.end(), worse);
    error = 0;
    for (const Panel& p : panels) error += open(p) ? p.error : 0;
  }
  double sum = 0;
  for (const Panel& p : panels) sum += p.value;
  return sum;
}

}  // namespace

double polygon_form_factor(std::span<const Vec3> from, std::span<const Vec3> to) {
  // Only the part of each polygon in front of the other's plane exchanges
  // energy (the cosines clamp at 0), and the two clips are independent.
  const Vec3 nf_area = vector_area2(from), nt_area = vector_area2(to);
  const double area_from = 0.5 * length(nf_area);
  if (!(area_from > 0) || !(length(nt_area) > 0)) return 0;
  const Vec3 nf = normalize(nf_area), nt = normalize(nt_area);
  // Clipping can leave an edge of rounding's length (a corner a hair off the
  // other's plane): dropped, it carries no energy and only noise.
  auto clipped = [](std::span<const Vec3> poly, const Vec3& x, const Vec3& n) {
    std::vector<Vec3> c = clip_in_front(poly, x, n), out;
    double size = 0;
    for (size_t k = 0; k < c.size(); ++k) size = std::max(size, length(c[(k + 1) % c.size()] - c[k]));
    for (size_t k = 0; k < c.size(); ++k)
      if (length(c[(k + 1) % c.size()] - c[k]) > 1e-9 * size) out.push_back(c[k]);
    return out;
  };
  const std::vector<Vec3> a = clipped(from, to[0], nt);
  const std::vector<Vec3> b = clipped(to, from[0], nf);
  if (a.size() < 3 || b.size() < 3) return 0;
  if (!(length(vector_area2(a)) > 0) || !(length(vector_area2(b)) > 0)) return 0;  // in the other's plane
  // ln r measured from r0, the distance between the polygons' first corners
  // (or 1): the constant ln r0 the closed contours cancel, the terms smaller.
  double r0_squared = dot(b[0] - a[0], b[0] - a[0]);
  if (!(r0_squared > 0)) r0_squared = 1;
  double sum = 0;
  for (size_t p = 0; p < a.size(); ++p) {
    const Vec3 x0 = a[p], e = a[(p + 1) % a.size()] - a[p];
    for (size_t q = 0; q < b.size(); ++q) {
      const Vec3 y0 = b[q], d = b[(q + 1) % b.size()] - b[q];
      const double len = length(d);
      if (!(len > 0)) continue;
      const Vec3 u = d / len;
      const double eu = dot(e, u);
      if (eu == 0) continue;  // perpendicular edges add nothing
      // Inner: along edge q in closed form (in length units: Int ln r ds);
      // outer: along edge p by quadrature. e . d dt_q = (e . u) ds.
      const Vec3 base = x0 - y0;  // first: exact for nearby corners far from the origin
      auto inner = [&](double t) {
        const Vec3 w = base + e * t;
        const double along = dot(w, u);
        const double h = length(w - u * along);
        return log_distance_integral(-along, len - along, h, r0_squared);
      };
      sum += eu * gauss_kronrod(inner, 0.0, 1.0, 1e-14 * len, 200);
    }
  }
  // Sparrow's contour form (Cohen and Wallace eq. 4.16): F = 1/(2 pi A_i) sum sum e_p . e_q Int Int ln r.
  return std::max(0.0, sum / (2 * kPi * area_from));
}

double parallel_rectangles_form_factor(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double x2 = x * x, y2 = y * y;
  const double sx = std::sqrt(1 + x2), sy = std::sqrt(1 + y2);
  return 2 / (kPi * x * y) *
         // log1p: for small plates far apart the terms cancel to x^2 y^2.
         (0.5 * (std::log1p(x2) + std::log1p(y2) - std::log1p(x2 + y2)) + x * sy * std::atan(x / sy) +
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

double radiosity_residual(const std::vector<Patch>& patches, const FormFactors& f,
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

double radiosity_system_check(const std::vector<Patch>& patches, const FormFactors& f) {
  if (f.size() != patches.size() * patches.size())
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
  return e_max;
}

SolveResult solve_radiosity(const std::vector<Patch>& patches, const FormFactors& f,
                            RadiositySolver solver, double tolerance, int max_iterations) {
  const size_t n = patches.size();
  const double e_max = radiosity_system_check(patches, f);
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
      for (;;) {
        out.residual = radiosity_residual(patches, f, out.b);
        if (out.residual <= goal || out.iterations >= max_iterations) break;
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

// ------------------------------------------------------------- the family's steps

namespace {

constexpr std::string_view kMethods = "rays|hemicube|exact";
constexpr std::string_view kSolvers = "jacobi|gauss-seidel|progressive";

// A unit vector perpendicular to unit n.
Vec3 perpendicular(const Vec3& n) {
  const Vec3 a = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  return normalize(cross(n, a));
}

bool convex_quad(std::span<const Vec3> q, const Vec3& n) {
  for (size_t i = 0; i < 4; ++i)
    if (!(dot(cross(q[(i + 1) % 4] - q[i], q[(i + 2) % 4] - q[(i + 1) % 4]), n) > 0)) return false;
  return true;
}

}  // namespace

std::vector<ParamSpec> radiosity_params() {
  return {
      {"form_factors", kMethods, "rays",
       "rays: Lambert's point-to-patch factor times the share of k x k rays that arrive; hemicube: the "
       "patch's view through the z-buffer; exact: the area-to-area factor (contour integral) times that share"},
      {"rays", "k, 1..16", "2", "form_factors=rays|exact: k x k rays from a patch's centre to each patch"},
      {"hemicube", "pixels, even, 8..1024", "64", "form_factors=hemicube: pixels a side of the top face"},
      {"solver", kSolvers, "gauss-seidel", "how B = E + rho F B is solved"},
      {"patch_area", "scene units^2, > 0", "area/256", "the largest patch: polygons are cut until every piece is this small"},
      {"error", "0..1, 0: off", "0",
       "refine: cut patches in four where a neighbour's radiosity differs by more than this share of the largest "
       "(weighted by the patch's side against the start's), and solve again (at most 4 cuts deep, 20000 patches)"},
      {"tolerance", "1e-12..0.1", "1e-4", "stop when the residual (progressive: the unshot energy) is this share of the emission"},
  };
}

RadiositySettings radiosity_settings(const Params& params, const std::string& source) {
  RadiositySettings s;
  for (const auto& [name, value] : params.items) {
    if (name == "form_factors") {
      s.method = FormFactorMethod(param_choice(source, name, value, kMethods));
    } else if (name == "rays") {
      s.rays = param_int(source, name, value, 1, 16);
    } else if (name == "hemicube") {
      s.hemicube = param_int(source, name, value, 8, 1024);
      if (s.hemicube % 2 != 0) throw InputError(source, 0, "hemicube: '" + value + "' is not even (the sides are half faces)");
    } else if (name == "solver") {
      s.solver = RadiositySolver(param_choice(source, name, value, kSolvers));
    } else if (name == "patch_area") {
      s.patch_area = param_number(source, name, value, 1e-300, 1e300);
    } else if (name == "error") {
      s.error = param_number(source, name, value, 0, 1);
    } else if (name == "tolerance") {
      s.tolerance = param_number(source, name, value, 1e-12, 0.1);
    } else {
      std::string known;
      for (const ParamSpec& p : radiosity_params()) known += (known.empty() ? "" : ", ") + std::string(p.name);
      throw InputError(source, 0, "unknown setting '" + name + "' (known: " + known + ")");
    }
  }
  return s;
}

PatchMesh mesh_scene(const Scene& scene, double max_area) {
  PatchMesh out;
  out.spheres_and_cones = uint64_t(scene.sphere_count()) + scene.cone_count();
  double total = 0;
  for (uint32_t p = 0; p < scene.polygon_count(); ++p) {
    const double a = 0.5 * length(vector_area2(scene.polygon_vertices(p)));
    if (std::isfinite(a)) total += a;
  }
  if (max_area <= 0) max_area = total / 256;
  if (!(max_area > 0)) return out;  // no polygon has area
  // The count before cutting: a dense n x n matrix must fit.
  if (total / max_area > double(kMaxPatches))
    throw InputError(scene.source, 0,
                     "patch_area " + std::to_string(max_area) + " cuts the scene's polygon area " +
                         std::to_string(total) + " into more than 20000 patches (a dense form-factor matrix of 3.2 GB)");
  out.max_area = out.cut_area = max_area;
  for (uint32_t p = 0; p < scene.polygon_count(); ++p) {
    const Material& m = scene.materials[scene.poly_material[p]];
    const Vec3 rho = m.color * m.kd;
    for (double r : {rho.x, rho.y, rho.z})
      if (!(r >= 0 && r < 1))
        throw InputError(scene.source, m.line,
                         "reflectance (colour x Kd) " + std::to_string(r) +
                             " is not below 1: radiosity's B = E + rho F B would not converge");
    const std::span<const Vec3> v = scene.polygon_vertices(p);
    // A polygon without area (its vertices on a line) has no patches.
    const double a = 0.5 * length(vector_area2(v));
    if (!(a > 0) || !std::isfinite(a)) {
      ++out.no_area;
      continue;
    }
    std::vector<Patch> pieces;
    if (v.size() == 4 && convex_quad(v, scene.poly_plane[p].n)) {
      pieces = mesh_polygon(v, rho, m.emission, max_area, int(p));
    } else {
      for (uint32_t t = scene.poly_tri_first[p]; t < scene.poly_tri_first[p + 1]; ++t) {
        const auto& tv = scene.tri_vertex[t];
        const Vec3 tri[3] = {scene.vertex[tv[0]], scene.vertex[tv[1]], scene.vertex[tv[2]]};
        for (Patch& q : mesh_polygon(tri, rho, m.emission, max_area, int(p))) pieces.push_back(q);
      }
    }
    for (Patch& q : pieces) out.patches.push_back(q);
  }
  index_vertices(out);
  return out;
}

void index_vertices(PatchMesh& mesh) {
  mesh.vertex.clear();
  mesh.corner.clear();
  std::map<std::tuple<int, double, double, double>, uint32_t> shared;
  for (const Patch& q : mesh.patches) {
    std::array<uint32_t, 4> c{0, 0, 0, 0};
    for (int k = 0; k < q.count; ++k) {
      const auto key = std::make_tuple(q.polygon, q.v[k].x, q.v[k].y, q.v[k].z);
      auto [it, fresh] = shared.emplace(key, uint32_t(mesh.vertex.size()));
      if (fresh) mesh.vertex.push_back(q.v[k]);
      c[k] = it->second;
    }
    mesh.corner.push_back(c);
  }
}

std::vector<double> radiosity_jumps(const PatchMesh& mesh, const std::vector<Vec3>& b) {
  const size_t n = mesh.patches.size();
  std::vector<double> jump(n, 0.0);
  // Relative to the largest reflected radiosity B - E (an emitter's own
  // emission would dwarf every jump on the walls).
  double top = 0;
  for (size_t i = 0; i < n; ++i) {
    const Vec3 r = b[i] - mesh.patches[i].emission;
    top = std::max({top, r.x, r.y, r.z});
  }
  if (!(top > 0)) return jump;
  // Neighbours: patches of one polygon whose boxes touch (within 1e-9 of
  // their size): every pair of a polygon, sorted by the boxes' low x.
  struct Item {
    Vec3 lo, hi;
    size_t index;
  };
  std::map<int, std::vector<Item>> by_polygon;
  for (size_t i = 0; i < n; ++i) {
    const Patch& p = mesh.patches[i];
    Vec3 lo = p.v[0], hi = p.v[0];
    for (const Vec3& v : p.corners())
      lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)},
      hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
    const double pad = 1e-9 * length(hi - lo) + 1e-12 * length(hi);
    by_polygon[p.polygon].push_back({lo - Vec3{pad, pad, pad}, hi + Vec3{pad, pad, pad}, i});
  }
  for (auto& [polygon, items] : by_polygon) {
    std::sort(items.begin(), items.end(), [](const Item& a, const Item& c) { return a.lo.x < c.lo.x; });
    for (size_t a = 0; a < items.size(); ++a)
      for (size_t c = a + 1; c < items.size() && items[c].lo.x <= items[a].hi.x; ++c) {
        const Item &p = items[a], &q = items[c];
        if (p.lo.y > q.hi.y || q.lo.y > p.hi.y || p.lo.z > q.hi.z || q.lo.z > p.hi.z) continue;
        const Vec3 d = b[p.index] - b[q.index];
        const double j = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)}) / top;
        jump[p.index] = std::max(jump[p.index], j);
        jump[q.index] = std::max(jump[q.index], j);
      }
  }
  return jump;
}

Refined refine_patches(PatchMesh& mesh, const std::vector<Vec3>& b, double e, double min_area) {
  Refined out;
  const std::vector<double> jump = radiosity_jumps(mesh, b);
  std::vector<double> jump_w(jump.size());
  // The candidates, largest jump first; each cut adds three patches.
  std::vector<size_t> order;
  for (size_t i = 0; i < mesh.patches.size(); ++i) {
    jump_w[i] = jump[i] * std::sqrt(mesh.patches[i].area() / mesh.max_area);
    if (jump_w[i] > e) order.push_back(i);
  }
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t c) { return jump_w[a] > jump_w[c]; });
  std::vector<unsigned char> cut(mesh.patches.size(), 0);
  size_t count = mesh.patches.size();
  for (size_t i : order) {
    if (mesh.patches[i].area() / 4 < min_area || count + 3 > kMaxPatches) {
      ++out.held;
      continue;
    }
    cut[i] = 1;
    count += 3;
    ++out.cut;
  }
  if (out.cut == 0) return out;
  std::vector<Patch> next;
  next.reserve(count);
  for (size_t i = 0; i < mesh.patches.size(); ++i) {
    const Patch& p = mesh.patches[i];
    if (!cut[i]) {
      next.push_back(p);
      continue;
    }
    auto child = [&](std::initializer_list<Vec3> corners) {
      Patch c = p;
      c.count = int(corners.size());
      std::copy(corners.begin(), corners.end(), c.v);
      mesh.cut_area = std::min(mesh.cut_area, c.area());
      next.push_back(c);
    };
    const Vec3* v = p.v;
    if (p.count == 4) {  // the bilinear grid's 2 x 2: planar pieces of a planar quad
      const Vec3 m01 = (v[0] + v[1]) / 2.0, m12 = (v[1] + v[2]) / 2.0, m23 = (v[2] + v[3]) / 2.0,
                 m30 = (v[3] + v[0]) / 2.0, mid = (v[0] + v[1] + v[2] + v[3]) / 4.0;
      child({v[0], m01, mid, m30});
      child({m01, v[1], m12, mid});
      child({mid, m12, v[2], m23});
      child({m30, mid, m23, v[3]});
    } else {
      const Vec3 m01 = (v[0] + v[1]) / 2.0, m12 = (v[1] + v[2]) / 2.0, m20 = (v[2] + v[0]) / 2.0;
      child({v[0], m01, m20});
      child({m01, v[1], m12});
      child({m20, m12, v[2]});
      child({m01, m12, m20});
    }
  }
  mesh.patches.swap(next);
  index_vertices(mesh);
  return out;
}

RadiositySolution solve_scene(const Scene& scene, const RadiositySettings& s, const FormFactorsOf& form_factors,
                              const RadiositySolve& solve) {
  RadiositySolution out;
  out.mesh = mesh_scene(scene, s.patch_area);
  const double smallest = out.mesh.max_area / std::pow(4.0, kRefineLevels);
  for (;;) {
    out.f = form_factors(out.mesh, std::move(out.f));
    out.solved = solve_patches(out.mesh, out.f, s, scene.source, solve);
    if (!(s.error > 0)) break;
    const Refined r = refine_patches(out.mesh, out.solved.b, s.error, smallest);
    out.held = r.held;
    if (r.cut == 0) break;
    ++out.rounds;
  }
  if (s.error > 0) {
    const std::vector<double> jump = radiosity_jumps(out.mesh, out.solved.b);
    for (size_t i = 0; i < jump.size(); ++i)
      out.jump = std::max(out.jump, jump[i] * std::sqrt(out.mesh.patches[i].area() / out.mesh.max_area));
  }
  return out;
}

Scene patch_scene(const PatchMesh& mesh, const View& view) {
  Scene s;
  s.view = view;
  add_material(s, Material{});
  for (const Patch& p : mesh.patches) add_polygon(s, p.corners(), {}, 0);
  return s;
}

HemicubeWeights hemicube_weights(int res) {
  HemicubeWeights w;
  w.res = res;
  const double pitch = 2.0 / res, da = pitch * pitch;
  auto centre = [&](int i) { return -1 + (i + 0.5) * pitch; };  // x of column i; y of row j is -centre(j)
  w.top.resize(size_t(res) * res);
  w.side.resize(size_t(res) * (res / 2));
  for (int j = 0; j < res; ++j)
    for (int i = 0; i < res; ++i) {
      const double x = centre(i), y = -centre(j);
      const double r2 = x * x + y * y + 1;
      w.top[size_t(j) * res + i] = da / (kPi * r2 * r2);
      if (j < res / 2) {
        // A side face: y is the height z above the patch's plane.
        w.side[size_t(j) * res + i] = y * da / (kPi * r2 * r2);
      }
    }
  return w;
}

double hemicube_turn(size_t patch) {
  const double golden = 0.6180339887498949;
  const double f = double(patch) * golden - std::floor(double(patch) * golden);
  return f * kPi / 2;
}

View hemicube_view(const Vec3& c, const Vec3& n, int face, int res, double near, double turn) {
  const Vec3 u0 = perpendicular(n), v0 = cross(n, u0);
  const Vec3 u = u0 * std::cos(turn) + v0 * std::sin(turn), v = cross(n, u);
  const Vec3 dirs[5] = {n, u, -u, v, -v};
  View view;
  view.from = c;
  view.at = c + dirs[face];
  view.up = face == 0 ? u : n;
  // Camera: the angle spans the edge pixels' centres, 1 - 1/res from the axis.
  view.angle = 2 * std::atan(double(res - 1) / res) * 180 / kPi;
  view.hither = near;
  view.xres = view.yres = res;
  return view;
}

void add_hemicube_face(const PatchMesh& mesh, const Scene& items, const ScreenMesh& screen, const Visibility& vis,
                       const HemicubeWeights& w, size_t i, int face, double* f_row) {
  const int res = w.res;
  const Vec3 c = mesh.patches[i].centre();
  // Side faces: only the upper half looks above the patch's plane.
  const int rows = face == 0 ? res : res / 2;
  const std::vector<double>& delta = face == 0 ? w.top : w.side;
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < res; ++x) {
      const uint32_t t = vis.tri[size_t(y) * res + x];
      if (t == Visibility::kNone) continue;
      const uint32_t j = items.tri_poly[screen.tris[t].source_tri];
      const Patch& to = mesh.patches[j];
      if (j == i || !(dot(to.normal(), c - to.v[0]) > 0)) continue;
      f_row[j] += delta[size_t(y) * res + x];
    }
}

double centre_form_factor(const PatchMesh& mesh, size_t i, size_t j) {
  if (i == j) return 0;
  const Patch& from = mesh.patches[i];
  const Patch& to = mesh.patches[j];
  const Vec3 c = from.centre();
  // In or behind j's plane, c gets nothing from j; "in" within 1e-9 rad of
  // it, far above rounding (the other patches of i's own polygon, far from
  // the origin, come out a few ulps off their plane).
  const Vec3 r = c - to.v[0];
  if (!(dot(to.normal(), r) > 1e-9 * length(r))) return 0;
  return point_polygon_form_factor(c, from.normal(), to.corners());
}

double exact_form_factor(const PatchMesh& mesh, size_t i, size_t j) {
  if (i == j || mesh.patches[i].polygon == mesh.patches[j].polygon) return 0;
  return polygon_form_factor(mesh.patches[i].corners(), mesh.patches[j].corners());
}

std::vector<Vec3> patch_targets(const Patch& p, int k) {
  std::vector<Vec3> out;
  if (p.count == 4) {
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        const double s = (i + 0.5) / k, t = (j + 0.5) / k;
        out.push_back(p.v[0] * ((1 - s) * (1 - t)) + p.v[1] * (s * (1 - t)) + p.v[2] * (s * t) + p.v[3] * ((1 - s) * t));
      }
    return out;
  }
  const Vec3 e1 = (p.v[1] - p.v[0]) / double(k), e2 = (p.v[2] - p.v[0]) / double(k);
  for (int j = 0; j < k; ++j)
    for (int i = 0; i + j < k; ++i) {
      const Vec3 base = p.v[0] + e1 * double(i) + e2 * double(j);
      out.push_back(base + (e1 + e2) / 3.0);
      if (i + j + 1 < k) out.push_back(base + (e1 + e2) * (2.0 / 3));
    }
  return out;
}

RasterSettings radiosity_item_buffer() {
  RasterSettings s;
  s.shading = Shading::kFlat;
  s.cull = CullMode::kNone;
  return s;
}

double hemicube_near(const PatchMesh& mesh) { return 1e-2 * std::sqrt(std::min(mesh.max_area, mesh.cut_area)); }

SolveResult solve_patches(const PatchMesh& mesh, const FormFactors& f, const RadiositySettings& s,
                          const std::string& source, const RadiositySolve& solve) {
  try {
    if (solve) return solve(mesh.patches, f, s.solver, s.tolerance, s.max_iterations);
    return solve_radiosity(mesh.patches, f, s.solver, s.tolerance, s.max_iterations);
  } catch (const std::invalid_argument& e) {
    throw InputError(source, 0, e.what());
  }
}

void radiosity_notes(const RadiositySolution& sol, const RadiositySettings& s, FrameStats& stats) {
  const PatchMesh& mesh = sol.mesh;
  const SolveResult& solved = sol.solved;
  const uint64_t n = mesh.patches.size();
  stats.items = n * n;
  stats.counts.insert(stats.counts.begin(), {{"patches", n}, {"iterations", uint64_t(solved.iterations)}});
  if (s.error > 0) stats.counts.push_back({"refinements", uint64_t(sol.rounds)});
  if (mesh.spheres_and_cones) stats.drop("spheres and cones: radiosity meshes polygons only", mesh.spheres_and_cones);
  if (mesh.no_area) stats.drop("polygons without area: no patches", mesh.no_area);
  bool emits = false;
  for (const Patch& p : mesh.patches) emits = emits || p.emission.x > 0 || p.emission.y > 0 || p.emission.z > 0;
  if (!emits)
    stats.notes.push_back("no emitter: every patch is black (an emitter is '#lockstep emit r g b' after an 'f' line)");
  if (solved.iterations >= s.max_iterations)
    stats.notes.push_back("the solve stopped after " + std::to_string(solved.iterations) + " " +
                          (s.solver == RadiositySolver::progressive ? "shots" : "sweeps") + " with residual " +
                          std::to_string(solved.residual));
  if (s.error > 0 && sol.held > 0)
    stats.notes.push_back(std::to_string(sol.held) + " patches still jump from a neighbour by more than error " +
                          std::to_string(s.error) + " (largest " + std::to_string(sol.jump) +
                          "): cut " + std::to_string(kRefineLevels) + " times already, or the mesh at " +
                          std::to_string(kMaxPatches) + " patches");
}

std::vector<Vec3> vertex_radiosity(const PatchMesh& mesh, const std::vector<Vec3>& b) {
  std::vector<Vec3> sum(mesh.vertex.size(), Vec3{0, 0, 0});
  std::vector<double> weight(mesh.vertex.size(), 0.0);
  for (size_t p = 0; p < mesh.patches.size(); ++p) {
    const double a = mesh.patches[p].area();
    for (int k = 0; k < mesh.patches[p].count; ++k) {
      sum[mesh.corner[p][k]] = sum[mesh.corner[p][k]] + b[p] * a;
      weight[mesh.corner[p][k]] += a;
    }
  }
  for (size_t v = 0; v < sum.size(); ++v) sum[v] = weight[v] > 0 ? sum[v] / weight[v] : Vec3{0, 0, 0};
  return sum;
}

Image radiosity_image(const Scene& patches, const PatchMesh& mesh, const std::vector<Vec3>& vertex_b,
                      const ScreenMesh& screen, const Visibility& vis, const Vec3& background) {
  const int w = screen.width, h = screen.height;
  Image image(w, h);
  image.depth.assign(size_t(w) * h, float(kInfinity));
  const Camera& cam = screen.camera;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const uint32_t t = vis.tri[(size_t(j) * w + i) * vis.spp];
      if (t == Visibility::kNone) {
        image.set(i, j, background);
        continue;
      }
      const uint32_t tri = screen.tris[t].source_tri;
      const uint32_t p = patches.tri_poly[tri];
      const auto& tv = patches.tri_vertex[tri];
      const Vec3 a = patches.vertex[tv[0]], b = patches.vertex[tv[1]], c = patches.vertex[tv[2]];
      // Where the pixel's centre ray meets the triangle's plane: barycentrics
      // by Cramer's rule (Moller and Trumbore 1997), no inside test (the
      // z-buffer decided coverage on snapped vertices; clamped below).
      const Ray r = cam.primary(i, j);
      const Vec3 e1 = b - a, e2 = c - a, pv = cross(r.d, e2);
      const double det = dot(e1, pv);
      double l1 = 0, l2 = 0, dist = 0;
      if (det != 0) {
        const Vec3 tv0 = r.o - a, q = cross(tv0, e1);
        l1 = dot(tv0, pv) / det;
        l2 = dot(r.d, q) / det;
        dist = dot(e2, q) / det;
      }
      l1 = std::clamp(l1, 0.0, 1.0);
      l2 = std::clamp(l2, 0.0, 1.0 - l1);
      const double l0 = 1 - l1 - l2;
      const uint32_t first = patches.poly_first[p];
      const Vec3 colour = vertex_b[mesh.corner[p][tv[0] - first]] * l0 + vertex_b[mesh.corner[p][tv[1] - first]] * l1 +
                          vertex_b[mesh.corner[p][tv[2] - first]] * l2;
      image.set(i, j, colour);
      image.depth[size_t(j) * w + i] = float(dist * dot(r.d, cam.forward));
    }
  return image;
}

void radiosity_sides(const PatchMesh& mesh, const std::vector<Vec3>& b, const std::vector<Vec3>& vertex_b,
                     const FrameOptions& opts, FrameStats* stats) {
  if (stats && opts.wants("patches")) stats->sides.emplace_back("patches", make_output(PatchSolution{mesh, b, vertex_b}));
}

}  // namespace lockstep
