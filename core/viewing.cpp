// lockstep core: the viewing pipeline of the raster families (core/raster.h),
// shared by every implementation: world -> eye -> cull -> clip -> screen -> snap.
//
// Foley et al., 2nd ed., 6.5 (the viewing transformation), 3.14 (Sutherland and
// Hodgman's polygon clipping, here against planes in eye space), 15.2.4
// (back-face culling). Everything is double precision; the only rounding that
// decides coverage is the final snap to 1/256 pixel, done once per vertex, so
// that two triangles sharing an edge share its snapped endpoints exactly.
#include <algorithm>
#include <cmath>
#include <span>
#include <tuple>
#include <vector>

#include "core/raster.h"
#include "core/shading.h"

namespace lockstep {

namespace {

// ---------------------------------------------------------------- eye space

// A vertex on its way through the pipeline: eye-space position plus what is
// interpolated along a clipped edge.
struct EyeVertex {
  Vec3 eye;     // x right, y up, z forward (depth along the view axis)
  Vec3 world;
  Vec3 normal;  // as given (not yet flipped towards the viewer)
  Vec3 color;
};

Vec3 eye_from_world(const Camera& c, const Vec3& p) {
  const Vec3 d = p - c.eye;
  return {dot(d, c.right), dot(d, c.up), dot(d, c.forward)};
}

// ---------------------------------------------------------------- clipping

// The clipping planes, as signed distances that are >= 0 inside: the hither
// plane z = near, and the four planes of the guard band |x|, |y| <= g z with
// g = kGuardBand * pitch (the band kGuardBand pixels either side of the image
// centre; far outside any image, so its cuts are never seen).
struct ClipPlanes {
  double near_z, g;
  static constexpr int kCount = 5;
  double distance(int k, const Vec3& e) const {
    switch (k) {
      case 0: return e.z - near_z;
      case 1: return g * e.z - e.x;
      case 2: return g * e.z + e.x;
      case 3: return g * e.z - e.y;
      default: return g * e.z + e.y;
    }
  }
};

// The point where edge a-b crosses plane k. The same edge is met from both
// triangles that share it, in opposite directions; interpolating always from
// the lexicographically smaller end makes both get the same point, bit for bit.
EyeVertex intersect(const ClipPlanes& planes, int k, const EyeVertex& a, const EyeVertex& b) {
  const bool swap = std::tie(b.eye.x, b.eye.y, b.eye.z) < std::tie(a.eye.x, a.eye.y, a.eye.z);
  const EyeVertex& p = swap ? b : a;
  const EyeVertex& q = swap ? a : b;
  const double dp = planes.distance(k, p.eye), dq = planes.distance(k, q.eye);
  const double t = dp / (dp - dq);
  auto lerp = [t](const Vec3& u, const Vec3& v) { return u + t * (v - u); };
  EyeVertex r{lerp(p.eye, q.eye), lerp(p.world, q.world), lerp(p.normal, q.normal), lerp(p.color, q.color)};
  if (k == 0) r.eye.z = planes.near_z;  // exactly on the hither plane
  if (length(r.normal) > 0) r.normal = normalize(r.normal);
  return r;
}

// Sutherland-Hodgman: the polygon clipped against each plane in turn.
std::vector<EyeVertex> clip(const ClipPlanes& planes, std::vector<EyeVertex> poly) {
  for (int k = 0; k < ClipPlanes::kCount && !poly.empty(); ++k) {
    std::vector<EyeVertex> out;
    for (size_t i = 0; i < poly.size(); ++i) {
      const EyeVertex& a = poly[i];
      const EyeVertex& b = poly[(i + 1) % poly.size()];
      const bool a_in = planes.distance(k, a.eye) >= 0, b_in = planes.distance(k, b.eye) >= 0;
      if (a_in) out.push_back(a);
      if (a_in != b_in) out.push_back(intersect(planes, k, a, b));
    }
    poly = std::move(out);
  }
  return poly;
}

// ---------------------------------------------------------------- clipping far-away triangles
//
// An edge from a vertex 1e21 units away to one as far the other side, cut by
// the guard band a few thousand units from the eye, loses everything to
// cancellation in double: the cut point p + t (q - p) is off by |p| 2^-53,
// 1e5 units, and the clipped polygon comes out anywhere or empty (issue #22:
// a front-facing plane at 1e21 behind a small triangle vanished from every
// rasterizer). So a triangle whose eye coordinates are that large against
// what a pixel is at the hither plane is clipped in __float128 (113 bits: the
// same cut is off by |p| 2^-113, 1e-13 pixels at 1e21 and 1e-4 at 1e30),
// starting again from its world coordinates (the eye transform of a huge
// vertex cancels the same way), and only the clipped polygon, whose
// coordinates are small, goes back to double. Both ends of an edge are met in
// the same order as in double (the lexicographically smaller first), so two
// triangles sharing an edge still share its cut points.

using Wide = __float128;
using WideVec = Vec3T<Wide>;

struct WideVertex {
  WideVec eye, world;
  Vec3 normal, color;  // bounded values: interpolated in double
};

// Whether double clipping of these vertices can be off by more than 2^-12
// pixel at the hither plane: |p| 2^-53 / (near pitch) > 2^-12. Scale-free
// (scaling a scene and its hither by 2^k keeps the decision).
bool needs_wide_clip(const EyeVertex* v, int n, double near_z, double pitch) {
  double m = 0;
  for (int i = 0; i < n; ++i) m = std::max(m, max_abs_component(v[i].eye));
  return m > std::ldexp(near_z * pitch, 41);
}

std::vector<EyeVertex> clip_wide(const Camera& c, const ClipPlanes& planes, const EyeVertex (&v)[3]) {
  const WideVec eye(c.eye), right(c.right), up(c.up), forward(c.forward);
  const Wide near_z = planes.near_z, g = planes.g;
  auto distance = [&](int k, const WideVec& e) -> Wide {
    switch (k) {
      case 0: return e.z - near_z;
      case 1: return g * e.z - e.x;
      case 2: return g * e.z + e.x;
      case 3: return g * e.z - e.y;
      default: return g * e.z + e.y;
    }
  };
  std::vector<WideVertex> poly;
  for (const EyeVertex& x : v) {
    const WideVec w(x.world), d = w - eye;
    poly.push_back({{dot(d, right), dot(d, up), dot(d, forward)}, w, x.normal, x.color});
  }
  for (int k = 0; k < ClipPlanes::kCount && !poly.empty(); ++k) {
    std::vector<WideVertex> out;
    for (size_t i = 0; i < poly.size(); ++i) {
      const WideVertex& a = poly[i];
      const WideVertex& b = poly[(i + 1) % poly.size()];
      const bool a_in = distance(k, a.eye) >= 0, b_in = distance(k, b.eye) >= 0;
      if (a_in) out.push_back(a);
      if (a_in == b_in) continue;
      const bool swap = std::tie(b.eye.x, b.eye.y, b.eye.z) < std::tie(a.eye.x, a.eye.y, a.eye.z);
      const WideVertex& p = swap ? b : a;
      const WideVertex& q = swap ? a : b;
      const Wide dp = distance(k, p.eye), dq = distance(k, q.eye);
      const Wide t = dp / (dp - dq);
      const double td = double(t);
      WideVertex r{p.eye + t * (q.eye - p.eye), p.world + t * (q.world - p.world), p.normal + td * (q.normal - p.normal),
                   p.color + td * (q.color - p.color)};
      if (k == 0) r.eye.z = near_z;
      if (length(r.normal) > 0) r.normal = normalize(r.normal);
      out.push_back(r);
    }
    poly = std::move(out);
  }
  std::vector<EyeVertex> result;
  for (const WideVertex& w : poly) result.push_back({Vec3(w.eye), Vec3(w.world), w.normal, w.color});
  return result;
}

bool finite(const Vec3& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

bool inside_all(const ClipPlanes& planes, const EyeVertex* v, int n) {
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < ClipPlanes::kCount; ++k)
      if (planes.distance(k, v[i].eye) < 0) return false;
  return true;
}

// ---------------------------------------------------------------- screen

// Eye space -> screen (pixels, y down) -> snapped (1/256 pixel). The image
// plane at distance 1 has pixel pitch c.pitch and its centre at (W/2, H/2)
// in screen coordinates, so pixel (i, j)'s centre (i + 1/2, j + 1/2) is the
// camera's sx(i), sy(j) (core/camera.h).
ScreenVertex to_screen(const Camera& c, const EyeVertex& e) {
  const double xs = 0.5 * c.width + e.eye.x / (e.eye.z * c.pitch);
  const double ys = 0.5 * c.height - e.eye.y / (e.eye.z * c.pitch);
  ScreenVertex v;
  v.x = int32_t(std::llround(xs * kSubpixel));
  v.y = int32_t(std::llround(ys * kSubpixel));
  v.z = e.eye.z;
  v.world = e.world;
  v.normal = e.normal;
  v.color = e.color;
  return v;
}

// Twice the signed area of the snapped triangle, exactly: E01(v2).
int64_t snapped_area(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c) {
  return int64_t(b.x - a.x) * (c.y - a.y) - int64_t(b.y - a.y) * (c.x - a.x);
}

// ---------------------------------------------------------------- spheres

}  // namespace

// How many latitude rings a sphere needs so that the tessellation's silhouette
// is within tess_error pixels of the true one. A lat-long mesh with N rings and
// 2N meridians has facets at most pi/N on a side in angle, so no point of the
// sphere is farther than r (1 - cos(pi / (N sqrt 2))) from the mesh (the facet's
// circumcircle has angular radius at most (pi/N)/sqrt 2). Seen from depth
// z_near = (centre depth - r) or more, one unit there is at most
// 1 / (z_near pitch) pixels, so the screen error is at most
//     R (1 - cos(pi / (N sqrt 2))),  R = r / (z_near pitch),
// and N is the smallest count that keeps it below tess_error (2..256).
int sphere_rings(double radius, double centre_z, const Camera& cam, double near_z, double tess_error) {
  constexpr int kMin = 2, kMax = 256;
  const double z_near = std::max(centre_z - radius, near_z);
  const double r_px = radius / (z_near * cam.pitch);
  if (r_px * (1 - std::cos(M_PI / (kMin * std::sqrt(2.0)))) <= tess_error) return kMin;
  const double max_angle = std::sqrt(2.0) * std::acos(1 - tess_error / r_px);  // pi/N <= this
  return std::clamp(int(std::ceil(M_PI / max_angle)), kMin, kMax);
}

// A lat-long unit sphere: `rings` bands of latitude, 2 * rings meridians;
// triangles at the poles, two per quad elsewhere, counter-clockwise seen from
// outside (theta grows southwards, phi eastwards).
UnitSphere unit_sphere(int rings) {
  UnitSphere m;
  m.rings = rings;
  const int meridians = 2 * rings;
  // Vertex (ring k = 0..rings, meridian l): the poles are stored once.
  auto index = [&](int k, int l) -> uint32_t {
    if (k == 0) return 0;
    if (k == rings) return 1;
    return uint32_t(2 + (k - 1) * meridians + (l % meridians));
  };
  m.unit.reserve(size_t(2 + (rings - 1) * meridians));
  m.tri.reserve(size_t(2 * (rings - 1) * meridians));
  m.unit.push_back({0, 0, 1});
  m.unit.push_back({0, 0, -1});
  // The sines and cosines of the meridians' longitudes once, not once per ring.
  std::vector<double> cos_phi(static_cast<size_t>(meridians)), sin_phi(static_cast<size_t>(meridians));
  for (int l = 0; l < meridians; ++l) {
    const double phi = 2 * M_PI * l / meridians;
    cos_phi[size_t(l)] = std::cos(phi);
    sin_phi[size_t(l)] = std::sin(phi);
  }
  for (int k = 1; k < rings; ++k) {
    const double theta = M_PI * k / rings;
    const double sin_theta = std::sin(theta), cos_theta = std::cos(theta);
    for (int l = 0; l < meridians; ++l)
      m.unit.push_back({sin_theta * cos_phi[size_t(l)], sin_theta * sin_phi[size_t(l)], cos_theta});
  }
  for (int k = 0; k < rings; ++k)
    for (int l = 0; l < meridians; ++l) {
      const uint32_t a = index(k, l), b = index(k + 1, l), c = index(k + 1, l + 1), d = index(k, l + 1);
      if (k == 0) m.tri.push_back({a, b, c});
      else if (k == rings - 1) m.tri.push_back({a, b, d});
      else {
        m.tri.push_back({a, b, c});
        m.tri.push_back({a, c, d});
      }
    }
  return m;
}

// Whether a sphere lies wholly outside the view (behind the hither plane or
// beyond a side of the image, with a pixel of margin): then it is not tessellated.
bool sphere_outside(const Camera& c, const Vec3& e, double r, double near_z) {
  if (e.z + r < near_z) return true;
  const double hx = (0.5 * c.width + 1) * c.pitch, hy = (0.5 * c.height + 1) * c.pitch;
  // Side planes through the eye: x = hx z etc.; unit normals (1, 0, -hx)/|...|.
  const double nx = std::sqrt(1 + hx * hx), ny = std::sqrt(1 + hy * hy);
  return (e.x - hx * e.z) / nx > r || (-e.x - hx * e.z) / nx > r || (e.y - hy * e.z) / ny > r ||
         (-e.y - hy * e.z) / ny > r;
}

namespace {

struct SphereMesh {
  std::vector<Vec3> position, normal;
  std::vector<std::array<uint32_t, 3>> tri;  // counter-clockwise seen from the visible side
};

// The unit sphere moved to the centre and scaled. Normals are the exact sphere
// normals, pointing to the visible side (inwards for NFF's negative radius),
// and the winding follows them.
SphereMesh tessellate_sphere(const Vec3& centre, double signed_radius, int rings) {
  const UnitSphere u = unit_sphere(rings);
  const double r = std::abs(signed_radius);
  SphereMesh m;
  for (const Vec3& unit : u.unit) {
    m.position.push_back(centre + r * unit);
    m.normal.push_back(signed_radius > 0 ? unit : -unit);
  }
  for (const auto& [a, b, c] : u.tri) {
    if (signed_radius > 0) m.tri.push_back({a, b, c});
    else m.tri.push_back({a, c, b});
  }
  return m;
}

// ---------------------------------------------------------------- one triangle

struct Emitter {
  const Scene& scene;
  const RasterSettings& s;
  ScreenMesh& mesh;
  ClipPlanes planes;

  // Adds world triangle (a, b, c), counter-clockwise seen from its front, of
  // primitive prim; face_normal is its unit front normal; two_sided: the back
  // is visible too; flat_color: the flat-shading colour, already evaluated.
  void triangle(const EyeVertex (&v)[3], uint32_t prim, uint32_t source_tri, const Vec3& face_normal,
                bool two_sided, const Vec3& flat_color) {
    const Camera& cam = mesh.camera;
    // Back-face culling in world space: the eye behind the plane of the face
    // (or in it: an edge-on face covers nothing).
    const bool front = dot(face_normal, cam.eye - v[0].world) > 0;
    if (!front && !two_sided && s.cull == CullMode::kWorld) {
      ++mesh.culled;
      return;
    }
    // The triangle itself, or the polygon left of it after clipping.
    // Coordinates whose differences overflow double (beyond about 1e308 apart)
    // or a NaN: nothing to draw with. Said, not hidden (issue #22).
    if (!finite(v[0].eye) || !finite(v[1].eye) || !finite(v[2].eye)) {
      mesh.drop("eye coordinates not finite (overflow in double)");
      return;
    }
    const EyeVertex* poly = v;
    size_t n = 3;
    std::vector<EyeVertex> clipped;
    if (!inside_all(planes, v, 3)) {
      ++mesh.clipped;
      clipped = needs_wide_clip(v, 3, planes.near_z, cam.pitch) ? clip_wide(cam, planes, v)
                                                                : clip(planes, std::vector<EyeVertex>(v, v + 3));
      if (clipped.size() < 3) return;  // wholly outside
      poly = clipped.data();
      n = clipped.size();
    }
    // Fan of the (convex) polygon.
    for (size_t k = 1; k + 1 < n; ++k) {
      ScreenTri t;
      t.v = {to_screen(cam, poly[0]), to_screen(cam, poly[k]), to_screen(cam, poly[k + 1])};
      t.prim = prim;
      t.source_tri = source_tri;
      t.flat_color = flat_color;
      const int64_t area = snapped_area(t.v[0], t.v[1], t.v[2]);
      if (area == 0) {  // edge-on after snapping: covers no sample
        ++mesh.degenerate;
        continue;
      }
      // Back-face culling in projection space: a front face is counter-clockwise
      // as the viewer sees it (NFF's order), which with y down is negative area.
      if (area > 0 && !two_sided && s.cull == CullMode::kProjection) {
        ++mesh.culled;
        continue;
      }
      // The rasteriser takes positive area: front faces are reordered; so is a
      // face drawn from its back (two-sided, cull none, or a world-space front
      // face that snapping turned over) the other way round.
      if (area < 0) std::swap(t.v[1], t.v[2]);
      t.face_normal = front ? face_normal : -face_normal;
      mesh.tris.push_back(t);
    }
  }
};

// The lighting at a vertex for Gouraud shading: Phong with the normal turned
// towards the viewer, as ray casting turns it per hit.
Vec3 lit(const Scene& scene, const Material& m, const Vec3& eye, const Vec3& p, Vec3 n) {
  const Vec3 v = normalize(eye - p);
  if (dot(n, v) < 0) n = -n;
  return phong(scene, m, p, n, v);
}

}  // namespace

// ---------------------------------------------------------------- the pipeline

ScreenMesh view_frame(const Scene& scene, int width, int height) {
  Vec3 lo, hi;
  scene_bounds(scene, lo, hi);
  return view_frame(scene, width, height, lo, hi);
}

ScreenMesh view_frame(const Scene& scene, int width, int height, const Vec3& lo, const Vec3& hi) {
  ScreenMesh mesh;
  mesh.camera = Camera::from_view(scene.view, width, height);
  mesh.width = width;
  mesh.height = height;
  const Camera& cam = mesh.camera;

  // Far: the deepest corner of the scene's bounds. Near: the hither distance;
  // rasterisation needs a positive one, so hither 0 becomes a millionth of far.
  double far_z = 0;
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
    far_z = std::max(far_z, eye_from_world(cam, corner).z);
  }
  mesh.far_z = std::max(far_z * (1 + 1e-6), 1e-300);
  mesh.near_z = scene.view.hither > 0 ? scene.view.hither : mesh.far_z * 1e-6;
  if (mesh.far_z <= mesh.near_z) mesh.far_z = 2 * mesh.near_z;
  return mesh;
}

// A tessellated sphere or cone (positions, normals, triangles) into the mesh
// as primitive prim; returns the triangles emitted. Every vertex goes to eye
// space once (and is lit once, for Gouraud): a vertex of the lat-long mesh is
// shared by up to six triangles.
template <class Tessellation>
uint64_t emit_surface(const Scene& scene, const RasterSettings& s, const Camera& cam, Emitter& emit,
                      const Tessellation& tm, const Material& m, uint32_t prim) {
  std::vector<EyeVertex> ev;
  ev.reserve(tm.position.size());
  for (size_t i = 0; i < tm.position.size(); ++i) {
    ev.push_back(EyeVertex{eye_from_world(cam, tm.position[i]), tm.position[i], tm.normal[i], {}});
    if (s.shading == Shading::kGouraud) ev.back().color = lit(scene, m, cam.eye, ev.back().world, ev.back().normal);
  }
  uint64_t emitted = 0;
  for (uint32_t t = 0; t < tm.tri.size(); ++t) {
    const auto& [a, b, c] = tm.tri[t];
    EyeVertex v[3] = {ev[a], ev[b], ev[c]};
    const Vec3 fn = cross(v[1].world - v[0].world, v[2].world - v[0].world);
    if (length(fn) == 0) continue;
    const Vec3 face = normalize(fn);
    // The flat colour only for faces that may be drawn: spheres and cones are
    // one-sided (NFF's rule), so a back face is culled in world space
    // (Emitter::triangle).
    const bool back = !(dot(face, cam.eye - v[0].world) > 0);
    Vec3 flat;
    if (s.shading == Shading::kFlat && !(back && s.cull == CullMode::kWorld))
      flat = lit(scene, m, cam.eye, (v[0].world + v[1].world + v[2].world) / 3.0, face);
    ++emitted;
    emit.triangle(v, prim, t, face, false, flat);
  }
  return emitted;
}

void view_spheres(const Scene& scene, const RasterSettings& s, uint32_t first, uint32_t last, ScreenMesh& mesh) {
  const Camera& cam = mesh.camera;
  Emitter emit{scene, s, mesh, {mesh.near_z, kGuardBand * cam.pitch}};
  // Each sphere tessellated as finely as its size on screen needs.
  for (uint32_t k = first; k < last; ++k) {
    const Vec3 c = scene.sphere_center[k];
    const double r = std::abs(scene.sphere_radius[k]);
    const Vec3 ce = eye_from_world(cam, c);
    if (sphere_outside(cam, ce, r, mesh.near_z)) continue;
    const SphereMesh sm = tessellate_sphere(c, scene.sphere_radius[k], sphere_rings(r, ce.z, cam, mesh.near_z, s.tess_error));
    mesh.sphere_tris += emit_surface(scene, s, cam, emit, sm, scene.materials[scene.sphere_material[k]], k);
  }
}

void view_polygons(const Scene& scene, const RasterSettings& s, uint32_t first, uint32_t last, ScreenMesh& mesh) {
  const Camera& cam = mesh.camera;
  Emitter emit{scene, s, mesh, {mesh.near_z, kGuardBand * cam.pitch}};
  auto eye_vertex = [&](const Vec3& p, const Vec3& n) { return EyeVertex{eye_from_world(cam, p), p, n, {}}; };
  // Each polygon's triangulation, with the polygon's plane normal, or the
  // vertex normals of patches.
  for (uint32_t p = first; p < last; ++p) {
    const Material& m = scene.materials[scene.poly_material[p]];
    const Vec3 face = scene.poly_plane[p].n;
    if (length(face) == 0) {
      // No plane normal: a polygon of zero area covers nothing; one whose
      // normal only overflowed or underflowed (measured: coordinates from
      // 1e77 up, or 1e-82 down) is left out, and said so.
      if (normal_lost_to_range(scene.polygon_vertices(p))) mesh.drop(kNormalLostToRange);
      continue;
    }
    Vec3 flat;
    if (s.shading == Shading::kFlat) {
      // One lighting evaluation per polygon, at its centroid.
      Vec3 centroid;
      for (const Vec3& x : scene.polygon_vertices(p)) centroid += x;
      flat = lit(scene, m, cam.eye, centroid / double(scene.polygon_vertices(p).size()), face);
    }
    for (uint32_t t = scene.poly_tri_first[p]; t < scene.poly_tri_first[p + 1]; ++t) {
      EyeVertex v[3];
      for (int i = 0; i < 3; ++i) {
        const uint32_t vi = scene.tri_vertex[t][i];
        v[i] = eye_vertex(scene.vertex[vi], scene.poly_is_patch[p] ? scene.vertex_normal[vi] : face);
        if (s.shading == Shading::kGouraud) v[i].color = lit(scene, m, cam.eye, v[i].world, v[i].normal);
      }
      ++mesh.scene_tris;
      emit.triangle(v, scene.sphere_count() + p, t, face, m.two_sided(), flat);
    }
  }
}

// ---------------------------------------------------------------- cones

// How many facets around its axis a cone needs so that the tessellation's
// silhouette is within tess_error pixels of the true one. The cone's side is a
// ruled surface: straight along the axis, so one band of facets between the
// two end circles is exact along it; around it, each end circle becomes a
// regular N-gon inscribed in it, at most r (1 - cos(pi / N)) from the circle,
// and every point of the side between is within the larger end's distance.
// Seen from eye depth z_near (the nearest either end disc can come, not less
// than hither) one unit is at most 1 / (z_near pitch) pixels, so the screen
// error is at most R (1 - cos(pi / N)), R = max(r0, r1) / (z_near pitch), and
// N is the smallest count that keeps it below tess_error (3..512: a sphere's
// 256 rings have 512 meridians).
int cone_segments(double r0, double r1, double base_z, double apex_z, const Camera& cam,
                  double near_z, double tess_error) {
  constexpr int kMin = 3, kMax = 512;
  const double r = std::max(r0, r1);
  const double z_near = std::max(std::min(base_z - r0, apex_z - r1), near_z);
  const double r_px = r / (z_near * cam.pitch);
  if (r_px * (1 - std::cos(M_PI / kMin)) <= tess_error) return kMin;
  const double max_angle = std::acos(1 - tess_error / r_px);  // pi/N <= this
  return std::clamp(int(std::ceil(M_PI / max_angle)), kMin, kMax);
}

ConeMesh tessellate_cone(const Vec3& base, double r0, const Vec3& apex, double r1, bool inside,
                         int segments) {
  ConeMesh m;
  const Vec3 axis = apex - base;
  const double h = length(axis);
  const Vec3 u = axis / h;
  // Two unit vectors across the axis (any pair: the cone is round).
  const Vec3 a = normalize(std::abs(u.x) < 0.9 ? cross(u, Vec3{1, 0, 0}) : cross(u, Vec3{0, 1, 0}));
  const Vec3 b = cross(u, a);
  const double k = (r1 - r0) / h;  // the slope: the radius grows by k per unit of height
  const double scale = 1 / std::sqrt(1 + k * k);
  // The side's normal at longitude phi is (radial - k u) / sqrt(1 + k^2), the
  // same at every height (core/shading.cpp's cone gradient, normalised).
  auto normal_at = [&](double phi) {
    const Vec3 n = (std::cos(phi) * a + std::sin(phi) * b - k * u) * scale;
    return inside ? -n : n;
  };
  const int n = segments;
  // Per longitude l: the base vertex 2l, the apex vertex 2l + 1. An end of
  // radius 0 is a point, where the normal is not defined: there each facet
  // gets its own vertex with the normal of the facet's middle longitude, so
  // that the shading does not average round the tip.
  for (int l = 0; l < n; ++l) {
    const double phi = 2 * M_PI * l / n;
    const Vec3 radial = std::cos(phi) * a + std::sin(phi) * b;
    const Vec3 nrm = normal_at(phi);
    const double mid = 2 * M_PI * (l + 0.5) / n;
    m.position.push_back(base + r0 * radial);
    m.normal.push_back(r0 > 0 ? nrm : normal_at(mid));
    m.position.push_back(apex + r1 * radial);
    m.normal.push_back(r1 > 0 ? nrm : normal_at(mid));
  }
  for (int l = 0; l < n; ++l) {
    const uint32_t b0 = uint32_t(2 * l), a0 = b0 + 1, b1 = uint32_t(2 * ((l + 1) % n)), a1 = b1 + 1;
    // Counter-clockwise seen from outside (longitude grows anticlockwise about u).
    std::array<std::array<uint32_t, 3>, 2> t = {{{b0, b1, a1}, {b0, a1, a0}}};
    if (r1 == 0) t = {{{b0, b1, a0}, {0, 0, 0}}};  // the apex is a point: one triangle
    if (r0 == 0) t = {{{b0, a1, a0}, {0, 0, 0}}};  // the base is a point
    for (const auto& tri : t) {
      if (tri[0] == tri[1]) continue;
      m.tri.push_back(inside ? std::array<uint32_t, 3>{tri[0], tri[2], tri[1]} : tri);
    }
  }
  return m;
}

void view_cones(const Scene& scene, const RasterSettings& s, uint32_t first, uint32_t last,
                ScreenMesh& mesh) {
  const Camera& cam = mesh.camera;
  Emitter emit{scene, s, mesh, {mesh.near_z, kGuardBand * cam.pitch}};
  for (uint32_t k = first; k < last; ++k) {
    const Vec3 &base = scene.cone_base[k], &apex = scene.cone_apex[k];
    const double r0 = scene.cone_r0[k], r1 = scene.cone_r1[k];
    // Outside the view: the ball around the axis' midpoint that holds both end discs.
    const double half = 0.5 * length(apex - base), rmax = std::max(r0, r1);
    if (sphere_outside(cam, eye_from_world(cam, 0.5 * (base + apex)),
                       std::sqrt(half * half + rmax * rmax), mesh.near_z))
      continue;
    const int n = cone_segments(r0, r1, eye_from_world(cam, base).z, eye_from_world(cam, apex).z,
                                cam, mesh.near_z, s.tess_error);
    const ConeMesh cm = tessellate_cone(base, r0, apex, r1, scene.cone_inside[k] != 0, n);
    const uint32_t prim = scene.cone_first_prim() + k;
    mesh.cone_tris += emit_surface(scene, s, cam, emit, cm, scene.materials[scene.cone_material[k]], prim);
  }
}

ScreenMesh view_scene(const Scene& scene, int width, int height, const RasterSettings& s) {
  // The frame: camera, near and far.
  ScreenMesh mesh = view_frame(scene, width, height);
  // Spheres first (tessellated as finely as their size on screen needs), then
  // polygons, then cones (tessellated likewise): the scene's primitive order,
  // which decides ties in depth.
  view_spheres(scene, s, 0, scene.sphere_count(), mesh);
  view_polygons(scene, s, 0, scene.polygon_count(), mesh);
  view_cones(scene, s, 0, scene.cone_count(), mesh);
  return mesh;
}

// ---------------------------------------------------------------- samples and depth

std::vector<std::array<int32_t, 2>> sample_offsets(const RasterSettings& s) {
  const int n = int(std::lround(std::sqrt(double(s.spp))));
  std::vector<std::array<int32_t, 2>> out;
  for (int b = 0; b < n; ++b)
    for (int a = 0; a < n; ++a) {
      // Regular grid position relative to the pixel centre, in pixels.
      double x = (a + 0.5) / n - 0.5, y = (b + 0.5) / n - 0.5;
      if (s.grid == SampleGrid::kRotated) {
        const double xr = x - y / n, yr = y + x / n;  // the shear that makes every row and column distinct
        x = xr;
        y = yr;
      }
      out.push_back({int32_t(std::lround((0.5 + x) * kSubpixel)), int32_t(std::lround((0.5 + y) * kSubpixel))});
    }
  return out;
}

double stored_depth(DepthFormat f, double z, double near_z, double far_z) {
  // Window depth: 0 at the near plane, 1 at the far one, affine in 1/z (so in screen space).
  const double window = (1 / near_z - 1 / z) / (1 / near_z - 1 / far_z);
  switch (f) {
    case DepthFormat::kFloat: return double(float(window));
    case DepthFormat::kReversed: return double(float(near_z / z));
    case DepthFormat::kFixed24: return std::nearbyint(std::clamp(window, 0.0, 1.0) * double((1 << 24) - 1));
    case DepthFormat::kDouble: break;
  }
  return window;
}

double empty_depth(DepthFormat f) { return f == DepthFormat::kReversed ? -kInfinity : kInfinity; }

}  // namespace lockstep
