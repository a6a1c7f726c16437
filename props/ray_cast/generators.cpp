#include "props/ray_cast/generators.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>

#include "core/camera.h"
#include "props/gen/numbers.h"
#include "props/ray_cast/meshes.h"

namespace lockstep::props::ray_cast {

using rc::Gen;
using namespace gen;

// ---------------------------------------------------------------- case pieces

namespace {

Material random_material(bool allow_two_sided) {
  Material m;
  m.color = {*uniform(0.1, 1), *uniform(0.1, 1), *uniform(0.1, 1)};
  m.kd = *uniform(0.3, 1);
  m.ks = *uniform(0, 0.5);
  m.shine = *uniform(1, 50);
  m.transmittance = allow_two_sided && *chance(1, 3) ? 0.5 : 0.0;
  return m;
}

// A simple (star-shaped) polygon whose vertices are exactly coplanar: z = a x + b y + c on a
// dyadic grid, then a signed permutation of the axes and a dyadic offset, all exact.
struct StarPolygon {
  std::vector<Vec3> verts;
  // map from the polygon's 2D parameter plane to 3D (exact for grid inputs)
  int64_t A = 0, B = 0, Cc = 0;
  int perm[3] = {0, 1, 2};
  int sign[3] = {1, 1, 1};
  Vec3 offset;
  int s = 0;  // size exponent: the polygon spans about 2^s
  double grid() const { return std::ldexp(1.0, s - 19); }
  Vec3 embed(int64_t X, int64_t Y) const {  // X, Y in units of 2^(s-16)
    const double x = std::ldexp(double(X), s - 16), y = std::ldexp(double(Y), s - 16);
    const double z = std::ldexp(double(A * X + B * Y), s - 19) + std::ldexp(double(Cc), s - 19);
    const double p[3] = {x, y, z};
    Vec3 q;
    for (int i = 0; i < 3; ++i) q[perm[i]] = sign[i] * p[i];
    return q + offset;
  }
  std::vector<std::pair<int64_t, int64_t>> xy;  // the vertices' parameters
};

StarPolygon star_polygon(int s_lo, int s_hi, double offset_range) {
  StarPolygon p;
  p.s = int(*int_towards(s_lo, s_hi, std::clamp(0, s_lo, s_hi)));
  p.A = *int_towards(-32, 32, 0);
  p.B = *int_towards(-32, 32, 0);
  p.Cc = *int_towards(-(1 << 22), 1 << 22, 0);
  const int64_t perm = *int_in(0, 5);
  const int perms[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
  for (int i = 0; i < 3; ++i) {
    p.perm[i] = perms[perm][i];
    p.sign[i] = *chance(1, 2) ? -1 : 1;
  }
  const double g = p.grid();
  for (int i = 0; i < 3; ++i) p.offset[i] = round_to(*uniform(-offset_range, offset_range), std::ilogb(g));
  // Vertices by increasing angle around the centre with every angular gap (the
  // closing one included) below pi: the polygon is star-shaped about the centre,
  // hence simple; radii vary, so it is often concave.
  const int n = int(*int_towards(3, 8, 3));
  std::vector<int64_t> w(static_cast<size_t>(n));
  int64_t sum = 0;
  for (auto& x : w) sum += (x = *int_towards(1, 64, 16));
  std::vector<int64_t> gap(static_cast<size_t>(n));
  bool ok = true;
  for (int i = 0; i < n; ++i) ok &= (gap[size_t(i)] = std::max<int64_t>(1, 1024 * w[size_t(i)] / sum)) < 500;
  if (!ok)
    for (auto& g : gap) g = 1024 / n;
  int64_t k = *int_in(0, 1023);
  for (int i = 0; i < n; ++i) {
    const double theta = 2 * M_PI * double(k) / 1024.0;
    const double R = *uniform(0.3, 1.0) * 65536.0;
    const int64_t X = int64_t(std::llround(R * std::cos(theta))), Y = int64_t(std::llround(R * std::sin(theta)));
    if (p.xy.empty() || p.xy.back() != std::make_pair(X, Y)) p.xy.push_back({X, Y});
    k += gap[size_t(i)];
  }
  if (p.xy.size() < 3) p.xy = {{65536, 0}, {-32768, 56756}, {-32768, -56756}};
  for (auto [X, Y] : p.xy) p.verts.push_back(p.embed(X, Y));
  return p;
}

Vec3 approx_normal(const std::vector<Vec3>& v) {
  Vec3 n{0, 0, 0};
  for (size_t i = 0; i < v.size(); ++i) n += cross(v[i], v[(i + 1) % v.size()]);
  const double len = length(n);
  return len > 0 ? n / len : Vec3{0, 0, 1};
}

// tmin / tmax choices: mostly (0, inf).
void range_for(Ray& r, double t_target) {
  const int64_t k = *int_in(0, 9);
  if (k == 7) r.tmin = t_target * *log_uniform(1e-6, 0.5);
  if (k == 8) r.tmax = t_target * *log_uniform(0.5, 4);
  if (k == 9) {
    r.tmin = t_target * *log_uniform(1e-6, 0.5);
    r.tmax = t_target * *log_uniform(0.5, 4);
  }
}

Vec3 scaled_dir(const Vec3& d) { return d * std::ldexp(1.0, int(*int_towards(-4, 4, 0))); }

void ensure_valid_view(View& v) {
  const Vec3 dir = v.at - v.from;
  if (length(dir) == 0) v.at = v.from + Vec3{0, 0, -1};
  const Vec3 side = cross(normalize(v.at - v.from), v.up);
  if (!(length(side) > 1e-3 * length(v.up))) {
    const Vec3 f = normalize(v.at - v.from);
    v.up = std::abs(f.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
  }
}

// ---------------------------------------------------------------- well-conditioned generators

Case rays_at_sphere() {
  Case c;
  c.generator = "rays_at_sphere";
  Vec3 center;
  for (int i = 0; i < 3; ++i) center[i] = *chance(1, 5) ? 0.0 : *signed_log_uniform(1e-2, 1e2);
  const double r = *log_uniform(0.1, 10);
  c.has_sphere = true;
  c.sphere = Sphere{center, r};
  add_sphere(c.scene, center, r, add_material(c.scene, Material{}));
  const int n = int(*int_towards(1, 20, 1));
  for (int i = 0; i < n; ++i) {
    Ray ray;
    const int64_t kind = *int_in(0, 9);
    if (kind < 7) {  // from outside, aimed at or near the sphere
      const double dist = *log_uniform(1.05, 100) * r;
      ray.o = center + *unit_dir() * dist;
      const Vec3 target = center + *unit_dir() * (r * *uniform(0, 1.3));
      ray.d = scaled_dir(target - ray.o);
      if (kind == 6) ray.d = -ray.d;  // the sphere behind
      range_for(ray, length(target - ray.o) / length(ray.d));
    } else if (kind < 9) {  // from inside
      ray.o = center + *unit_dir() * (r * *uniform(0, 0.95));
      ray.d = scaled_dir(*unit_dir());
    } else {  // anywhere
      for (int k = 0; k < 3; ++k) ray.o[k] = center[k] + *uniform(-50, 50) * r;
      ray.d = scaled_dir(*unit_dir());
    }
    c.rays.push_back(ray);
  }
  return c;
}

Case rays_at_plane() {
  Case c;
  c.generator = "rays_at_plane";
  const Vec3 n = *unit_dir();
  Vec3 p0;
  for (int i = 0; i < 3; ++i) p0[i] = *chance(1, 5) ? 0.0 : *signed_log_uniform(1e-2, 1e2);
  c.has_plane = true;
  c.plane = Plane{n, -dot(n, p0)};
  const int cnt = int(*int_towards(1, 20, 1));
  for (int i = 0; i < cnt; ++i) {
    Ray ray;
    const double size = *log_uniform(0.01, 100);
    const Vec3 target = p0 + *unit_dir() * size;  // near the plane
    ray.o = target + *unit_dir() * (*log_uniform(0.1, 10) * size);
    const int64_t kind = *int_in(0, 3);
    ray.d = kind < 3 ? scaled_dir(target - ray.o) : scaled_dir(*unit_dir());
    range_for(ray, length(target - ray.o) / length(ray.d));
    c.rays.push_back(ray);
  }
  return c;
}

// Rays aimed at points of (or near) a polygon, from the given origin distances.
void rays_at(Case& c, const StarPolygon& p, int count, double dist_lo, double dist_hi) {
  int64_t lo_x = INT64_MAX, lo_y = INT64_MAX, hi_x = INT64_MIN, hi_y = INT64_MIN;
  for (auto [X, Y] : p.xy) lo_x = std::min(lo_x, X), hi_x = std::max(hi_x, X), lo_y = std::min(lo_y, Y), hi_y = std::max(hi_y, Y);
  const int64_t mx = (hi_x - lo_x) / 5 + 1, my = (hi_y - lo_y) / 5 + 1;
  const Vec3 n = approx_normal(p.verts);
  const double size = std::ldexp(1.0, p.s);
  for (int i = 0; i < count; ++i) {
    Ray ray;
    const Vec3 target = p.embed(*int_in(lo_x - mx, hi_x + mx), *int_in(lo_y - my, hi_y + my));
    Vec3 dir = *unit_dir();
    if (std::abs(dot(dir, n)) < 0.2) dir = normalize(dir + n * (dot(dir, n) < 0 ? -0.5 : 0.5));
    ray.o = target + dir * (*log_uniform(dist_lo, dist_hi) * size);
    ray.d = scaled_dir(target - ray.o);
    range_for(ray, length(target - ray.o) / length(ray.d));
    c.rays.push_back(ray);
  }
}

Case rays_at_polygon() {
  Case c;
  c.generator = "rays_at_polygon";
  const StarPolygon p = star_polygon(-3, 6, 4);
  add_polygon(c.scene, p.verts, {}, add_material(c.scene, random_material(true)));
  c.has_poly = true;
  c.poly = 0;
  rays_at(c, p, int(*int_towards(1, 20, 1)), 0.1, 100);
  return c;
}

Case scenes() {
  Case c;
  c.generator = "scenes";
  Scene& s = c.scene;
  const int ns = int(*int_towards(1, 6, 1));
  for (int i = 0; i < ns; ++i) {
    const Vec3 center{*uniform(-4, 4), *uniform(-4, 4), *uniform(-4, 4)};
    const double r = *uniform(0.2, 1.5) * (*chance(1, 10) ? -1 : 1);
    add_sphere(s, center, r, add_material(s, random_material(false)));
  }
  const int np = int(*int_towards(0, 3, 0));
  for (int i = 0; i < np; ++i) {
    const StarPolygon p = star_polygon(-1, 2, 4);
    add_polygon(s, p.verts, {}, add_material(s, random_material(true)));
  }
  const int nl = int(*int_towards(1, 3, 1));
  for (int i = 0; i < nl; ++i) {
    Light l;
    l.position = {*uniform(-10, 10), *uniform(-10, 10), *uniform(-10, 10)};
    l.has_color = *chance(1, 2);
    if (l.has_color) l.color = {*uniform(0.2, 1), *uniform(0.2, 1), *uniform(0.2, 1)};
    // lockstep's NFF extension (io/nff.h): attenuation on about a third of the
    // lights, strong enough to matter at the scene's distances (5 .. 25) ...
    if (*chance(1, 3)) l.atten = {*uniform(0.05, 1), *uniform(0, 0.3), *uniform(0, 0.02)};
    // ... and a spot on about a third, aimed near the middle of the scene so
    // that its cone (and often its edge) falls on something.
    if (*chance(1, 3)) {
      l.spot = true;
      const Vec3 target{*uniform(-3, 3), *uniform(-3, 3), *uniform(-3, 3)};
      const Vec3 aim = target - l.position;  // zero only when both shrink to one point
      l.spot_dir = length(aim) > 0 ? normalize(aim) : Vec3{0, 0, -1};
      l.spot_cutoff = *uniform(10, 90);
      l.spot_exponent = *chance(1, 4) ? 0.0 : *uniform(0, 40);
    }
    s.lights.push_back(l);
  }
  s.background = {*uniform(0, 1), *uniform(0, 1), *uniform(0, 1)};
  View& v = s.view;
  v.from = *unit_dir() * *uniform(10, 20);
  v.at = {*uniform(-1, 1), *uniform(-1, 1), *uniform(-1, 1)};
  v.up = *unit_dir();
  v.angle = *uniform(30, 70);
  v.hither = 1e-3;
  v.xres = v.yres = 16;
  ensure_valid_view(v);
  c.render_size = 16;
  const Camera cam = Camera::from_view(v, 16, 16);
  const int nr = int(*int_towards(1, 24, 1));
  for (int i = 0; i < nr; ++i) {
    Ray ray;
    const int64_t kind = *int_in(0, 9);
    // A point of some object (or near it) to aim at.
    Vec3 target;
    const uint32_t prim = uint32_t(*int_in(0, s.prim_count() - 1));
    if (prim < s.sphere_count()) {
      target = s.sphere_center[prim] + *unit_dir() * (std::abs(s.sphere_radius[prim]) * *uniform(0, 1.2));
    } else {
      const auto vs = s.polygon_vertices(prim - s.sphere_count());
      const double a = *uniform(0, 1), b = *uniform(0, 1 - a);
      target = vs[0] + (vs[1] - vs[0]) * a + (vs[2] - vs[0]) * b;
    }
    if (kind < 6) {  // from the eye
      ray = Ray{cam.eye, scaled_dir(target - cam.eye), 1e-3, kInfinity};
    } else if (kind < 8) {  // from the eye, anywhere in the field of view
      const double half = std::tan(v.angle * 0.5 * M_PI / 180.0);
      const Vec3 d = cam.forward + *uniform(-half, half) * cam.right + *uniform(-half, half) * cam.up;
      ray = Ray{cam.eye, scaled_dir(d), 1e-3, kInfinity};
    } else {  // from anywhere, at the object
      ray.o = {*uniform(-8, 8), *uniform(-8, 8), *uniform(-8, 8)};
      ray.d = scaled_dir(target - ray.o);
    }
    c.rays.push_back(ray);
  }
  return c;
}

// ---------------------------------------------------------------- stability generators

Case grazing_rays() {
  Case c;
  c.generator = "grazing_rays";
  Vec3 center;
  for (int i = 0; i < 3; ++i) center[i] = *chance(1, 5) ? 0.0 : *signed_log_uniform(1e-2, 1e2);
  const double r0 = *log_uniform(1e-2, 1e2);
  const double r = nudge(r0, *int_towards(-4, 4, 0));
  const double ratio = *log_uniform(1.01, 1e3);
  const Vec3 w0 = *unit_dir();
  const Vec3 o = center + w0 * (ratio * r0);
  c.has_sphere = true;
  c.sphere = Sphere{center, r};
  const double sign = *chance(1, 5) ? -1 : 1;
  add_sphere(c.scene, center, sign * r, add_material(c.scene, Material{}));
  const int n = int(*int_towards(1, 12, 1));
  for (int i = 0; i < n; ++i) {
    const Vec3 f = o - center;
    const double fl = length(f);
    const Vec3 fh = f / fl;
    Vec3 e = cross(fh, *unit_dir());
    if (length(e) < 1e-3) e = cross(fh, std::abs(fh.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0});
    e = normalize(e);
    // Tangent to a sphere of radius r (1 + s 2^-j): j in 8..52 puts the ray anywhere from
    // a few ulps to 0.4% of the radius off the tangent, inside or outside; then ulp nudges.
    const int j = int(*int_towards(8, 60, 60));
    const double rt = j > 52 ? r : r * (1 + (*chance(1, 2) ? -1 : 1) * std::ldexp(1.0, -j));
    const double sa = std::min(1.0, rt / fl), ca = std::sqrt(std::max(0.0, 1 - sa * sa));
    Vec3 u = -ca * fh + sa * e;  // tangent to the sphere, up to rounding
    for (int k = 0; k < 3; ++k) u[k] = nudge(u[k], *int_towards(-4, 4, 0));
    c.rays.push_back(Ray{o, scaled_dir(u), 0, kInfinity});
  }
  return c;
}

Case parallel_rays() {
  Case c;
  c.generator = "parallel_rays";
  const StarPolygon p = star_polygon(-3, 6, 4);
  add_polygon(c.scene, p.verts, {}, add_material(c.scene, random_material(true)));
  c.has_poly = true;
  c.poly = 0;
  c.has_plane = true;
  c.plane = c.scene.poly_plane[0];
  const Vec3 n = approx_normal(p.verts);
  const double size = std::ldexp(1.0, p.s);
  const int cnt = int(*int_towards(1, 12, 1));
  const int nv = int(p.verts.size());
  for (int i = 0; i < cnt; ++i) {
    const int a = int(*int_in(0, nv - 1));
    const int b = (a + 1 + int(*int_in(0, nv - 2))) % nv;
    Vec3 d = p.verts[size_t(b)] - p.verts[size_t(a)];  // exactly in the plane
    d = scaled_dir(d / std::ldexp(1.0, p.s));
    for (int k = 0; k < 3; ++k) d[k] = nudge(d[k], *int_towards(-3, 3, 0));
    int64_t lo_x = INT64_MAX, lo_y = INT64_MAX, hi_x = INT64_MIN, hi_y = INT64_MIN;
    for (auto [X, Y] : p.xy) lo_x = std::min(lo_x, X), hi_x = std::max(hi_x, X), lo_y = std::min(lo_y, Y), hi_y = std::max(hi_y, Y);
    const Vec3 q = p.embed(*int_in(lo_x, hi_x), *int_in(lo_y, hi_y));
    const double h = *chance(1, 3) ? 0.0 : *signed_log_uniform(1e-14, 1) * size;
    // Back off along d (by an exact power of two) so that the ray may start outside
    // the polygon; with h = 0 the ray then lies exactly in the plane.
    const double back = *chance(1, 4) ? 0.0 : std::ldexp(1.0, int(*int_in(-1, 1)));
    const Vec3 o = (h == 0 ? q : q + n * h) - d * back;
    c.rays.push_back(Ray{o, d, 0, kInfinity});
  }
  return c;
}

Case far_small_spheres() {
  Case c;
  c.generator = "far_small_spheres";
  const double r = *log_uniform(1e-3, 1e3);
  const double ratio = *log_uniform(10, 1e6);
  Vec3 o;
  for (int i = 0; i < 3; ++i) o[i] = *chance(1, 3) ? 0.0 : *signed_log_uniform(1e-1, 1e2);
  const Vec3 center = o + *unit_dir() * (ratio * r);
  c.has_sphere = true;
  c.sphere = Sphere{center, r};
  add_sphere(c.scene, center, r, add_material(c.scene, Material{}));
  const int n = int(*int_towards(1, 12, 1));
  for (int i = 0; i < n; ++i) {
    const Vec3 target = center + *unit_dir() * (r * *uniform(0, 1.25));
    c.rays.push_back(Ray{o, scaled_dir(target - o), 0, kInfinity});
  }
  return c;
}

Case far_translated() {
  Case c;
  c.generator = "far_translated";
  const Vec3 T = *unit_dir() * *log_uniform(1, 1e7);
  const Vec3 center{*uniform(-4, 4), *uniform(-4, 4), *uniform(-4, 4)};
  const double r = *uniform(0.2, 2);
  const StarPolygon p = star_polygon(-1, 2, 4);
  std::vector<Vec3> verts;
  for (const Vec3& v : p.verts) verts.push_back(v + T);
  const uint32_t m = add_material(c.scene, random_material(true));
  add_sphere(c.scene, center + T, r, m);
  add_polygon(c.scene, verts, {}, m);
  c.has_sphere = true;
  c.sphere = Sphere{center + T, r};
  c.has_poly = true;
  c.poly = 0;
  c.has_plane = true;
  c.plane = c.scene.poly_plane[0];
  const int n = int(*int_towards(1, 12, 1));
  int64_t lo_x = INT64_MAX, lo_y = INT64_MAX, hi_x = INT64_MIN, hi_y = INT64_MIN;
  for (auto [X, Y] : p.xy) lo_x = std::min(lo_x, X), hi_x = std::max(hi_x, X), lo_y = std::min(lo_y, Y), hi_y = std::max(hi_y, Y);
  for (int i = 0; i < n; ++i) {
    const Vec3 target = *chance(1, 2) ? center + *unit_dir() * (r * *uniform(0, 1.2))
                                      : p.embed(*int_in(lo_x, hi_x), *int_in(lo_y, hi_y));
    const Vec3 o{*uniform(-10, 10), *uniform(-10, 10), *uniform(-10, 10)};
    c.rays.push_back(Ray{o + T, scaled_dir(target - o), 0, kInfinity});
  }
  c.scene.view.from = c.rays[0].o;
  c.scene.view.at = center + T;
  ensure_valid_view(c.scene.view);
  return c;
}

Case shared_edge_rays() {
  Case c;
  c.generator = "shared_edge_rays";
  const int64_t kind = *int_in(0, 5);
  Mesh m;
  switch (kind) {
    case 0: m = octahedron(); break;
    case 1: m = icosahedron(20); break;
    case 2: m = icosphere(1, 20); break;
    case 3: m = tessellated_cube(int(1 << *int_in(0, 2)), false); break;
    case 4: m = tessellated_cube(int(1 << *int_in(0, 2)), true); break;
    default: m = tessellated_cube(2, *chance(1, 2)); break;
  }
  // A signed permutation of the axes, a power-of-two scale and a dyadic offset: all exact.
  const int perms[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
  const int pi = int(*int_in(0, 5));
  int sg[3];
  for (int& s : sg) s = *chance(1, 2) ? -1 : 1;
  const int scale = int(*int_towards(-3, 5, 0));
  Vec3 off;
  for (int i = 0; i < 3; ++i) off[i] = std::ldexp(double(*int_towards(-(1 << 23), 1 << 23, 0)), scale - 20);
  bool odd = pi >= 3;
  for (int s : sg) odd ^= (s < 0);
  for (Vec3& v : m.verts) {
    Vec3 q;
    for (int i = 0; i < 3; ++i) q[perms[pi][i]] = sg[i] * std::ldexp(v[i], scale);
    v = q + off;
  }
  if (odd)
    for (auto& f : m.faces) std::reverse(f.begin(), f.end());
  const uint32_t mat = add_material(c.scene, *chance(1, 5) ? Material{{1, 1, 1}, 1, 0, 1, 0.5, 1} : Material{});
  std::vector<Vec3> fn;  // face normals
  for (const auto& f : m.faces) {
    std::vector<Vec3> vs;
    for (uint32_t i : f) vs.push_back(m.verts[i]);
    add_polygon(c.scene, vs, {}, mat);
    fn.push_back(approx_normal(vs));
  }
  const int grid = scale - 26;
  const int n = int(*int_towards(1, 12, 1));
  for (int i = 0; i < n; ++i) {
    const size_t f = size_t(*int_in(0, int64_t(m.faces.size()) - 1));
    const auto& face = m.faces[f];
    const size_t nv = face.size();
    const int64_t what = *int_in(0, 2);  // 0 vertex, 1 edge, 2 inside the face
    Vec3 target;
    Vec3 nsum{0, 0, 0};
    std::vector<Vec3> incident;  // normals of the faces through the target
    if (what == 0) {
      const uint32_t vi = face[size_t(*int_in(0, int64_t(nv) - 1))];
      target = m.verts[vi];
      for (size_t g = 0; g < m.faces.size(); ++g)
        if (std::find(m.faces[g].begin(), m.faces[g].end(), vi) != m.faces[g].end()) nsum += fn[g], incident.push_back(fn[g]);
    } else if (what == 1) {
      const size_t e = size_t(*int_in(0, int64_t(nv) - 1));
      const uint32_t a = face[e], b = face[(e + 1) % nv];
      const double lambda = double(*int_in(1, 15)) / 16.0;
      target = m.verts[a] + (m.verts[b] - m.verts[a]) * lambda;
      for (size_t g = 0; g < m.faces.size(); ++g) {
        const auto& fg = m.faces[g];
        if (std::find(fg.begin(), fg.end(), a) != fg.end() && std::find(fg.begin(), fg.end(), b) != fg.end())
          nsum += fn[g], incident.push_back(fn[g]);
      }
    } else {
      int64_t w[3] = {*int_in(1, 14), *int_in(1, 14), 0};
      if (w[0] + w[1] > 15) w[1] = 15 - w[0];
      w[2] = 16 - w[0] - w[1];
      const Vec3 a = m.verts[face[0]], b = m.verts[face[1]], cc = m.verts[face[2]];
      target = a + (b - a) * (double(w[1]) / 16) + (cc - a) * (double(w[2]) / 16);
      nsum = fn[f];
      incident.push_back(fn[f]);
    }
    Vec3 dir = normalize(nsum);
    bool oblique = *chance(1, 2);
    if (oblique) {
      // Oblique: any direction from which every face through the target is seen
      // from its front, at least 0.05 (about 3 degrees) off each face's plane; the
      // mesh is convex, so the target is the ray's first contact. Rejection
      // sampling, else the near-normal direction below.
      oblique = false;
      for (int attempt = 0; attempt < 64 && !oblique; ++attempt) {
        const Vec3 u = *unit_dir();
        bool ok = true;
        for (const Vec3& nf : incident) ok &= dot(u, nf) > 0.05;
        if (ok) dir = u, oblique = true;
      }
    }
    if (!oblique) {  // near the mean normal: within about 26 degrees
      const Vec3 wobble = *unit_dir() * *uniform(0, 0.3);
      if (dot(normalize(dir + wobble), dir) > 0.9) dir = normalize(dir + wobble);
    }
    const double dist = *log_uniform(0.5, 20) * std::ldexp(1.0, scale);
    const Vec3 o = round_to(target + dir * dist, grid);
    Vec3 d = target - o;  // exact: the ray passes exactly through target at t = 1
    d = d * std::ldexp(1.0, int(*int_towards(-2, 2, 0)));
    c.rays.push_back(Ray{o, d, 0, kInfinity});
  }
  c.scene.view.from = c.rays[0].o;
  c.scene.view.at = off;
  ensure_valid_view(c.scene.view);
  return c;
}

Case degenerate_polygons() {
  Case c;
  c.generator = "degenerate_polygons";
  const int64_t kind = *int_in(0, 6);
  Vec3 p0, delta;
  for (int i = 0; i < 3; ++i) {
    p0[i] = std::ldexp(double(*int_towards(-(1 << 26), 1 << 26, 0)), -26);
    delta[i] = std::ldexp(double(*int_towards(-(1 << 26), 1 << 26, 0)), -29);
  }
  if (delta == Vec3{0, 0, 0}) delta = {0x1p-3, 0, 0};
  Vec3 third;
  for (int i = 0; i < 3; ++i) third[i] = std::ldexp(double(*int_towards(-(1 << 20), 1 << 20, 0)), -20);
  std::vector<Vec3> v;
  switch (kind) {
    case 0: {  // exactly collinear, generic mantissas (Newell rounds to a nonzero normal)
      const int n = int(*int_towards(3, 5, 3));
      const int ks[5] = {0, 1, 3, 2, 4};
      for (int i = 0; i < n; ++i) v.push_back(p0 + delta * double(ks[i]));
      break;
    }
    case 1: v = {p0, p0, p0 + delta}; break;            // repeated vertex, zero area
    case 2: v = {p0, p0 + delta, p0}; break;            // there and back
    case 3: v = {p0, p0, p0}; break;                    // one point
    case 4: v = {p0, p0 + delta, p0 + delta, third}; break;  // repeated vertex, nonzero area
    case 5: v = {p0, p0 + delta * 0.5, p0 + delta, third}; break;  // collinear extra vertex
    default: {  // sliver: the midpoint nudged a few ulps off the line
      Vec3 mid = p0 + delta * 0.5;
      const int axis = int(*int_in(0, 2));
      mid[axis] = nudge(mid[axis], *int_towards(-8, 8, 1));
      v = {p0, mid, p0 + delta};
      break;
    }
  }
  add_polygon(c.scene, v, {}, add_material(c.scene, random_material(true)));
  c.has_poly = true;
  c.poly = 0;
  const int n = int(*int_towards(1, 12, 1));
  for (int i = 0; i < n; ++i) {
    const int64_t what = *int_in(0, 3);
    Vec3 target;
    if (what == 0) target = v[size_t(*int_in(0, int64_t(v.size()) - 1))];
    else if (what == 1) target = p0 + delta * (double(*int_in(0, 8)) / 8.0);
    else if (what == 2) target = (p0 + delta * 0.5 + third) * 0.5;
    else target = p0 + *unit_dir() * *log_uniform(1e-6, 1);
    const Vec3 o = round_to(target + *unit_dir() * *log_uniform(0.25, 8), -30);
    c.rays.push_back(Ray{o, target - o, 0, kInfinity});
  }
  c.scene.view.from = c.rays[0].o;
  c.scene.view.at = p0;
  ensure_valid_view(c.scene.view);
  return c;
}

// ---------------------------------------------------------------- cones

// A random NFF cone (scene cone 0): base near the origin (as rays_at_sphere's
// centre), axis of any direction, 0.1-10 long; a cylinder, a pointed cone
// (apex radius 0) or a truncated one; a quarter seen from inside.
struct RandomCone {
  Vec3 base, apex, u;
  double r0 = 1, r1 = 1, h = 1;
  double radius(double s) const { return r0 + (r1 - r0) * (s / h); }
  double size() const { return std::sqrt(0.25 * h * h + std::max(r0, r1) * std::max(r0, r1)); }
  // The point at height s (from the base) at angle phi around the axis, and the
  // outward radial unit vector there.
  Vec3 e1, e2;
  Vec3 radial(double phi) const { return std::cos(phi) * e1 + std::sin(phi) * e2; }
  Vec3 at(double s, double phi, double rscale = 1) const {
    return base + s * u + radius(s) * rscale * radial(phi);
  }
};

RandomCone random_cone(Case& c, int64_t shape) {
  RandomCone k;
  for (int i = 0; i < 3; ++i) k.base[i] = *chance(1, 5) ? 0.0 : *signed_log_uniform(1e-2, 1e2);
  k.h = *log_uniform(0.1, 10);
  k.u = *unit_dir();
  k.apex = k.base + k.u * k.h;
  k.h = length(k.apex - k.base);  // as rounded
  k.u = (k.apex - k.base) / k.h;
  k.r0 = *log_uniform(0.1, 10);
  if (shape == 0)
    k.r1 = k.r0;  // cylinder
  else if (shape == 1)
    k.r1 = 0;  // pointed
  else
    k.r1 = k.r0 * *uniform(0.1, 2);
  if (*chance(1, 2)) std::swap(k.r0, k.r1);
  const Vec3 a = std::abs(k.u.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  k.e1 = normalize(cross(k.u, a));
  k.e2 = cross(k.u, k.e1);
  const bool inside = k.r0 > 0 && k.r1 > 0 && *chance(1, 4);
  add_cone(c.scene, k.base, k.r0, k.apex, k.r1, inside, add_material(c.scene, Material{}));
  c.has_cone = true;
  c.cone = 0;
  c.scene.view.from = k.base + k.u * (0.5 * k.h) + k.e1 * (10 * k.size());
  c.scene.view.at = k.base + k.u * (0.5 * k.h);
  ensure_valid_view(c.scene.view);
  return k;
}

Case rays_at_cone() {
  Case c;
  c.generator = "rays_at_cone";
  const RandomCone k = random_cone(c, *int_in(0, 2));
  const double R = k.size();
  const Vec3 mid = k.base + k.u * (0.5 * k.h);
  const int n = int(*int_towards(1, 20, 1));
  for (int i = 0; i < n; ++i) {
    Ray ray;
    const int64_t kind = *int_in(0, 9);
    if (kind < 7) {  // from outside the bounding sphere, aimed at or near the side
      const Vec3 target = k.at(k.h * *uniform(-0.2, 1.2), *uniform(0, 2 * M_PI), *uniform(0, 1.3));
      ray.o = mid + *unit_dir() * (*log_uniform(1.05, 100) * R);
      ray.d = scaled_dir(target - ray.o);
      if (kind == 6) ray.d = -ray.d;  // the cone behind
      range_for(ray, length(target - ray.o) / length(ray.d));
    } else if (kind < 9) {  // from inside, near the axis
      ray.o = k.at(k.h * *uniform(0.05, 0.95), *uniform(0, 2 * M_PI), *uniform(0, 0.5));
      ray.d = scaled_dir(*unit_dir());
    } else {  // anywhere
      for (int j = 0; j < 3; ++j) ray.o[j] = mid[j] + *uniform(-20, 20) * R;
      ray.d = scaled_dir(*unit_dir());
    }
    c.rays.push_back(ray);
  }
  return c;
}

// Ill-conditioned rays at one cone, each kind aimed at one of the cone's
// decision boundaries: tangent to the side (the silhouette), at or next to a
// pointed apex, parallel to a side line (the quadric's A -> 0) near the
// surface, and through the rim circles (height 0 or h).
Case cone_ill_rays() {
  Case c;
  c.generator = "cone_ill_rays";
  const int64_t kind = *int_in(0, 3);
  const RandomCone k = random_cone(c, kind == 1 ? 1 : *int_in(0, 2));
  const double R = k.size();
  const int n = int(*int_towards(1, 12, 1));
  auto nudge_all = [](Vec3 v, int ulps) {
    for (int j = 0; j < 3; ++j) v[j] = *nudged(v[j], ulps);
    return v;
  };
  for (int i = 0; i < n; ++i) {
    Ray ray;
    const double phi = *uniform(0, 2 * M_PI);
    const double s = k.h * *uniform(0.05, 0.95);
    // Side line direction at phi (base circle to apex circle) and the tangent
    // circle direction; the outward normal is across both.
    const Vec3 side = normalize(k.at(k.h, phi) - k.at(0, phi));
    const Vec3 around = cross(k.u, k.radial(phi));
    const double dist = *log_uniform(1, 50) * R;
    if (kind == 0) {  // grazing: tangent to the side at a point of the silhouette
      const double a = *uniform(0, M_PI);
      const Vec3 dir = std::cos(a) * around + std::sin(a) * 0.2 * side;
      const Vec3 p = k.at(s, phi);
      ray.o = nudge_all(p - normalize(dir) * dist, 4);
      ray.d = scaled_dir(nudge_all(normalize(dir), 4));
    } else if (kind == 1) {  // the apex (radius 0): at it or next to it
      const Vec3 tip = k.r1 == 0 ? k.apex : k.base;
      const Vec3 target =
          tip + *unit_dir() * (R * (*chance(1, 3) ? 0.0 : *log_uniform(1e-12, 1e-3)));
      ray.o = target + *unit_dir() * dist;
      ray.d = scaled_dir(target - ray.o);
    } else if (kind == 2) {  // parallel to a side line, just off the surface
      const double off = R * *signed_log_uniform(1e-9, 1e-1);
      const Vec3 n = normalize(cross(side, around));
      const Vec3 p = k.at(s, phi) + n * off;
      ray.o = nudge_all(p - side * dist, 3);
      ray.d = scaled_dir(nudge_all(*chance(1, 2) ? side : -side, 3));
      if (dot(ray.d, side) < 0) ray.o = p + side * dist;
    } else {  // through a rim circle
      const Vec3 target = k.at(*chance(1, 2) ? 0.0 : k.h, phi);
      ray.o = target + *unit_dir() * dist;
      ray.d = scaled_dir(target - ray.o);
    }
    c.rays.push_back(ray);
  }
  return c;
}

template <Case (*F)()>
Gen<Case> exec() {
  return rc::gen::exec([] { return F(); });
}

}  // namespace

const std::vector<Named>& generators() {
  static const std::vector<Named> r = {
      {"rays_at_sphere", kSphereKernel, false,
       "one sphere, rays from outside (1.05-100 radii) aimed at or near it, from inside, and anywhere",
       exec<rays_at_sphere>()},
      {"rays_at_plane", kPlaneKernel, false, "one plane, rays aimed at it from 0.1-10 sizes away, some at random",
       exec<rays_at_plane>()},
      {"rays_at_polygon", kPolygonKernel, false,
       "one star-shaped (concave) polygon, exactly coplanar vertices, rays aimed at its bounding box",
       exec<rays_at_polygon>()},
      {"scenes", kTrace | kRender, false, "1-6 spheres, 0-3 polygons, 1-3 lights (some attenuated, some spots), a camera; 16x16 renders",
       exec<scenes>()},
      {"grazing_rays", kSphereKernel | kTrace, true, "rays tangent to a sphere, components nudged +-4 ulps",
       exec<grazing_rays>()},
      {"parallel_rays", kPlaneKernel | kPolygonKernel | kTrace, true,
       "rays parallel to a polygon's plane (an edge direction, nudged +-3 ulps), 0-1 sizes off it",
       exec<parallel_rays>()},
      {"far_small_spheres", kSphereKernel | kTrace, true, "distance/radius log-uniform in 10..1e6",
       exec<far_small_spheres>()},
      {"far_translated", kSphereKernel | kPlaneKernel | kPolygonKernel | kTrace, true,
       "a sphere, a polygon and rays, everything translated up to 1e7 from the origin", exec<far_translated>()},
      {"shared_edge_rays", kWatertight, true,
       "closed meshes (octahedron, icosahedron, icosphere, tessellated cube as triangles or quads), rays "
       "exactly through shared vertices, edges and faces from outside",
       exec<shared_edge_rays>()},
      {"degenerate_polygons", kDegenerate, true,
       "zero-area (collinear, repeated) polygons, collinear/repeated vertices in valid ones, slivers",
       exec<degenerate_polygons>()},
      {"rays_at_cone", kConeKernel, false,
       "one open cone (cylinder, pointed or truncated; a quarter inside-only), rays from outside (1.05-100 "
       "sizes) aimed at or near its side and rims, from inside, and anywhere",
       exec<rays_at_cone>()},
      {"cone_ill_rays", kConeKernel, true,
       "rays tangent to a cone's side (+-4 ulps), at or 1e-12..1e-3 sizes from a pointed apex, parallel to a "
       "side line 1e-9..0.1 sizes off the surface (+-3 ulps), and through the rim circles",
       exec<cone_ill_rays>()},
  };
  return r;
}

const Named* find_generator(std::string_view name) {
  for (const Named& n : generators())
    if (n.name == name) return &n;
  return nullptr;
}

}  // namespace lockstep::props::ray_cast
