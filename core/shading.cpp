#include "core/shading.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace lockstep {

namespace {

// Barycentric coordinates (b0, b1, b2) of p in triangle (a, b, c), via areas
// projected on the plane with normal n.
void barycentric(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p, const Vec3& n,
                 double out[3]) {
  const double area = dot(cross(b - a, c - a), n);
  out[0] = dot(cross(c - b, p - b), n) / area;
  out[1] = dot(cross(a - c, p - c), n) / area;
  out[2] = 1.0 - out[0] - out[1];
}

}  // namespace

Vec3 cone_outward_normal(const Scene& scene, uint32_t c, const Vec3& p) {
  // The cone's gradient (core/cone_quadric.h): w_perp - r(s) k u.
  const Vec3 axis = scene.cone_apex[c] - scene.cone_base[c];
  const double h = length(axis);
  const Vec3 u = axis / h;
  const double k = (scene.cone_r1[c] - scene.cone_r0[c]) / h;
  const Vec3 w = p - scene.cone_base[c];
  const double s = dot(w, u);
  const Vec3 g = (w - s * u) - (scene.cone_r0[c] + k * s) * k * u;
  // At a pointed tip (radius 0) the gradient vanishes: the axis, away from the cone.
  return length(g) > 0 ? normalize(g) : (k > 0 ? -u : u);
}

Vec3 surface_normal(const Scene& scene, uint32_t prim, uint32_t tri, const Vec3& p, const Vec3& d) {
  Vec3 n;
  if (prim < scene.sphere_count()) {
    n = (p - scene.sphere_center[prim]) / scene.sphere_radius[prim];
  } else if (prim >= scene.cone_first_prim()) {
    n = cone_outward_normal(scene, prim - scene.cone_first_prim(), p);
  } else {
    const uint32_t poly = prim - scene.sphere_count();
    n = scene.poly_plane[poly].n;
    if (scene.poly_is_patch[poly]) {
      // Find the triangle holding p if the caller did not say: the one whose
      // smallest barycentric coordinate is largest (p may sit on an edge).
      double b[3];
      if (tri == Hit::kNoHit) {
        double best = -kInfinity;
        for (uint32_t k = scene.poly_tri_first[poly]; k < scene.poly_tri_first[poly + 1]; ++k) {
          const auto& t = scene.tri_vertex[k];
          barycentric(scene.vertex[t[0]], scene.vertex[t[1]], scene.vertex[t[2]], p, n, b);
          const double m = std::min({b[0], b[1], b[2]});
          if (m > best) {
            best = m;
            tri = k;
          }
        }
      }
      if (tri != Hit::kNoHit) {
        const auto& t = scene.tri_vertex[tri];
        barycentric(scene.vertex[t[0]], scene.vertex[t[1]], scene.vertex[t[2]], p, n, b);
        const Vec3 s = b[0] * scene.vertex_normal[t[0]] + b[1] * scene.vertex_normal[t[1]] +
                       b[2] * scene.vertex_normal[t[2]];
        if (length(s) > 0) n = normalize(s);
      }
    }
  }
  // Face the viewer: two-sided polygons are seen from the back too.
  if (dot(n, d) > 0) n = -n;
  return n;
}

double attenuation(const Light& light, double d) {
  // Foley et al. 16.1.4: 1 / (c1 + c2 d + c3 d^2), never brighter than the light
  // itself (the min(1, .) keeps a light close to a surface from blowing up).
  const double denominator = light.atten.x + light.atten.y * d + light.atten.z * d * d;
  return std::min(1.0, 1.0 / denominator);
}

double spot_cos_cutoff(const Light& light) { return std::cos(light.spot_cutoff * (std::numbers::pi / 180.0)); }

double spot_factor(const Light& light, const Vec3& l) {
  if (!light.spot) return 1.0;
  // Warn's model: the light shines along D; a point sees it along -l.
  const double cos_angle = dot(-l, light.spot_dir);
  // Outside the cone (angle > cutoff, i.e. cos(angle) < cos(cutoff)): no light.
  if (cos_angle < spot_cos_cutoff(light)) return 0.0;
  // Inside: the falloff cos(angle)^exponent (pow(0, 0) = 1: exponent 0 is a hard-edged cone).
  return std::pow(std::max(0.0, cos_angle), light.spot_exponent);
}

LightSample light_at(const Scene& scene, const Light& light, const Vec3& p) {
  const double default_ip = 1.0 / std::sqrt(double(scene.lights.size()));
  const Vec3 to_light = light.position - p;
  const double d = length(to_light);
  LightSample s;
  s.l = to_light / d;
  // The light's own intensity, then what distance and the spot cone leave of it.
  const Vec3 i_light = light.has_color ? light.color : Vec3{default_ip, default_ip, default_ip};
  s.ip = attenuation(light, d) * spot_factor(light, s.l) * i_light;
  return s;
}

Vec3 phong_light(const Material& m, const Vec3& n, const Vec3& v, const LightSample& light, Specular specular) {
  const auto& [l, ip] = light;
  const double n_dot_l = dot(n, l);
  if (n_dot_l <= 0) return {};  // light behind the surface
  double spec = 0;
  if (m.ks > 0) {
    if (specular == Specular::kPhong) {
      const Vec3 r = 2.0 * n_dot_l * n - l;  // L mirrored about N
      spec = m.ks * std::pow(std::max(0.0, dot(r, v)), m.shine);
    } else {
      const Vec3 h = normalize(l + v);  // halfway between light and viewer
      spec = m.ks * std::pow(std::max(0.0, dot(n, h)), m.shine);
    }
  }
  return mul(ip, n_dot_l * (m.kd * m.color) + Vec3{spec, spec, spec});
}

Vec3 phong(const Scene& scene, const Material& m, const Vec3& p, const Vec3& n, const Vec3& v, Specular specular) {
  Vec3 c = kAmbient * (m.kd * m.color);
  for (const Light& light : scene.lights) c += phong_light(m, n, v, light_at(scene, light, p), specular);
  return c;
}

Vec3 toon(const Scene& scene, const Material& m, const Vec3& p, const Vec3& n, int bands) {
  const Vec3 kd_c = m.kd * m.color;
  Vec3 c = kAmbient * kd_c;
  for (const Light& light : scene.lights) {
    const auto [l, ip] = light_at(scene, light, p);
    const double n_dot_l = dot(n, l);
    if (n_dot_l <= 0) continue;
    // Quantise: [0, 1/bands) -> 0, ..., [1 - 1/bands, 1] -> (bands - 1) / bands, 1 -> 1.
    const double q = std::min(1.0, std::floor(n_dot_l * bands) / (bands - (bands > 1 ? 1 : 0)));
    c += mul(ip, q * kd_c);
  }
  return c;
}

Vec3 shade(const Scene& scene, const Ray& ray, const Hit& hit) {
  if (!hit.hit()) return scene.background;
  const Vec3 p = ray.o + hit.t * ray.d;
  const Vec3 d = normalize(ray.d);
  const Vec3 n = surface_normal(scene, hit.prim, hit.tri, p, d);
  return phong(scene, scene.material_of_prim(hit.prim), p, n, -d);
}

}  // namespace lockstep
