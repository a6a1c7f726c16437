// lockstep props/marching_cubes: the accuracy oracle (see oracle.h).
#include "props/marching_cubes/oracle.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

namespace lockstep::props::marching_cubes {

namespace {

using K = CGAL::Simple_cartesian<double>;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

K::Point_3 point(const Vec3f& v) { return {double(v.x), double(v.y), double(v.z)}; }
K::Point_3 point(const Vec3& v) { return {v.x, v.y, v.z}; }

Triangles triangles_of(const Mesh& m) {
  Triangles out;
  out.reserve(m.triangles.size());
  for (const auto& t : m.triangles)
    out.emplace_back(point(m.vertices[t[0]]), point(m.vertices[t[1]]), point(m.vertices[t[2]]));
  return out;
}

// A surface by parameters: faces x [0, 1]^2 -> points (periodic: s and t wrap).
struct Surface {
  int faces = 1;
  int ns = 1, nt = 1;  // grid steps per face
  bool periodic = false;
  std::function<Vec3(int, double, double)> at;
};

// The largest distance from the surface to the mesh (see oracle.h).
double surface_to_mesh(const Surface& s, const Triangles& tris) {
  if (tris.empty()) return kInfinity;
  Tree tree(tris.begin(), tris.end());
  tree.accelerate_distance_queries();
  auto dist = [&](int f, double u, double v) {
    if (s.periodic) {
      u -= std::floor(u);
      v -= std::floor(v);
    } else {
      u = std::clamp(u, 0.0, 1.0);
      v = std::clamp(v, 0.0, 1.0);
    }
    return std::sqrt(tree.squared_distance(point(s.at(f, u, v))));
  };
  struct Sample {
    double d;
    int f;
    double u, v;
  };
  std::vector<Sample> samples;
  for (int f = 0; f < s.faces; ++f)
    for (int i = 0; i <= s.ns; ++i)
      for (int j = 0; j <= s.nt; ++j) {
        const double u = double(i) / s.ns, v = double(j) / s.nt;
        samples.push_back({dist(f, u, v), f, u, v});
      }
  const size_t top = std::min<size_t>(64, samples.size());
  std::partial_sort(samples.begin(), samples.begin() + long(top), samples.end(),
                    [](const Sample& a, const Sample& b) { return a.d > b.d; });
  double worst = samples.front().d;
  for (size_t c = 0; c < top; ++c) {
    Sample x = samples[c];
    double du = 1.0 / s.ns, dv = 1.0 / s.nt;
    for (int halvings = 0; halvings < 20;) {
      Sample best = x;
      for (int a = -1; a <= 1; ++a)
        for (int b = -1; b <= 1; ++b) {
          if (a == 0 && b == 0) continue;
          double u = x.u + a * du, v = x.v + b * dv;
          if (!s.periodic) {
            u = std::clamp(u, 0.0, 1.0);
            v = std::clamp(v, 0.0, 1.0);
          }
          const double d = dist(x.f, u, v);
          if (d > best.d) best = {d, x.f, u, v};
        }
      if (best.d > x.d) {
        x = best;
      } else {
        du /= 2;
        dv /= 2;
        ++halvings;
      }
    }
    worst = std::max(worst, x.d);
  }
  return worst;
}

int steps(double length, double spacing) { return std::max(2, int(std::ceil(length / spacing))); }

}  // namespace

Hausdorff sphere_hausdorff(const Mesh& mesh, double r, double spacing) {
  Hausdorff h;
  const Triangles tris = triangles_of(mesh);
  const K::Point_3 o(0, 0, 0);
  for (const K::Triangle_3& t : tris) {
    double far = 0;
    for (int k = 0; k < 3; ++k)
      far = std::max(far, std::sqrt(CGAL::squared_distance(o, t.vertex(k))));
    const double near = std::sqrt(CGAL::squared_distance(o, t));
    h.mesh_to_surface = std::max({h.mesh_to_surface, far - r, r - near});
  }
  Surface s;
  s.faces = 6;
  s.ns = s.nt = steps(std::numbers::pi / 2 * r, spacing);
  s.at = [r](int f, double u, double v) {
    const double a = 2 * u - 1, b = 2 * v - 1, sign = (f & 1) ? 1.0 : -1.0;
    const Vec3 p = f / 2 == 0 ? Vec3{sign, a, b} : f / 2 == 1 ? Vec3{a, sign, b} : Vec3{a, b, sign};
    return (r / length(p)) * p;
  };
  h.surface_to_mesh = surface_to_mesh(s, tris);
  return h;
}

Hausdorff torus_hausdorff(const Mesh& mesh, double a, double b, double spacing) {
  Hausdorff h;
  const Triangles tris = triangles_of(mesh);
  auto dist = [a, b](const Vec3& p) {
    return std::abs(std::hypot(std::hypot(p.x, p.y) - a, p.z) - b);
  };
  // Barycentric grid per triangle; the 16 worst triangles refined.
  constexpr int n = 16;
  std::vector<std::pair<double, size_t>> worst;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3 p0{mesh.vertices[tri[0]].x, mesh.vertices[tri[0]].y, mesh.vertices[tri[0]].z};
    const Vec3 p1{mesh.vertices[tri[1]].x, mesh.vertices[tri[1]].y, mesh.vertices[tri[1]].z};
    const Vec3 p2{mesh.vertices[tri[2]].x, mesh.vertices[tri[2]].y, mesh.vertices[tri[2]].z};
    double d = 0;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j)
        d = std::max(d, dist(p0 + (double(i) / n) * (p1 - p0) + (double(j) / n) * (p2 - p0)));
    worst.push_back({d, t});
  }
  const size_t top = std::min<size_t>(16, worst.size());
  std::partial_sort(worst.begin(), worst.begin() + long(top), worst.end(), std::greater<>());
  for (size_t c = 0; c < top; ++c) {
    const auto& tri = mesh.triangles[worst[c].second];
    const Vec3 p0{mesh.vertices[tri[0]].x, mesh.vertices[tri[0]].y, mesh.vertices[tri[0]].z};
    const Vec3 p1{mesh.vertices[tri[1]].x, mesh.vertices[tri[1]].y, mesh.vertices[tri[1]].z};
    const Vec3 p2{mesh.vertices[tri[2]].x, mesh.vertices[tri[2]].y, mesh.vertices[tri[2]].z};
    auto at = [&](double u, double w) {
      u = std::clamp(u, 0.0, 1.0);
      w = std::clamp(w, 0.0, 1.0 - u);
      return dist(p0 + u * (p1 - p0) + w * (p2 - p0));
    };
    // Start from the best grid sample.
    double bu = 0, bw = 0, bd = -1;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j)
        if (const double d = at(double(i) / n, double(j) / n); d > bd)
          bd = d, bu = double(i) / n, bw = double(j) / n;
    double step = 1.0 / n;
    for (int halvings = 0; halvings < 20;) {
      double nu = bu, nw = bw, nd = bd;
      for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
          if (const double d = at(bu + x * step, bw + y * step); d > nd)
            nd = d, nu = bu + x * step, nw = bw + y * step;
      if (nd > bd) {
        bu = std::clamp(nu, 0.0, 1.0);
        bw = std::clamp(nw, 0.0, 1.0 - bu);
        bd = nd;
      } else {
        step /= 2;
        ++halvings;
      }
    }
    worst[c].first = std::max(worst[c].first, bd);
  }
  for (size_t c = 0; c < top; ++c) h.mesh_to_surface = std::max(h.mesh_to_surface, worst[c].first);
  Surface s;
  s.periodic = true;
  s.ns = steps(2 * std::numbers::pi * (a + b), spacing);
  s.nt = steps(2 * std::numbers::pi * b, spacing);
  s.at = [a, b](int, double u, double v) {
    const double phi = 2 * std::numbers::pi * u, theta = 2 * std::numbers::pi * v;
    const double rho = a + b * std::cos(theta);
    return Vec3{rho * std::cos(phi), rho * std::sin(phi), b * std::sin(theta)};
  };
  h.surface_to_mesh = surface_to_mesh(s, tris);
  return h;
}

}  // namespace lockstep::props::marching_cubes
