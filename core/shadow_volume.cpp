// lockstep core: shadow volumes' shared steps (core/shadow_volume.h; the
// method and its sources: reference/shadow_volume.h).
#include "core/shadow_volume.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <numeric>
#include <utility>

#include "core/mesh.h"

namespace lockstep {

namespace {

using Tri = std::array<Vec3, 3>;

// The sphere tessellations the z-buffer draws (view_spheres: the same rings,
// positions and winding), for every sphere, on screen or not.
void add_spheres(const Scene& scene, const ScreenMesh& frame, const RasterSettings& s,
                 std::vector<Tri>& out) {
  const Camera& cam = frame.camera;
  for (uint32_t k = 0; k < scene.sphere_count(); ++k) {
    const Vec3 c = scene.sphere_center[k];
    const double signed_r = scene.sphere_radius[k], r = std::abs(signed_r);
    const Vec3 d = c - cam.eye;
    const double cz = dot(d, cam.forward);
    const UnitSphere u = unit_sphere(sphere_rings(r, cz, cam, frame.near_z, s.tess_error));
    for (const auto& [a, b, cc] : u.tri) {
      const Vec3 pa = c + r * u.unit[a], pb = c + r * u.unit[b], pc = c + r * u.unit[cc];
      out.push_back(signed_r > 0 ? Tri{pa, pb, pc} : Tri{pa, pc, pb});
    }
  }
}

}  // namespace

// ---------------------------------------------------------------- occluders

OccluderMesh occluder_mesh(std::vector<Tri> tris) {
  OccluderMesh m;
  m.tri = std::move(tris);
  const size_t n = m.tri.size();
  // Vertices matched by exact position.
  std::map<std::array<double, 3>, uint32_t> ids;
  std::vector<std::array<uint32_t, 3>> vid(n);
  for (size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = m.tri[t][k];
      vid[t][k] =
          ids.emplace(std::array<double, 3>{p.x, p.y, p.z}, uint32_t(ids.size())).first->second;
    }
  // Every undirected edge: which triangles use it, in which direction.
  struct Use {
    uint32_t tri;
    int edge;
    bool forward;  // traversed from the smaller vertex id to the larger
  };
  std::map<std::pair<uint32_t, uint32_t>, std::vector<Use>> edges;
  std::vector<uint8_t> degenerate(n, 0);
  for (uint32_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = vid[t][k], b = vid[t][(k + 1) % 3];
      if (a == b) {
        degenerate[t] = 1;  // two corners at one position: no edge to pair
        continue;
      }
      edges[{std::min(a, b), std::max(a, b)}].push_back({t, k, a < b});
    }
  UnionFind comp(n);  // the edge-connected components
  for (const auto& [key, uses] : edges)
    for (size_t i = 1; i < uses.size(); ++i) comp.join(uses[0].tri, uses[i].tri);
  // Number the components; a component is closed when every edge of it has
  // exactly two uses, in opposite directions, and no triangle is degenerate.
  std::map<uint32_t, uint32_t> number;
  m.component.resize(n);
  for (uint32_t t = 0; t < n; ++t)
    m.component[t] = number.emplace(comp.find(t), uint32_t(number.size())).first->second;
  m.closed.assign(number.size(), 1);
  m.adj.assign(n, {OccluderMesh::kNone, OccluderMesh::kNone, OccluderMesh::kNone});
  for (uint32_t t = 0; t < n; ++t)
    if (degenerate[t]) m.closed[m.component[t]] = 0;
  for (const auto& [key, uses] : edges) {
    const bool good = uses.size() == 2 && uses[0].forward != uses[1].forward;
    if (!good) m.closed[m.component[uses[0].tri]] = 0;
    if (uses.size() == 2) {
      m.adj[uses[0].tri][uses[0].edge] = uses[1].tri;
      m.adj[uses[1].tri][uses[1].edge] = uses[0].tri;
    }
  }
  // A closed component turned inside out (all its faces inward, as NFF allows
  // for one-sided polygons) is turned outward for the volume: the silhouette
  // method sweeps the occluder's inside with it, which only an outward
  // orientation gives (its inner faces may be seen through its culled outer
  // ones, and are in its shadow). The sign of the enclosed volume (the
  // divergence theorem: the sum of a . (b x c) / 6 over the faces) tells.
  std::vector<double> volume(m.closed.size(), 0.0);
  for (uint32_t t = 0; t < n; ++t)
    volume[m.component[t]] += dot(m.tri[t][0], cross(m.tri[t][1], m.tri[t][2]));
  for (uint32_t t = 0; t < n; ++t)
    if (m.closed[m.component[t]] && volume[m.component[t]] < 0) {
      std::swap(m.tri[t][1], m.tri[t][2]);  // edges a->c, c->b, b->a: the old 2, 1, 0 reversed
      std::swap(m.adj[t][0], m.adj[t][2]);
    }
  for (uint32_t c = 0; c < m.closed.size(); ++c)
    m.inverted_components += m.closed[c] && volume[c] < 0 ? 1 : 0;
  for (uint32_t t = 0; t < n; ++t)
    if (!m.closed[m.component[t]]) ++m.open_tris;
  for (uint8_t c : m.closed) m.open_components += c ? 0 : 1;
  return m;
}

OccluderMesh occluder_mesh(const Scene& scene, const ScreenMesh& frame, const RasterSettings& s) {
  std::vector<Tri> tris;
  add_spheres(scene, frame, s, tris);
  for (uint32_t p = 0; p < scene.polygon_count(); ++p) {
    if (length(scene.poly_plane[p].n) == 0) continue;  // the z-buffer draws nothing of it either
    for (uint32_t t = scene.poly_tri_first[p]; t < scene.poly_tri_first[p + 1]; ++t) {
      const auto& [a, b, c] = scene.tri_vertex[t];
      tris.push_back({scene.vertex[a], scene.vertex[b], scene.vertex[c]});
    }
  }
  return occluder_mesh(std::move(tris));
}

std::string occluder_note(const OccluderMesh& occ) {
  if (occ.open_tris == 0) return "";
  return "shadow volumes: " + std::to_string(occ.open_tris) + " of " +
         std::to_string(occ.tri.size()) + " occluder triangles (" +
         std::to_string(occ.open_components) +
         " meshes) are not closed and consistently oriented: each casts a volume of its own "
         "(exact, more fill)";
}

// ---------------------------------------------------------------- the volume

namespace {

bool lexicographic_less(const Vec3& a, const Vec3& b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  return a.z < b.z;
}

// The same triangle (same orientation) starting at its smallest vertex.
Tri canonical(const Tri& t) {
  int m = 0;
  for (int k = 1; k < 3; ++k)
    if (lexicographic_less(t[k], t[m])) m = k;
  return {t[m], t[(m + 1) % 3], t[(m + 2) % 3]};
}

}  // namespace

double shadow_far(const Scene& scene, const Vec3& light) {
  Vec3 lo, hi;
  scene_bounds(scene, lo, hi);
  const Vec3 eye = scene.view.from;
  lo = {std::min(lo.x, eye.x), std::min(lo.y, eye.y), std::min(lo.z, eye.z)};
  hi = {std::max(hi.x, eye.x), std::max(hi.y, eye.y), std::max(hi.z, eye.z)};
  double far = 0;
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
    far = std::max(far, length(corner - light));
  }
  return 2 * far;
}

std::vector<Tri> shadow_volume(const OccluderMesh& occ, const Vec3& light, double far, bool caps,
                               bool silhouette_only_for_open, std::vector<uint8_t>* is_cap) {
  if (is_cap) is_cap->clear();
  const size_t n = occ.tri.size();
  // Which side of each triangle the light is on: > 0 light-facing.
  std::vector<double> facing(n);
  for (size_t t = 0; t < n; ++t) {
    const Tri& v = occ.tri[t];
    facing[t] = dot(cross(v[1] - v[0], v[2] - v[0]), light - v[0]);
  }
  // How far to extrude. A volume's back cap is the flat triangle through its
  // corners extruded to distance D, so it lies at D * h from the light, h the
  // distance from the centre of the unit sphere to the plane through the
  // corners' directions (u0, u1, u2): near 1 for a triangle that subtends a
  // small angle, near 0 for one that the light sees almost edge-on or from
  // close by its plane (a light just inside a box). D = far keeps every point
  // within far / 2 of the light (the box around the scene and the eye,
  // shadow_far) inside the volume only where h >= 1/2; with a smaller h the
  // back cap cut the volume short, short of the scene (a light 0.011 from a
  // box face: h = 0.008, the cap 0.28 from the light, the floor 8 away lit).
  // So D = far / (2 h_min) when some emitted triangle has h_min < 1/2: one D
  // per light, the same for every triangle, so that coincident sides of two
  // per-triangle volumes still cancel. h below 1e-12 (the light within
  // rounding of the triangle's plane: a volume of no thickness) is left out.
  // A light inside a closed component (its winding number about the light,
  // the sum of its triangles' signed solid angles over 4 pi, is not 0) has
  // no silhouette to speak of: everything outside is in its shadow. That
  // component takes the per-triangle volumes (exact for any soup) for this
  // light instead of being left without a shadow.
  std::vector<double> winding(occ.closed.size(), 0.0);
  for (uint32_t t = 0; t < n; ++t) {
    if (!occ.closed[occ.component[t]]) continue;
    const Vec3 a = occ.tri[t][0] - light, b = occ.tri[t][1] - light, c = occ.tri[t][2] - light;
    const double la = length(a), lb = length(b), lc = length(c);
    winding[occ.component[t]] +=
        2 * std::atan2(dot(a, cross(b, c)),
                       la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la);
  }
  auto silhouette = [&](uint32_t t) {
    const uint32_t c = occ.component[t];
    return (occ.closed[c] && std::lround(winding[c] / (4 * std::numbers::pi)) == 0) ||
           silhouette_only_for_open;
  };
  auto emitted = [&](uint32_t t) { return silhouette(t) ? facing[t] > 0 : facing[t] != 0; };
  double h_min = 1;
  for (uint32_t t = 0; t < n; ++t) {
    const Tri& v = occ.tri[t];
    if (!emitted(t) || v[0] == light || v[1] == light || v[2] == light) continue;
    const Vec3 u0 = normalize(v[0] - light), u1 = normalize(v[1] - light),
               u2 = normalize(v[2] - light);
    const Vec3 m = cross(u1 - u0, u2 - u0);
    const double h = std::abs(dot(u0, m)) / length(m);
    if (h > 1e-12) h_min = std::min(h_min, h);
  }
  const double extrude = h_min < 0.5 ? far / (2 * h_min) : far;
  auto away = [&](const Vec3& p) { return light + (extrude / length(p - light)) * (p - light); };
  std::vector<Tri> out;
  // The volume of a light-facing triangle (a, b, c): front cap (a, b, c), back
  // cap (a', c', b'), and the side quad (b, a, a', b') over each edge a -> b
  // that is a silhouette edge (`side(k)`); all outward-facing.
  auto emit = [&](const Tri& v, auto side) {
    if (v[0] == light || v[1] == light || v[2] == light)
      return;  // a corner at the light: no volume
    const Tri e{away(v[0]), away(v[1]), away(v[2])};
    if (caps) {
      out.push_back(v);
      out.push_back({e[0], e[2], e[1]});
      if (is_cap) is_cap->insert(is_cap->end(), {1, 1});
    }
    for (int k = 0; k < 3; ++k) {
      if (!side(k)) continue;
      const int k1 = (k + 1) % 3;
      const Vec3 &p = v[k], &q = v[k1], &pe = e[k], &qe = e[k1];
      // The quad (q, p, p', q') split along the diagonal from the smaller
      // endpoint (by coordinates) to the other's extrusion, each triangle
      // starting at its smallest vertex: the two per-triangle volumes that
      // share an edge then give the very same screen triangles, mirrored, so
      // that they cancel at every sample, rounding included.
      if (lexicographic_less(p, q)) {
        out.push_back(canonical({q, p, qe}));
        out.push_back(canonical({p, pe, qe}));
      } else {
        out.push_back(canonical({q, p, pe}));
        out.push_back(canonical({q, pe, qe}));
      }
      if (is_cap) is_cap->insert(is_cap->end(), {0, 0});
    }
  };
  for (uint32_t t = 0; t < n; ++t) {
    const Tri& v = occ.tri[t];
    if (silhouette(t)) {
      // Crow: the silhouette edges, where a light-facing triangle meets one
      // that is not (or, for the wrong rule on open meshes, the mesh's border).
      if (!(facing[t] > 0)) continue;
      emit(v, [&](int k) {
        const uint32_t nb = occ.adj[t][k];
        return nb == OccluderMesh::kNone || !(facing[nb] > 0);
      });
    } else if (facing[t] != 0) {
      // The fallback: the triangle on its own, turned to face the light.
      const Tri w = facing[t] > 0 ? v : Tri{v[0], v[2], v[1]};
      emit(w, [](int) { return true; });
    }
  }
  return out;
}

ViewedVolume view_volume(const Scene& scene, const ScreenMesh& frame, const RasterSettings& s,
                         const std::vector<Tri>& volume, const std::vector<uint8_t>* is_cap) {
  // The volume's triangles as polygons of a scene of their own, two-sided so
  // that none is culled, through the z-buffer's viewing pipeline.
  Scene vol;
  vol.view = scene.view;
  Material m;
  m.transmittance = 1;  // two-sided
  vol.materials.push_back(m);
  std::vector<Vec3> normal;  // per volume polygon: its outward normal
  std::vector<uint8_t> cap;  // per volume polygon: a cap
  for (size_t i = 0; i < volume.size(); ++i) {
    const Tri& t = volume[i];
    const Vec3 n = cross(t[1] - t[0], t[2] - t[0]);
    const double len = length(n);
    if (!(len > 0)) continue;  // no area: covers nothing
    const uint32_t first = uint32_t(vol.vertex.size());
    for (const Vec3& p : t) {
      vol.vertex.push_back(p);
      vol.vertex_normal.push_back(n / len);
    }
    vol.poly_first.push_back(uint32_t(vol.vertex.size()));
    vol.poly_plane.push_back({n / len, -dot(n / len, t[0])});
    vol.poly_material.push_back(0);
    vol.poly_is_patch.push_back(0);
    vol.tri_vertex.push_back({first, first + 1, first + 2});
    vol.tri_poly.push_back(uint32_t(vol.poly_plane.size() - 1));
    vol.poly_tri_first.push_back(uint32_t(vol.tri_vertex.size()));
    normal.push_back(n);
    cap.push_back(is_cap ? (*is_cap)[i] : 0);
  }
  ViewedVolume out;
  ScreenMesh& vm = out.mesh;
  vm.camera = frame.camera;
  vm.width = frame.width;
  vm.height = frame.height;
  vm.near_z = frame.near_z;
  vm.far_z = frame.far_z;
  RasterSettings vs = s;
  vs.shading = Shading::kPhong;  // no lighting at vertices: the volume is not drawn
  vs.cull = CullMode::kNone;
  view_polygons(vol, vs, 0, vol.polygon_count(), vm);
  out.front.resize(vm.tris.size());
  out.cap.resize(vm.tris.size());
  for (size_t i = 0; i < vm.tris.size(); ++i) {
    const ScreenTri& t = vm.tris[i];
    // Facing as the eye sees it: the rasteriser stores positive area, swapping
    // a front face's v[1], v[2]; the stored order against the polygon's
    // outward normal tells which (clipping keeps the order, fans keep it).
    const Vec3 stored = cross(t.v[1].world - t.v[0].world, t.v[2].world - t.v[0].world);
    out.front[i] = dot(stored, normal[t.source_tri]) < 0;
    out.cap[i] = cap[t.source_tri];
  }
  return out;
}

[[gnu::noinline]] double sample_depth(const ScreenTri& t, int64_t e0, int64_t e1, int64_t e2) {
  const ScreenVertex &v0 = t.v[0], &v1 = t.v[1], &v2 = t.v[2];
  const int64_t area = int64_t(v1.x - v0.x) * (v2.y - v0.y) - int64_t(v1.y - v0.y) * (v2.x - v0.x);
  const double l0 = double(e0) / double(area), l1 = double(e1) / double(area),
               l2 = double(e2) / double(area);
  const double inv_z = l0 / v0.z + l1 / v1.z + l2 / v2.z;
  return 1 / inv_z;
}

}  // namespace lockstep
