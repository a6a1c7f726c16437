// lockstep reference: shadow volumes (see reference/shadow_volume.h for the
// method, the sources and what is exact).
#include "reference/shadow_volume.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <utility>

#include "core/error.h"
#include "core/shading.h"

namespace lockstep::ref {

namespace {

using Tri = std::array<Vec3, 3>;

// Union-find over triangles, for the edge-connected components.
struct Components {
  std::vector<uint32_t> parent;
  explicit Components(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(uint32_t a, uint32_t b) { parent[find(a)] = find(b); }
};

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
  Components comp(n);
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
  auto away = [&](const Vec3& p) { return light + (far / length(p - light)) * (p - light); };
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
    if (occ.closed[occ.component[t]] || silhouette_only_for_open) {
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

// ---------------------------------------------------------------- stencil counting

namespace {

int64_t edge(const ScreenVertex& a, const ScreenVertex& b, int64_t px, int64_t py) {
  return int64_t(b.x - a.x) * (py - a.y) - int64_t(b.y - a.y) * (px - a.x);
}
bool top_left(const ScreenVertex& a, const ScreenVertex& b) {
  const int32_t dx = b.x - a.x, dy = b.y - a.y;
  return (dy == 0 && dx > 0) || dy < 0;
}
bool owns(int64_t e, bool is_top_left) { return e > 0 || (e == 0 && is_top_left); }

// The eye depth of triangle t at a sample with edge functions e0, e1, e2 (the
// z-buffer's formula: screen barycentrics, the plane of 1/z). One function,
// not inlined, for visible samples and volume faces alike, so that equal
// inputs give equal depths bit for bit.
[[gnu::noinline]] double depth_at(const ScreenTri& t, int64_t e0, int64_t e1, int64_t e2) {
  const ScreenVertex &v0 = t.v[0], &v1 = t.v[1], &v2 = t.v[2];
  const int64_t area = edge(v0, v1, v2.x, v2.y);
  const double l0 = double(e0) / double(area), l1 = double(e1) / double(area),
               l2 = double(e2) / double(area);
  const double inv_z = l0 / v0.z + l1 / v1.z + l2 / v2.z;
  return 1 / inv_z;
}

// Every sample of triangle t (the z-buffer's loop): visit(index, z).
template <class Visit>
void for_samples(const ScreenTri& t, int w, int h,
                 const std::vector<std::array<int32_t, 2>>& offsets, Visit visit) {
  const ScreenVertex &v0 = t.v[0], &v1 = t.v[1], &v2 = t.v[2];
  const bool tl0 = top_left(v1, v2), tl1 = top_left(v2, v0), tl2 = top_left(v0, v1);
  const int32_t xmin = std::min({v0.x, v1.x, v2.x}), xmax = std::max({v0.x, v1.x, v2.x});
  const int32_t ymin = std::min({v0.y, v1.y, v2.y}), ymax = std::max({v0.y, v1.y, v2.y});
  const int i0 = std::max(0, int(std::floor(double(xmin) / kSubpixel)));
  const int i1 = std::min(w - 1, int(std::floor(double(xmax) / kSubpixel)));
  const int j0 = std::max(0, int(std::floor(double(ymin) / kSubpixel)));
  const int j1 = std::min(h - 1, int(std::floor(double(ymax) / kSubpixel)));
  const int spp = int(offsets.size());
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i)
      for (int k = 0; k < spp; ++k) {
        const int64_t px = int64_t(i) * kSubpixel + offsets[k][0];
        const int64_t py = int64_t(j) * kSubpixel + offsets[k][1];
        const int64_t e0 = edge(v1, v2, px, py), e1 = edge(v2, v0, px, py),
                      e2 = edge(v0, v1, px, py);
        if (!owns(e0, tl0) || !owns(e1, tl1) || !owns(e2, tl2)) continue;
        visit((size_t(j) * w + i) * spp + k, depth_at(t, e0, e1, e2));
      }
}

}  // namespace

std::vector<double> visible_z(const ScreenMesh& mesh, const RasterSettings& s,
                              const Visibility& vis) {
  std::vector<double> z(vis.tri.size(), kInfinity);
  const auto offsets = sample_offsets(s);
  for (uint32_t ti = 0; ti < mesh.tris.size(); ++ti)
    for_samples(mesh.tris[ti], mesh.width, mesh.height, offsets, [&](size_t index, double d) {
      if (vis.tri[index] == ti) z[index] = d;
    });
  return z;
}

void stencil_counts(const Scene& scene, const ScreenMesh& frame, const RasterSettings& s,
                    const std::vector<Tri>& volume, const std::vector<double>& z_visible,
                    std::vector<int32_t>& count, const std::vector<uint8_t>* is_cap) {
  count.assign(z_visible.size(), 0);
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
  ScreenMesh vm;
  vm.camera = frame.camera;
  vm.width = frame.width;
  vm.height = frame.height;
  vm.near_z = frame.near_z;
  vm.far_z = frame.far_z;
  RasterSettings vs = s;
  vs.shading = Shading::kPhong;  // no lighting at vertices: the volume is not drawn
  vs.cull = CullMode::kNone;
  view_polygons(vol, vs, 0, vol.polygon_count(), vm);

  const auto offsets = sample_offsets(s);
  for (const ScreenTri& t : vm.tris) {
    // Facing as the eye sees it: the rasteriser stores positive area, swapping
    // a front face's v[1], v[2]; the stored order against the polygon's
    // outward normal tells which (clipping keeps the order, fans keep it).
    const Vec3 stored = cross(t.v[1].world - t.v[0].world, t.v[2].world - t.v[0].world);
    const bool front = dot(stored, normal[t.source_tri]) < 0;
    // z-pass: +1 entering (front) in front of the surface, -1 leaving;
    // z-fail: +1 leaving (back) behind it, -1 entering.
    const int32_t step = s.zfail ? (front ? -1 : 1) : (front ? 1 : -1);
    const bool is_a_cap = cap[t.source_tri];
    for_samples(t, vm.width, vm.height, offsets, [&](size_t index, double z) {
      const double zv = z_visible[index];
      if (zv == kInfinity) return;
      // A cap at exactly the visible depth is the visible triangle's own.
      // Counting it or not is the count just before or just after the surface
      // along the view ray; shadow rays leave from the surface's light side,
      // which is the eye's side when the cap (outward = towards the light)
      // faces the eye, and the far side when it does not. So an equal front
      // cap is behind the surface, an equal back cap in front of it. A side
      // at the visible depth (the sample on the silhouette edge it rises
      // from) is behind, whichever way it faces, so that the two coincident
      // sides of an edge shared by two per-triangle volumes cancel.
      const bool in_front = z < zv || (z == zv && is_a_cap && !front);
      if (in_front != s.zfail) count[index] += step;
    });
  }
}

ShadowMasks shadow_masks(const Scene& scene, const ScreenMesh& frame, const RasterSettings& s,
                         const OccluderMesh& occ, const Visibility& vis) {
  ShadowMasks masks;
  masks.lights = uint32_t(scene.lights.size());
  masks.lit.assign(vis.tri.size() * masks.lights, 1);
  const std::vector<double> z = visible_z(frame, s, vis);
  std::vector<int32_t> count;
  for (uint32_t k = 0; k < masks.lights; ++k) {
    const Vec3 light = scene.lights[k].position;
    // Capped for z-pass too: a front cap is where the view ray enters a
    // volume through its occluder, which counts when the occluder is not
    // drawn (a back face culled from the eye still casts a shadow) and at a
    // visible cap itself (a smooth-shaded triangle facing away from the light
    // but lit by its normal: stencil_counts' equal-depth rule). The back cap
    // lies beyond the scene and the eye, never in front of a visible point.
    std::vector<uint8_t> is_cap;
    const std::vector<Tri> volume =
        shadow_volume(occ, light, shadow_far(scene, light), true, false, &is_cap);
    masks.volume_tris += volume.size();
    stencil_counts(scene, frame, s, volume, z, count, &is_cap);
    for (size_t i = 0; i < count.size(); ++i) masks.lit[i * masks.lights + k] = count[i] == 0;
  }
  return masks;
}

// ---------------------------------------------------------------- shading

Vec3 shade_fragment_lit(const Scene& scene, const ScreenMesh& mesh, const RasterSettings& s,
                        const Fragment& f, const uint8_t* lit) {
  // shade_fragment's Phong (core/raster_shading.cpp), the light sum of phong()
  // (core/shading.cpp) restricted to the lights that reach the point.
  const ScreenTri& t = mesh.tris[f.tri];
  const Camera& cam = mesh.camera;
  const Material& m = scene.material_of_prim(t.prim);
  const double cx = (f.sx - 0.5 * mesh.width) * cam.pitch,
               cy = (0.5 * mesh.height - f.sy) * cam.pitch;
  const Vec3 dir = cam.forward + cx * cam.right + cy * cam.up;
  const Vec3 v = -normalize(dir);
  Vec3 n = f.b[0] * t.v[0].normal + f.b[1] * t.v[1].normal + f.b[2] * t.v[2].normal;
  n = length(n) > 0 ? normalize(n) : t.face_normal;
  if (dot(n, dir) > 0) n = -n;
  const Vec3 p = cam.eye + f.z * dir;
  const Specular spec = s.shading == Shading::kBlinn ? Specular::kBlinn : Specular::kPhong;
  Vec3 c = kAmbient * (m.kd * m.color);
  for (size_t k = 0; k < scene.lights.size(); ++k)
    if (lit[k]) c += phong_light(m, n, v, light_at(scene, scene.lights[k], p), spec);
  if (s.silhouette && std::abs(dot(n, v)) < s.silhouette_eps) c = Vec3{0, 0, 0};
  return c;
}

}  // namespace lockstep::ref
