// lockstep core: welding and the topology of triangle meshes (see core/mesh.h).
#include "core/mesh.h"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <unordered_map>

namespace lockstep {

namespace {

// A position's bits (with -0 as +0), for exact hashing.
struct Key {
  uint32_t b[3];
  bool operator==(const Key& o) const { return b[0] == o.b[0] && b[1] == o.b[1] && b[2] == o.b[2]; }
};
struct KeyHash {
  size_t operator()(const Key& k) const {
    uint64_t h = 1469598103934665603ull;
    for (uint32_t x : k.b) h = (h ^ x) * 1099511628211ull;
    return size_t(h ^ (h >> 29));
  }
};
Key key(const Vec3f& v) {
  Key k;
  const float c[3] = {v.x + 0.0f, v.y + 0.0f, v.z + 0.0f};  // -0 + 0 = +0
  std::memcpy(k.b, c, sizeof c);
  return k;
}

}  // namespace

Mesh weld(const Mesh& mesh) {
  Mesh out;
  std::unordered_map<Key, uint32_t, KeyHash> index;
  index.reserve(mesh.vertices.size());
  std::vector<uint32_t> remap(mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const auto [it, fresh] = index.emplace(key(mesh.vertices[i]), uint32_t(out.vertices.size()));
    if (fresh) out.vertices.push_back(mesh.vertices[i]);
    remap[i] = it->second;
  }
  out.triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    const std::array<uint32_t, 3> w = {remap[t[0]], remap[t[1]], remap[t[2]]};
    if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) continue;
    out.triangles.push_back(w);
  }
  return out;
}

Topology topology(const Mesh& m) {
  Topology t;
  t.vertices = long(m.vertices.size());
  t.faces = long(m.triangles.size());
  // Undirected edge -> (triangles on it, how many run it a -> b with a < b).
  struct Use {
    int count = 0, forward = 0;
  };
  std::unordered_map<uint64_t, Use> edges;
  edges.reserve(m.triangles.size() * 2);
  UnionFind comp(m.vertices.size());
  std::vector<uint8_t> used(m.vertices.size(), 0);
  for (const auto& tri : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = tri[size_t(k)], b = tri[size_t(k + 1) % 3];
      const uint64_t e = uint64_t(std::min(a, b)) << 32 | std::max(a, b);
      Use& u = edges[e];
      ++u.count;
      u.forward += a < b;
      comp.join(a, b);
      used[a] = 1;
    }
  t.edges = long(edges.size());
  for (const auto& [e, u] : edges) {
    if (u.count == 1) ++t.boundary_edges;
    else if (u.count > 2) ++t.nonmanifold_edges;
    else if (u.forward != 1) ++t.misoriented_edges;
  }
  // A vertex is manifold when its triangles form one fan: joined through the
  // edges at the vertex, they are one group.
  std::vector<std::vector<uint32_t>> around(m.vertices.size());
  for (uint32_t f = 0; f < m.triangles.size(); ++f)
    for (uint32_t v : m.triangles[f]) around[v].push_back(f);
  for (size_t v = 0; v < around.size(); ++v) {
    const auto& fs = around[v];
    if (fs.size() < 2) continue;
    // Faces around v share an edge (v, w) when they have another vertex w in common.
    UnionFind fan(fs.size());
    std::unordered_map<uint32_t, size_t> first_with;
    for (size_t i = 0; i < fs.size(); ++i)
      for (uint32_t w : m.triangles[fs[i]]) {
        if (w == v) continue;
        const auto [it, fresh] = first_with.emplace(w, i);
        if (!fresh) fan.join(uint32_t(i), uint32_t(it->second));
      }
    size_t groups = 0;
    for (size_t i = 0; i < fs.size(); ++i) groups += fan.find(uint32_t(i)) == i;
    if (groups > 1) ++t.nonmanifold_vertices;
  }
  for (size_t v = 0; v < m.vertices.size(); ++v)
    if (used[v] && comp.find(uint32_t(v)) == v) ++t.components;
  return t;
}

size_t zero_area_triangles(const Mesh& m) {
  size_t n = 0;
  for (const auto& t : m.triangles) {
    const Vec3f &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    const Vec3 u{double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
    const Vec3 w{double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
    const Vec3 x = cross(u, w);
    n += x.x == 0 && x.y == 0 && x.z == 0;
  }
  return n;
}

std::string Topology::str() const {
  std::string s = "V " + std::to_string(vertices) + " E " + std::to_string(edges) + " F " + std::to_string(faces) +
                  " chi " + std::to_string(euler()) + ", " + std::to_string(components) +
                  (components == 1 ? " component" : " components");
  if (closed_manifold()) return s + ", closed oriented manifold";
  if (boundary_edges) s += ", " + std::to_string(boundary_edges) + " boundary edges";
  if (nonmanifold_edges) s += ", " + std::to_string(nonmanifold_edges) + " non-manifold edges";
  if (misoriented_edges) s += ", " + std::to_string(misoriented_edges) + " misoriented edges";
  if (nonmanifold_vertices) s += ", " + std::to_string(nonmanifold_vertices) + " pinched vertices";
  return s;
}

}  // namespace lockstep
