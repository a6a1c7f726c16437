// lockstep core: what happens at a hit, shared by every ray-casting implementation.
//
// This is the lighting model, in double precision, as the reference evaluates it
// per hit. The optimized renders (simd, embree) evaluate the same formula 8 hits
// at a time in float (optimized/shade_simd.h, pow as exp(shine log x)); their
// frames are held to the reference within 1/255 per channel (registry/ray_cast_row.cpp), so
// the comparison covers both the intersection code and that vectorised shading.
//
// Local illumination, Phong (Foley et al., 16.1; Phong 1975), no shadows:
//   I = Ia kd C + sum over lights Ip [ kd C max(0, N.L) + ks max(0, R.V)^shine ]
// with C the material colour and R = 2 (N.L) N - L, the mirror of L about N.
// Our choices where NFF is silent:
//   * ambient Ia = 0.1 (white): NFF has no ambient term;
//   * Ip = the light's colour when given, else 1/sqrt(number of lights) (white),
//     the rule Haines suggests, so that many lights do not saturate;
//   * the specular highlight is white (the light's colour), not the material's;
//   * colours are not clamped here; 8-bit outputs clamp on write;
//   * Ip may be scaled by distance attenuation and a spotlight cone, given per
//     light by lockstep's NFF extension (see light_at and io/nff.h).
#pragma once

#include "core/math.h"
#include "core/scene.h"

namespace lockstep {

inline constexpr double kAmbient = 0.1;

// Unit geometric/shading normal at point p on prim, facing against the ray direction d.
// Spheres: (p - c) / r (a negative radius flips it: only the inside is seen).
// Polygons: the plane normal. Patches ('pp'): the vertex normals interpolated with
// the barycentric coordinates of p in triangle tri of the polygon's triangulation;
// tri may be Hit::kNoHit, and the containing triangle is then looked up.
Vec3 surface_normal(const Scene& scene, uint32_t prim, uint32_t tri, const Vec3& p, const Vec3& d);

// The specular term: Phong's max(0, R.V)^shine or Blinn's max(0, N.H)^shine with
// H = normalize(L + V) (Blinn 1977). Same exponent for both, so Blinn-Phong's
// highlights are broader (N.H >= R.V); we do not rescale shine.
enum class Specular : uint8_t { kPhong, kBlinn };

// What one light delivers at p: the unit direction l from p to the light and
// the intensity ip arriving there,
//   ip = I_light * f_att(d) * spot(l)
// with I_light the light's colour or the default 1/sqrt(number of lights),
// d = |light - p|, and the two factors of lockstep's NFF extension (io/nff.h):
//   f_att = min(1, 1 / (c1 + c2 d + c3 d^2))    (Foley et al. 16.1.4; 1 by default)
//   spot  = max(0, -l.D)^exponent if the angle between -l and the spot
//           direction D is at most the cutoff, else 0   (Warn 1983; Foley 16.1.6;
//           1 for an ordinary point light).
struct LightSample {
  Vec3 l;
  Vec3 ip;
};
LightSample light_at(const Scene& scene, const Light& light, const Vec3& p);

// The two factors on their own (light_at multiplies them in), for the
// vectorised shaders and the tests: f_att at distance d, and the spot factor
// for the unit direction l from the point to the light.
double attenuation(const Light& light, double d);
double spot_factor(const Light& light, const Vec3& l);
// cos(cutoff): -l.D >= this is "inside the cone". Computed in one place so that
// every implementation draws the cone's edge from the same number.
double spot_cos_cutoff(const Light& light);

// One light's diffuse + specular term at a point with unit normal n and unit
// direction to the viewer v (0 when the light is behind the surface): what a
// shadow ray can take away (core/ray_trace.h). phong() is the ambient term
// plus this for every light.
Vec3 phong_light(const Material& m, const Vec3& n, const Vec3& v, const LightSample& light,
                 Specular specular = Specular::kPhong);

// Phong (or Blinn-Phong) at p with unit normal n and unit direction to the viewer v.
Vec3 phong(const Scene& scene, const Material& m, const Vec3& p, const Vec3& n, const Vec3& v,
           Specular specular = Specular::kPhong);

// Toon shading (cel shading): the diffuse term max(0, N.L) quantised into
// `bands` >= 2 levels 0, 1/(bands-1), ..., 1 (N.L in [k/bands, (k+1)/bands)
// gives k/(bands-1)), no specular; ambient as in phong.
Vec3 toon(const Scene& scene, const Material& m, const Vec3& p, const Vec3& n, int bands);

// The unit outward normal of cone c (not prim) at a point p on its side.
Vec3 cone_outward_normal(const Scene& scene, uint32_t c, const Vec3& p);

// The colour seen along ray: background on a miss, else Phong at the hit.
Vec3 shade(const Scene& scene, const Ray& ray, const Hit& hit);

// Whether a hit with unit-or-not direction d on prim with (unnormalised) outward
// geometric normal n is visible under NFF's sidedness rules: spheres are seen from
// outside (from inside when the radius is negative), cones likewise, polygons from their front
// (counter-clockwise) side unless the material transmits (T > 0).
inline bool visible_side(const Scene& scene, uint32_t prim, double d_dot_n) {
  if (prim < scene.sphere_count()) return scene.sphere_radius[prim] > 0 ? d_dot_n < 0 : d_dot_n > 0;
  if (prim >= scene.cone_first_prim())
    return scene.cone_inside[prim - scene.cone_first_prim()] ? d_dot_n > 0 : d_dot_n < 0;
  if (scene.materials[scene.poly_material[prim - scene.sphere_count()]].two_sided()) return true;
  return d_dot_n < 0;
}

}  // namespace lockstep
