// lockstep core: shadow maps for point lights (core/shadow_map.h): the cube's
// geometry, what a texel stores, and the biased, optionally filtered test.
#include "core/shadow_map.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace lockstep {

namespace {

constexpr std::array<Vec3, kCubeFaces> kForward = {Vec3{1, 0, 0},  Vec3{-1, 0, 0}, Vec3{0, 1, 0},
                                                   Vec3{0, -1, 0}, Vec3{0, 0, 1},  Vec3{0, 0, -1}};
// Any up not along the axis: the face's image is then turned, which no test sees.
constexpr std::array<Vec3, kCubeFaces> kUp = {Vec3{0, 1, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1},
                                              Vec3{0, 0, 1}, Vec3{1, 0, 0}, Vec3{1, 0, 0}};

// The face's basis (as Camera::from_view makes it: right = forward x up).
void basis(int face, Vec3& forward, Vec3& right, Vec3& up) {
  forward = kForward[size_t(face)];
  right = normalize(cross(forward, kUp[size_t(face)]));
  up = cross(right, forward);
}

// Screen position (texels, y down) of direction d on face `face`: the formula
// of core/viewing.cpp's to_screen, so that a texel's sample and the lookup of
// a point agree on where the point falls. d must be in front of the face.
void face_xy(int face, const Vec3& d, int n, double& x, double& y) {
  Vec3 f, r, u;
  basis(face, f, r, u);
  const double pitch = 2.0 / n;
  const double z = dot(d, f);
  x = 0.5 * n + dot(d, r) / (z * pitch);
  y = 0.5 * n - dot(d, u) / (z * pitch);
}

int clamp_texel(double x, int n) { return std::clamp(int(std::floor(x)), 0, n - 1); }

}  // namespace

int cube_face(const Vec3& d) {
  const double ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
  if (ax >= ay && ax >= az) return d.x >= 0 ? 0 : 1;
  if (ay >= az) return d.y >= 0 ? 2 : 3;
  return d.z >= 0 ? 4 : 5;
}

Camera cube_face_camera(const Vec3& light, int face, int n) {
  Camera c;
  c.eye = light;
  basis(face, c.forward, c.right, c.up);
  c.pitch = 2.0 / n;
  c.hither = 0;
  c.width = c.height = n;
  return c;
}

CubeTexel cube_texel(const Vec3& d, int n) {
  CubeTexel t;
  t.face = cube_face(d);
  double x, y;
  face_xy(t.face, d, n, x, y);
  t.i = clamp_texel(x, n);
  t.j = clamp_texel(y, n);
  return t;
}

Vec3 cube_direction(int face, double x, double y, int n) {
  Vec3 f, r, u;
  basis(face, f, r, u);
  const double pitch = 2.0 / n;
  return f + ((x - 0.5 * n) * pitch) * r + ((0.5 * n - y) * pitch) * u;
}

ScreenMesh cube_face_frame(const Scene& scene, const Vec3& light, int face, int n) {
  ScreenMesh mesh;
  mesh.camera = cube_face_camera(light, face, n);
  mesh.width = mesh.height = n;
  // Far: the deepest corner of the scene's bounds along the face's axis (as
  // view_frame). Near: a millionth of it, so that nothing in front of the face
  // is lost (a surface nearer the light than that does not shadow; a point
  // light that close to a surface is not one the scene can mean).
  Vec3 lo, hi;
  scene_bounds(scene, lo, hi);
  double far_z = 0;
  for (int k = 0; k < 8; ++k) {
    const Vec3 corner{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
    far_z = std::max(far_z, dot(corner - light, mesh.camera.forward));
  }
  mesh.far_z = far_z > 0 ? far_z * (1 + 1e-6) : 1.0;  // nothing in front of the face: any frame
  mesh.near_z = mesh.far_z * 1e-6;
  return mesh;
}

RasterSettings depth_pass_settings(const RasterSettings& s) {
  RasterSettings d;
  d.shading = Shading::kPhong;  // view_scene lights nothing for it
  d.cull = CullMode::kNone;
  d.spp = 1;
  d.tess_error = s.tess_error;
  d.depth = DepthFormat::kDouble;
  d.perspective = true;
  return d;
}

double texel_distance(const ScreenMesh& frame, double window, int i, int j) {
  if (!std::isfinite(window)) return kInfinity;
  // stored_depth(kDouble) inverted: window = (1/n - 1/z) / (1/n - 1/f).
  const double inv_n = 1 / frame.near_z, inv_f = 1 / frame.far_z;
  const double z = 1 / (inv_n - window * (inv_n - inv_f));
  // The texel centre's ray has forward component 1: its length per unit depth.
  const double pitch = frame.camera.pitch;
  const double u = (i + 0.5 - 0.5 * frame.width) * pitch,
               v = (0.5 * frame.height - (j + 0.5)) * pitch;
  return z * std::sqrt(1 + u * u + v * v);
}

namespace {

// tan theta from cos theta, capped (core/shadow_map.h).
double capped_tan(double cos_theta) {
  constexpr double kMaxTan = 10;
  const double c = std::clamp(std::abs(cos_theta), 0.0, 1.0);
  return c * kMaxTan >= std::sqrt(1 - c * c) ? std::sqrt(1 - c * c) / c : kMaxTan;
}

}  // namespace

double shadow_bias(const RasterSettings& s, int n, double r, double cos_theta) {
  return kShadowRounding * r + s.bias + s.slope_bias * (2 * r / n) * capped_tan(cos_theta);
}

double lit_fraction(const ShadowCube& cube, const RasterSettings& s, const Vec3& p,
                    const Vec3& face_normal) {
  const Vec3 d = p - cube.light;
  const double r = length(d);
  if (!(r > 0)) return 1;  // at the light itself
  const double cos_theta = dot(face_normal, d) / r;
  const double reach = r - shadow_bias(s, cube.n, r, cos_theta);
  if (s.pcf <= 1) return reach > cube.at(cube_texel(d, cube.n)) ? 0.0 : 1.0;
  // Percentage-closer filtering: the k x k texels around p's position on its
  // face. A sample (a, b) texels away sees p's plane up to |(a, b)| texel
  // widths further along its slope, so its bias grows by that many texels
  // (without it half of every tilted plane would shadow itself).
  const int face = cube_face(d);
  double x, y;
  face_xy(face, d, cube.n, x, y);
  const int half = s.pcf / 2;
  const double texel_slope = (2 * r / cube.n) * capped_tan(cos_theta);
  int passed = 0;
  for (int b = -half; b <= half; ++b)
    for (int a = -half; a <= half; ++a) {
      const Vec3 da = cube_direction(face, x + a, y + b, cube.n);
      const double reach_ab = reach - std::sqrt(double(a * a + b * b)) * texel_slope;
      if (!(reach_ab > cube.at(cube_texel(da, cube.n)))) ++passed;
    }
  return double(passed) / double(s.pcf * s.pcf);
}

void check_shadow_settings(const RasterSettings& s, const std::string& source,
                           const std::string& shading_name) {
  const bool per_sample = s.shading == Shading::kPhong || s.shading == Shading::kBlinn;
  if (s.shadows == ShadowMode::kVolume && !per_sample)
    throw InputError(source, 0,
                     "shadows=volume needs per-sample lighting: shading phong or blinn, not " +
                         shading_name);
  if (s.shadows == ShadowMode::kMap && !per_sample)
    throw InputError(
        source, 0,
        "shadows=map needs per-sample lighting: shading phong or blinn (flat, gouraud and toon "
        "light vertices or polygons, before any shadow test)");
}

ShadowMaps build_shadow_maps_direct(const Scene& scene, const RasterSettings& s,
                                    const FaceDistances& distances) {
  const RasterSettings depth = depth_pass_settings(s);
  const int n = s.map_size;
  ShadowMaps maps;
  for (const Light& light : scene.lights) {
    ShadowCube cube;
    cube.light = light.position;
    cube.n = n;
    for (int face = 0; face < kCubeFaces; ++face) {
      ScreenMesh frame = cube_face_frame(scene, light.position, face, n);
      view_spheres(scene, depth, 0, scene.sphere_count(), frame);
      view_polygons(scene, depth, 0, scene.polygon_count(), frame);
      std::vector<float>& dist = cube.dist[size_t(face)];
      dist.resize(size_t(n) * size_t(n));
      distances(frame, depth, dist.data());
    }
    maps.cubes.push_back(std::move(cube));
  }
  return maps;
}

ShadowMaps build_shadow_maps(const Scene& scene, const RasterSettings& s,
                             const DepthPass& visibility) {
  Visibility vis;  // reused across faces
  return build_shadow_maps_direct(
      scene, s, [&](const ScreenMesh& frame, const RasterSettings& depth, float* dist) {
        visibility(frame, depth, vis);
        const int n = frame.width;
        for (int j = 0; j < n; ++j)
          for (int i = 0; i < n; ++i) {
            const size_t k = size_t(j) * size_t(n) + size_t(i);
            dist[k] = vis.tri[k] == Visibility::kNone
                          ? float(kInfinity)
                          : float(texel_distance(frame, vis.depth[k], i, j));
          }
      });
}

}  // namespace lockstep
