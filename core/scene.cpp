#include "core/scene.h"

#include <algorithm>
#include <cmath>

namespace lockstep {

uint32_t add_material(Scene& scene, const Material& m) {
  scene.materials.push_back(m);
  return uint32_t(scene.materials.size() - 1);
}

void add_sphere(Scene& scene, const Vec3& center, double radius, uint32_t material) {
  scene.sphere_center.push_back(center);
  scene.sphere_radius.push_back(radius);
  scene.sphere_material.push_back(material);
}

void add_cone(Scene& scene, const Vec3& base, double r0, const Vec3& apex, double r1, bool inside,
              uint32_t material) {
  scene.cone_base.push_back(base);
  scene.cone_apex.push_back(apex);
  scene.cone_r0.push_back(r0);
  scene.cone_r1.push_back(r1);
  scene.cone_inside.push_back(inside ? 1 : 0);
  scene.cone_material.push_back(material);
}

namespace {

// Newell's method: the normal of a (possibly concave, possibly slightly
// non-planar) polygon as the sum of its edges' projected areas. For a planar
// polygon it equals twice the area times the unit normal, oriented by the
// counter-clockwise order.
Vec3 newell_normal(std::span<const Vec3> v) {
  Vec3 n{0, 0, 0};
  for (size_t i = 0; i < v.size(); ++i) {
    const Vec3& a = v[i];
    const Vec3& b = v[(i + 1) % v.size()];
    n.x += (a.y - b.y) * (a.z + b.z);
    n.y += (a.z - b.z) * (a.x + b.x);
    n.z += (a.x - b.x) * (a.y + b.y);
  }
  return n;
}

struct P2 {
  double x, y;
};
double orient2d(const P2& a, const P2& b, const P2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

}  // namespace

std::vector<std::array<uint32_t, 3>> triangulate(std::span<const Vec3> vertices, const Vec3& normal) {
  std::vector<std::array<uint32_t, 3>> out;
  const size_t n = vertices.size();
  if (n < 3 || normal == Vec3{0, 0, 0}) return out;
  // Project onto the plane of the two axes other than the dominant one, keeping
  // the orientation counter-clockwise (flip when the dropped axis points down).
  const int drop = dominant_axis(normal);
  const int ax = (drop + 1) % 3, ay = (drop + 2) % 3;
  const bool flip = normal[drop] < 0;
  std::vector<P2> p(n);
  for (size_t i = 0; i < n; ++i) {
    p[i] = {vertices[i][ax], vertices[i][ay]};
    if (flip) p[i].y = -p[i].y;
  }
  if (n == 3) {
    if (orient2d(p[0], p[1], p[2]) > 0) out.push_back({0, 1, 2});
    return out;
  }
  // Ear clipping: repeatedly cut off a convex corner that contains no other vertex.
  std::vector<uint32_t> idx(n);
  for (size_t i = 0; i < n; ++i) idx[i] = uint32_t(i);
  size_t guard = 0;
  while (idx.size() > 3 && guard < 4 * n * n) {
    bool cut = false;
    const size_t m = idx.size();
    for (size_t i = 0; i < m; ++i, ++guard) {
      const uint32_t a = idx[(i + m - 1) % m], b = idx[i], c = idx[(i + 1) % m];
      const double o = orient2d(p[a], p[b], p[c]);
      if (o < 0) continue;  // reflex corner: not an ear
      if (o == 0) {         // collinear: drop the middle vertex, it adds no area
        idx.erase(idx.begin() + long(i));
        cut = true;
        break;
      }
      bool empty = true;
      for (size_t j = 0; j < m && empty; ++j) {
        const uint32_t q = idx[j];
        if (q == a || q == b || q == c) continue;
        if (orient2d(p[a], p[b], p[q]) >= 0 && orient2d(p[b], p[c], p[q]) >= 0 &&
            orient2d(p[c], p[a], p[q]) >= 0)
          empty = false;
      }
      if (!empty) continue;
      out.push_back({a, b, c});
      idx.erase(idx.begin() + long(i));
      cut = true;
      break;
    }
    if (!cut) break;  // not a simple polygon (self-intersecting): fan the rest below
  }
  if (idx.size() >= 3) {
    for (size_t i = 1; i + 1 < idx.size(); ++i)
      if (orient2d(p[idx[0]], p[idx[i]], p[idx[i + 1]]) > 0) out.push_back({idx[0], idx[i], idx[i + 1]});
  }
  return out;
}

void add_polygon(Scene& scene, std::span<const Vec3> vertices, std::span<const Vec3> normals,
                 uint32_t material) {
  const uint32_t first = uint32_t(scene.vertex.size());
  const uint32_t poly = scene.polygon_count();
  scene.vertex.insert(scene.vertex.end(), vertices.begin(), vertices.end());
  for (size_t i = 0; i < vertices.size(); ++i)
    scene.vertex_normal.push_back(i < normals.size() ? normalize(normals[i]) : Vec3{0, 0, 0});
  scene.poly_first.push_back(uint32_t(scene.vertex.size()));
  const Vec3 nw = newell_normal(vertices);
  const double len = length(nw);
  Plane plane;
  if (len > 0 && std::isfinite(len)) {
    plane.n = nw / len;
    plane.d = -dot(plane.n, vertices[0]);
  }
  scene.poly_plane.push_back(plane);
  scene.poly_material.push_back(material);
  scene.poly_is_patch.push_back(normals.empty() ? 0 : 1);
  for (const auto& t : triangulate(vertices, plane.n)) {
    scene.tri_vertex.push_back({first + t[0], first + t[1], first + t[2]});
    scene.tri_poly.push_back(poly);
  }
  scene.poly_tri_first.push_back(uint32_t(scene.tri_vertex.size()));
}

// Whether a polygon without a plane normal has area after all: its Newell
// normal, recomputed from vertices moved to the first one and scaled by a
// power of two to unit size, is not zero.
bool normal_lost_to_range(std::span<const Vec3> v) {
  if (v.size() < 3) return false;
  double m = 0;
  for (const Vec3& x : v) m = std::max(m, max_abs_component(x - v[0]));
  if (!(m > 0) || !std::isfinite(m)) return !(m == 0);
  const double s = std::ldexp(1.0, -std::ilogb(m));
  Vec3 n;
  for (size_t i = 0; i < v.size(); ++i) {
    const Vec3 a = (v[i] - v[0]) * s, b = (v[(i + 1) % v.size()] - v[0]) * s;
    n += cross(a, b);
  }
  return length(n) > 0;
}

uint64_t range_lost_polygons(const Scene& scene) {
  uint64_t n = 0;
  for (uint32_t p = 0; p < scene.polygon_count(); ++p)
    if (dot(scene.poly_plane[p].n, scene.poly_plane[p].n) == 0 && normal_lost_to_range(scene.polygon_vertices(p))) ++n;
  return n;
}

void scene_bounds(const Scene& scene, Vec3& lo, Vec3& hi) {
  lo = Vec3{kInfinity, kInfinity, kInfinity};
  hi = -lo;
  auto grow = [&](const Vec3& p, double r) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k] - r);
      hi[k] = std::max(hi[k], p[k] + r);
    }
  };
  for (uint32_t i = 0; i < scene.sphere_count(); ++i)
    grow(scene.sphere_center[i], std::abs(scene.sphere_radius[i]));
  for (const Vec3& v : scene.vertex) grow(v, 0);
  // A cone lies in the convex hull of its two end discs; each disc lies in the
  // ball of its radius (loose by up to the radius along the axis, never short).
  for (uint32_t i = 0; i < scene.cone_count(); ++i) {
    grow(scene.cone_base[i], scene.cone_r0[i]);
    grow(scene.cone_apex[i], scene.cone_r1[i]);
  }
}

}  // namespace lockstep
