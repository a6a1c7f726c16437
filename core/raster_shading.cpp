// lockstep core: the shading of a fragment (core/raster.h's shade_fragment),
// shared by the implementations that shade in double (the three references and
// opt::simd::painter): flat, Gouraud, Phong, Blinn-Phong and toon (core/shading.h's
// lighting, as ray casting lights a hit), and silhouettes.
#include <cmath>

#include "core/raster.h"
#include "core/shading.h"

namespace lockstep {

// ---------------------------------------------------------------- shading

Vec3 shade_fragment(const Scene& scene, const ScreenMesh& mesh, const RasterSettings& s, const Fragment& f) {
  const ScreenTri& t = mesh.tris[f.tri];
  const Camera& cam = mesh.camera;
  const Material& m = scene.material_of_prim(t.prim);
  // The view ray through the sample: its direction has forward component 1, so
  // the point at eye depth z is eye + z * dir (as ray casting's hit point).
  const double cx = (f.sx - 0.5 * mesh.width) * cam.pitch, cy = (0.5 * mesh.height - f.sy) * cam.pitch;
  const Vec3 dir = cam.forward + cx * cam.right + cy * cam.up;
  const Vec3 v = -normalize(dir);

  // The interpolated normal, renormalised, turned towards the viewer (ray
  // casting's rule, core/shading.cpp's surface_normal).
  auto normal = [&] {
    Vec3 n = f.b[0] * t.v[0].normal + f.b[1] * t.v[1].normal + f.b[2] * t.v[2].normal;
    n = length(n) > 0 ? normalize(n) : t.face_normal;
    if (dot(n, dir) > 0) n = -n;
    return n;
  };

  Vec3 c;
  switch (s.shading) {
    case Shading::kFlat: c = t.flat_color; break;
    case Shading::kGouraud: c = f.b[0] * t.v[0].color + f.b[1] * t.v[1].color + f.b[2] * t.v[2].color; break;
    case Shading::kPhong: c = phong(scene, m, cam.eye + f.z * dir, normal(), v, Specular::kPhong); break;
    case Shading::kBlinn: c = phong(scene, m, cam.eye + f.z * dir, normal(), v, Specular::kBlinn); break;
    case Shading::kToon: c = toon(scene, m, cam.eye + f.z * dir, normal(), s.toon_bands); break;
  }
  // Silhouettes: where the surface turns away from the viewer, N.V near 0.
  if (s.silhouette && std::abs(dot(normal(), v)) < s.silhouette_eps) c = Vec3{0, 0, 0};
  return c;
}

Vec3 shade_fragment(const Scene& scene, const ScreenMesh& mesh, const RasterSettings& s, const Fragment& f,
                    const LightReach& lit) {
  if (s.shading != Shading::kPhong && s.shading != Shading::kBlinn) return shade_fragment(scene, mesh, s, f);
  const ScreenTri& t = mesh.tris[f.tri];
  const Camera& cam = mesh.camera;
  const Material& m = scene.material_of_prim(t.prim);
  // The point, view direction and normal exactly as the unshadowed path above
  // finds them, so that with every light reaching (lit = 1) the colours are
  // the same bit for bit.
  const double cx = (f.sx - 0.5 * mesh.width) * cam.pitch, cy = (0.5 * mesh.height - f.sy) * cam.pitch;
  const Vec3 dir = cam.forward + cx * cam.right + cy * cam.up;
  const Vec3 v = -normalize(dir);
  Vec3 n = f.b[0] * t.v[0].normal + f.b[1] * t.v[1].normal + f.b[2] * t.v[2].normal;
  n = length(n) > 0 ? normalize(n) : t.face_normal;
  if (dot(n, dir) > 0) n = -n;
  const Vec3 p = cam.eye + f.z * dir;
  // The point the shadow test asks about: where the sample's ray meets the
  // triangle's plane in world space. f.z comes from the snapped triangle,
  // whose plane is turned by up to 1/512 pixel at a vertex: seen at a grazing
  // angle that puts p off the surface by more than a shadow map's bias.
  Vec3 q = p;
  const Vec3 e1 = t.v[1].world - t.v[0].world, e2 = t.v[2].world - t.v[0].world, pn = cross(e1, e2);
  if (const double den = dot(pn, dir); den != 0) {
    const double s_hit = dot(pn, t.v[0].world - cam.eye) / den;
    if (s_hit > 0 && std::isfinite(s_hit)) q = cam.eye + s_hit * dir;
  }
  const Specular spec = s.shading == Shading::kBlinn ? Specular::kBlinn : Specular::kPhong;
  // core/shading.cpp's phong(), one light at a time (the same sum in the same order).
  Vec3 c = kAmbient * (m.kd * m.color);
  for (uint32_t k = 0; k < scene.lights.size(); ++k) {
    const Vec3 term = phong_light(m, n, v, light_at(scene, scene.lights[k], p), spec);
    if (term == Vec3{}) continue;
    const double reach = lit(k, q, t.face_normal);
    if (reach == 1) c += term;
    else if (reach > 0) c += reach * term;
  }
  if (s.silhouette && std::abs(dot(n, v)) < s.silhouette_eps) c = Vec3{0, 0, 0};
  return c;
}

}  // namespace lockstep
