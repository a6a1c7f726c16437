// lockstep props/ray_cast: closed meshes on a dyadic grid (see meshes.h).
#include "props/ray_cast/meshes.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace lockstep::props::ray_cast {

double round_to(double x, int grid_exp) { return std::ldexp(std::nearbyint(std::ldexp(x, -grid_exp)), grid_exp); }
Vec3 round_to(const Vec3& v, int grid_exp) {
  return {round_to(v.x, grid_exp), round_to(v.y, grid_exp), round_to(v.z, grid_exp)};
}

namespace {

// Orients every face counter-clockwise seen from outside (convex meshes around the origin).
void orient_outward(Mesh& m) {
  for (auto& f : m.faces) {
    const Vec3 a = m.verts[f[0]], b = m.verts[f[1]], c = m.verts[f[2]];
    Vec3 centroid{0, 0, 0};
    for (uint32_t i : f) centroid += m.verts[i];
    centroid = centroid / double(f.size());
    if (dot(cross(b - a, c - a), centroid) < 0) std::reverse(f.begin(), f.end());
  }
}

}  // namespace

Mesh octahedron() {
  Mesh m;
  m.verts = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (uint32_t x : {0u, 1u})
    for (uint32_t y : {2u, 3u})
      for (uint32_t z : {4u, 5u}) m.faces.push_back({x, y, z});
  orient_outward(m);
  return m;
}

Mesh icosahedron(int grid_bits) {
  Mesh m;
  const double p = (1 + std::sqrt(5.0)) / 2;
  const double raw[12][3] = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0}, {0, -1, p}, {0, 1, p},
                             {0, -1, -p}, {0, 1, -p}, {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
  const double s = 1 / std::sqrt(1 + p * p);
  for (auto& v : raw) m.verts.push_back(round_to(Vec3{v[0] * s, v[1] * s, v[2] * s}, -grid_bits));
  const uint32_t f[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                             {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                             {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (auto& t : f) m.faces.push_back({t[0], t[1], t[2]});
  orient_outward(m);
  return m;
}

Mesh icosphere(int level, int grid_bits) {
  Mesh m = icosahedron(60);  // unrounded first
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.verts.push_back(normalize(m.verts[a] + m.verts[b]));
      return mid[key] = uint32_t(m.verts.size() - 1);
    };
    std::vector<std::vector<uint32_t>> faces;
    for (const auto& t : m.faces) {
      const uint32_t a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
      faces.push_back({t[0], a, c});
      faces.push_back({t[1], b, a});
      faces.push_back({t[2], c, b});
      faces.push_back({a, b, c});
    }
    m.faces = std::move(faces);
  }
  for (Vec3& v : m.verts) v = round_to(v, -grid_bits);
  orient_outward(m);
  return m;
}

Mesh tessellated_cube(int n, bool quads) {
  Mesh m;
  std::map<std::tuple<int, int, int>, uint32_t> index;
  auto vert = [&](int i, int j, int k) {  // grid coordinates 0..n
    const auto key = std::make_tuple(i, j, k);
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    m.verts.push_back({std::ldexp(2.0 * i - n, 0) / n, std::ldexp(2.0 * j - n, 0) / n, std::ldexp(2.0 * k - n, 0) / n});
    return index[key] = uint32_t(m.verts.size() - 1);
  };
  // n is 1, 2 or 4 so that the grid coordinates are dyadic.
  for (int axis = 0; axis < 3; ++axis) {
    for (int side : {0, n}) {
      for (int a = 0; a < n; ++a) {
        for (int b = 0; b < n; ++b) {
          auto at = [&](int u, int v) {
            int c[3];
            c[axis] = side;
            c[(axis + 1) % 3] = u;
            c[(axis + 2) % 3] = v;
            return vert(c[0], c[1], c[2]);
          };
          const uint32_t q[4] = {at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)};
          if (quads) {
            m.faces.push_back({q[0], q[1], q[2], q[3]});
          } else if ((a + b) % 2) {
            m.faces.push_back({q[0], q[1], q[2]});
            m.faces.push_back({q[0], q[2], q[3]});
          } else {
            m.faces.push_back({q[0], q[1], q[3]});
            m.faces.push_back({q[1], q[2], q[3]});
          }
        }
      }
    }
  }
  orient_outward(m);
  return m;
}

}  // namespace lockstep::props::ray_cast
