// lockstep kinds: the mesh output kind (see kinds/mesh_kind.h).
#include "kinds/mesh_kind.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <unordered_map>

#include "core/family.h"
#include "io/mesh_io.h"
#include "core/scene.h"
#include "io/image_io.h"
#include "kinds/image_kind.h"

namespace lockstep {

namespace {

const Mesh& mesh(const Output& o) { return output_as<Mesh>(o); }

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

Vec3 to_d(const Vec3f& v) { return {v.x, v.y, v.z}; }

void bounds(const Mesh& m, Vec3& lo, Vec3& hi) {
  lo = Vec3{kInfinity, kInfinity, kInfinity};
  hi = -1.0 * lo;
  for (const Vec3f& f : m.vertices) {
    const Vec3 v = to_d(f);
    lo = Vec3{std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
    hi = Vec3{std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
  }
}

// ---------------------------------------------------------------- pictures

// Heat colours, as the image kind's heat maps: blue 0, green, yellow, red at 1 and above.
Vec3 heat(double x) {
  static const Vec3 knots[] = {{0, 0, 1}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
  x = std::clamp(x, 0.0, 1.0) * 3;
  const int i = std::min(2, int(x));
  const double t = x - i;
  return (1 - t) * knots[i] + t * knots[i + 1];
}

// The mesh as an NFF scene: per-vertex normals (area-weighted) for Phong,
// seen from a corner of its bounding box. colour_of(t) picks triangle t's
// material among materials.
template <class MaterialOf>
Scene scene_of(const Mesh& welded, const Vec3& lo, const Vec3& hi, const std::vector<Material>& materials,
               MaterialOf material_of) {
  Scene s;
  for (const Material& m : materials) add_material(s, m);
  std::vector<Vec3> normal(welded.vertices.size(), Vec3{0, 0, 0});
  for (const auto& t : welded.triangles) {
    const Vec3 a = to_d(welded.vertices[t[0]]), b = to_d(welded.vertices[t[1]]), c = to_d(welded.vertices[t[2]]);
    const Vec3 n = cross(b - a, c - a);
    for (uint32_t v : t) normal[v] = normal[v] + n;
  }
  for (size_t t = 0; t < welded.triangles.size(); ++t) {
    const auto& tri = welded.triangles[t];
    Vec3 p[3], n[3];
    bool smooth = true;
    for (int k = 0; k < 3; ++k) {
      p[k] = to_d(welded.vertices[tri[size_t(k)]]);
      const double len = length(normal[tri[size_t(k)]]);
      smooth = smooth && len > 0;
      n[k] = len > 0 ? (1.0 / len) * normal[tri[size_t(k)]] : Vec3{0, 0, 1};
    }
    add_polygon(s, p, smooth ? std::span<const Vec3>(n) : std::span<const Vec3>(), material_of(t));
  }
  const Vec3 centre = 0.5 * (lo + hi);
  const double diag = std::max(length(hi - lo), 1e-6);
  s.view.at = centre;
  s.view.from = centre + 1.6 * diag * normalize(Vec3{1.0, -1.4, 0.8});
  s.view.up = Vec3{0, 0, 1};
  s.view.angle = 2 * std::atan(0.5 / 1.6) * 180 / std::numbers::pi;
  s.view.hither = 1e-3 * diag;
  s.background = Vec3{0.12, 0.12, 0.16};
  Light key, fill;
  key.position = centre + 3 * diag * normalize(Vec3{1, -0.5, 1.5});
  fill.position = centre + 3 * diag * normalize(Vec3{-1, -1, 0.2});
  fill.color = Vec3{0.35, 0.35, 0.4};
  fill.has_color = true;
  key.color = Vec3{0.9, 0.9, 0.85};
  key.has_color = true;
  s.lights = {key, fill};
  s.source = "<mesh preview>";
  return s;
}

std::string draw(const Scene& s, const std::string& stem, MeshDraw rasterize) {
  FrameOptions o;
  o.width = o.height = 512;
  o.params.set("shading", "phong");
  o.params.set("cull", "none");  // both sides: a misoriented patch shows
  return save_picture(rasterize(s, o), stem);
}

// ---------------------------------------------------------------- the kind's functions

void write(const Output& o, const std::string& path) { write_mesh(mesh(o), path); }
// Goldens are welded: they are compared welded, and a soup's copies of each
// vertex would only make the file six times larger.
void write_golden(const Output& o, const std::string& path) { write_mesh(weld(mesh(o)), path); }
Output read(const std::string& path) { return make_output<Mesh>(read_mesh(path)); }

Agreement compare(const Output& oa, const Output& ob, const Tolerance& tol) {
  const Mesh a = weld(mesh(oa)), b = weld(mesh(ob));
  Agreement r;
  if (a.vertices.empty() || b.vertices.empty()) {
    r.comparable = a.vertices.empty() == b.vertices.empty();
    r.pass = r.comparable;
    r.worst = r.comparable ? 0 : kInfinity;
    return r;
  }
  const std::vector<double> ab = nearest_vertex_distance(b, a), ba = nearest_vertex_distance(a, b);
  for (const auto* d : {&ab, &ba})
    for (double x : *d) {
      ++r.samples;
      r.worst = std::max(r.worst, std::isnan(x) ? kInfinity : x);
      r.over += !(x <= tol.abs);
      r.over_hard += !(x <= tol.hard);
    }
  Vec3 lo, hi, lo2, hi2;
  bounds(a, lo, hi);
  bounds(b, lo2, hi2);
  const double diag = length(Vec3{std::max(hi.x, hi2.x), std::max(hi.y, hi2.y), std::max(hi.z, hi2.z)} -
                             Vec3{std::min(lo.x, lo2.x), std::min(lo.y, lo2.y), std::min(lo.z, lo2.z)});
  r.score = r.worst > 0 ? 20 * std::log10(diag / r.worst) : kInfinity;
  const long allowed = long(std::floor((1.0 - tol.fraction) * double(r.samples) + 1e-9));
  r.pass = r.over <= allowed && r.over_hard == 0;
  // Vertices alone do not see a missing triangle (its corners belong to its
  // neighbours too): the two surfaces must also have the same open edges (the
  // same holes and cracks; their Euler characteristic may differ where
  // ambiguous faces are separated the other way, and in a peer that puts cut
  // points on samples equal to iso, as VTK does, welding may pinch an edge;
  // ours never put one there: core/marching_cubes.h, the tie rule).
  const Topology ta = topology(a), tb = topology(b);
  if (ta.boundary_edges != tb.boundary_edges) {
    r.pass = false;
    r.detail = "open edges " + std::to_string(ta.boundary_edges) + " against " + std::to_string(tb.boundary_edges);
  }
  return r;
}

std::string describe(const Agreement& a, const Tolerance& tol) {
  if (!a.comparable) return "one mesh is empty, the other is not";
  if (!a.detail.empty() && a.over == 0 && a.over_hard == 0) return a.detail;
  if (a.over_hard > 0) return std::to_string(a.over_hard) + " vertices farther than the hard limit " + fmt("%.3g", tol.hard);
  if (a.over > 0) return std::to_string(a.over) + " vertices farther than " + fmt("%.4g", tol.abs) + " from the other mesh";
  return {};
}

std::string describe_tolerance(const Tolerance& t) {
  return "vertices within " + fmt("%.3g", t.abs) + " of the other mesh's on >= " + fmt("%.4g", 100.0 * t.fraction) +
         "% of them, hard limit " + fmt("%.3g", t.hard);
}

}  // namespace

namespace mesh_kind_detail {

std::string save_view(const Output& o, const std::string& stem, MeshDraw rasterize) {
  const Mesh w = weld(mesh(o));
  if (w.triangles.empty()) {
    write_mesh(w, stem + ".ply");
    return stem + ".ply";
  }
  Vec3 lo, hi;
  bounds(w, lo, hi);
  Material m;
  m.color = Vec3{0.85, 0.78, 0.62};
  m.kd = 0.8;
  m.ks = 0.3;
  m.shine = 24;
  return draw(scene_of(w, lo, hi, {m}, [](size_t) { return 0u; }), stem, rasterize);
}

std::string save_difference(const Output& oa, const Output& ob, const Tolerance& tol, const std::string& stem,
                            MeshDraw rasterize) {
  const Mesh a = weld(mesh(oa)), b = weld(mesh(ob));
  if (a.triangles.empty() || b.triangles.empty()) return save_view(ob, stem, rasterize);
  const std::vector<double> d = nearest_vertex_distance(a, b);
  constexpr int kLevels = 16;
  std::vector<Material> levels(kLevels);
  for (int i = 0; i < kLevels; ++i) {
    levels[size_t(i)].color = heat(double(i) / (kLevels - 1));
    levels[size_t(i)].kd = 0.9;
  }
  Vec3 lo, hi;
  bounds(b, lo, hi);
  const double scale = tol.abs > 0 ? tol.abs : 1;
  return draw(scene_of(b, lo, hi, levels,
                       [&](size_t t) {
                         double e = 0;
                         for (uint32_t v : b.triangles[t]) e = std::max(e, d[v]);
                         return uint32_t(std::lround(std::clamp(e / scale, 0.0, 1.0) * (kLevels - 1)));
                       }),
              stem, rasterize);
}

}  // namespace mesh_kind_detail

namespace {

std::string shape(const Output& o) {
  return std::to_string(mesh(o).triangles.size()) + " triangles, " + std::to_string(mesh(o).vertices.size()) +
         " vertices";
}
uint64_t count(const Output& o) { return mesh(o).triangles.size(); }
std::string check_frame(const Output&, const FrameOptions&) { return {}; }
const void* data(const Output& o) { return mesh(o).triangles.data(); }

}  // namespace

std::vector<double> nearest_vertex_distance(const Mesh& a, const Mesh& b) {
  std::vector<double> out(b.vertices.size(), kInfinity);
  if (a.vertices.empty()) return out;
  // A uniform grid over a's vertices, about two per cell; each query searches
  // shells of cells outwards until no nearer vertex can be in the next shell.
  Vec3 lo, hi;
  bounds(a, lo, hi);
  const Vec3 ext = hi - lo;
  const double diag = std::max(length(ext), 1e-30);
  const double cell = std::max(diag / std::cbrt(std::max<double>(1.0, double(a.vertices.size()) / 2.0)), 1e-12 * diag);
  const int n[3] = {std::max(1, int(ext.x / cell) + 1), std::max(1, int(ext.y / cell) + 1),
                    std::max(1, int(ext.z / cell) + 1)};
  auto cell_of = [&](const Vec3& p, int axis) {
    const double x = (axis == 0 ? p.x - lo.x : axis == 1 ? p.y - lo.y : p.z - lo.z) / cell;
    return std::clamp(int(std::floor(x)), 0, n[axis] - 1);
  };
  std::unordered_map<uint64_t, std::vector<uint32_t>> grid;
  auto key = [&](int i, int j, int k) { return (uint64_t(k) * uint64_t(n[1]) + uint64_t(j)) * uint64_t(n[0]) + uint64_t(i); };
  for (uint32_t v = 0; v < a.vertices.size(); ++v) {
    const Vec3 p = to_d(a.vertices[v]);
    grid[key(cell_of(p, 0), cell_of(p, 1), cell_of(p, 2))].push_back(v);
  }
  const int max_r = std::max({n[0], n[1], n[2]});
  for (size_t q = 0; q < b.vertices.size(); ++q) {
    const Vec3 p = to_d(b.vertices[q]);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      out[q] = kInfinity;
      continue;
    }
    const int c[3] = {cell_of(p, 0), cell_of(p, 1), cell_of(p, 2)};
    double best = kInfinity;
    for (int r = 0; r <= max_r; ++r) {
      // Every vertex in shell r is at least (r - 1) cells away (p may lie outside a's box: clamped).
      if (r > 1 && double(r - 1) * cell > best) break;
      for (int k = c[2] - r; k <= c[2] + r; ++k)
        for (int j = c[1] - r; j <= c[1] + r; ++j)
          for (int i = c[0] - r; i <= c[0] + r; ++i) {
            if (std::max({std::abs(i - c[0]), std::abs(j - c[1]), std::abs(k - c[2])}) != r) continue;
            if (i < 0 || j < 0 || k < 0 || i >= n[0] || j >= n[1] || k >= n[2]) continue;
            const auto it = grid.find(key(i, j, k));
            if (it == grid.end()) continue;
            for (uint32_t v : it->second) best = std::min(best, length(to_d(a.vertices[v]) - p));
          }
    }
    out[q] = best;
  }
  return out;
}

namespace mesh_kind_detail {

OutputKind base() {
  return OutputKind{
      .name = "mesh",
      .samples = "vertices",
      .sample = "vertices",
      .score = "dB (bounding-box diagonal over the worst vertex distance)",
      .legend = "max err = the largest distance from a vertex of either mesh to the other's nearest vertex (both "
                "welded), in world units; score = 20 log10(bounding-box diagonal / max err). Pictures: the mesh drawn "
                "by the z-buffer (Phong, both sides); differences: the mesh coloured by each triangle's vertex "
                "distance to the reference (blue 0 to red at the case's threshold). Goldens are binary PLY.",
      .write = write,
      .check_path = check_mesh_path,
      .read = read,
      .golden_extension = ".ply",
      .write_golden = write_golden,
      .compare = compare,
      .describe = describe,
      .describe_tolerance = describe_tolerance,
      .save_view = nullptr,        // set by mesh_kind<Draw>() (kinds/mesh_kind.h)
      .save_difference = nullptr,  // the same
      // Pictures as the image kind's (kinds/image_kind.h).
      .save_beside = save_picture_scaled,
      .picture_extension = image_kind().picture_extension,
      .picture_type = image_kind().picture_type,
      .shape = shape,
      .count = count,
      .check_frame = check_frame,
      .data = data,
  };
}

}  // namespace mesh_kind_detail

}  // namespace lockstep
