// lockstep core: the scene, as flat arrays.
//
// One Scene holds what an NFF file describes. Spheres and polygons are kept in
// structure-of-arrays form so that kernels can stream them; polygons are kept as
// polygons (with their plane) for the textbook point-in-polygon test, and also
// as a triangulation for kernels that only know triangles. Primitive ids run over
// spheres first, then polygons, then cones: prim < sphere_count() is a sphere,
// prim >= cone_first_prim() a cone. The ray casters and tracers intersect cones
// (core/cone_quadric.h; optimized/ray_cone.h), the rasterizers tessellate them
// (core/viewing.cpp view_cones); a row that cannot would refuse the scene
// (registry/loaders.h refuse_cones) rather than drop them silently.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/math.h"

namespace lockstep {

// The NFF viewpoint ('v' entity). angle is the full field of view in degrees,
// measured between the centres of the edge pixels (see Camera).
struct View {
  Vec3 from{0, 0, 0};
  Vec3 at{0, 0, -1};
  Vec3 up{0, 1, 0};
  double angle = 45.0;
  double hither = 1e-6;
  int xres = 256;
  int yres = 256;
};

// NFF 'f': colour, Kd, Ks, Shine, T, index of refraction.
struct Material {
  Vec3 color{1, 1, 1};
  double kd = 1.0;
  double ks = 0.0;
  double shine = 1.0;
  double transmittance = 0.0;
  double ior = 1.0;
  // lockstep's NFF extension '#lockstep emit r g b' (io/nff.h): the radiosity
  // the surfaces emit, per channel; radiosity's emitters. Other families do
  // not draw emission (a ray-cast emitter looks like its colour).
  Vec3 emission{0, 0, 0};
  // The line of its 'f' in the file it came from (0: none), for messages
  // about it that only a family can give (radiosity: reflectance >= 1).
  int line = 0;
  // NFF: polygons are one-sided unless the material transmits light.
  bool two_sided() const { return transmittance > 0.0; }
};

// NFF 'l': positional light. has_color is false when the file gave none; the
// intensity is then 1/sqrt(number of lights) (see core/shading.h).
//
// lockstep's NFF extension (io/nff.h) adds, per light:
//   atten  distance attenuation f_att = min(1, 1 / (c1 + c2 d + c3 d^2)),
//          Foley et al. 16.1.4; the default 1 0 0 is no attenuation;
//   spot   a Warn spotlight (Warn 1983; Foley et al. 16.1.6): unit direction
//          spot_dir, cone half-angle spot_cutoff in degrees (0, 90], falloff
//          exponent spot_exponent >= 0.
struct Light {
  Vec3 position;
  Vec3 color{1, 1, 1};
  bool has_color = false;
  Vec3 atten{1, 0, 0};  // c1, c2, c3: all >= 0, not all 0
  bool spot = false;
  Vec3 spot_dir{0, 0, -1};     // unit, where the spot points
  double spot_cutoff = 90.0;   // degrees
  double spot_exponent = 0.0;
};

// Plane n.x + d = 0 with unit normal n (n = 0 for a degenerate polygon).
struct Plane {
  Vec3 n;
  double d = 0.0;
};

struct Sphere {
  Vec3 center;
  double radius = 1.0;  // NFF: negative means only the inside is visible
};

struct Scene {
  View view;
  Vec3 background{0, 0, 0};
  std::vector<Light> lights;
  std::vector<Material> materials;

  // Spheres.
  std::vector<Vec3> sphere_center;
  std::vector<double> sphere_radius;  // signed, as in the file
  std::vector<uint32_t> sphere_material;

  // Polygons: vertices of polygon p are vertex[poly_first[p] .. poly_first[p+1]).
  std::vector<uint32_t> poly_first{0};
  std::vector<Vec3> vertex;
  std::vector<Vec3> vertex_normal;  // unit; only meaningful where poly_is_patch
  std::vector<Plane> poly_plane;
  std::vector<uint32_t> poly_material;
  std::vector<uint8_t> poly_is_patch;

  // Triangulation of the polygons (indices into vertex), and the polygon each came from.
  std::vector<std::array<uint32_t, 3>> tri_vertex;
  std::vector<uint32_t> tri_poly;
  // Triangles of polygon p are tri_vertex[poly_tri_first[p] .. poly_tri_first[p+1]).
  std::vector<uint32_t> poly_tri_first{0};

  // Cones ('c'): open-ended truncated cones, cylinders when the radii are equal,
  // from cone_base (radius cone_r0) to cone_apex (radius cone_r1). Radii are
  // stored >= 0 and not both 0; the axis is not of zero length. cone_inside is
  // NFF's "both radii negative": only the inside is visible (as a sphere's
  // negative radius).
  std::vector<Vec3> cone_base, cone_apex;
  std::vector<double> cone_r0, cone_r1;
  std::vector<uint8_t> cone_inside;
  std::vector<uint32_t> cone_material;

  // Where it came from, for messages.
  std::string source = "<memory>";

  uint32_t sphere_count() const { return uint32_t(sphere_center.size()); }
  uint32_t polygon_count() const { return uint32_t(poly_plane.size()); }
  uint32_t cone_count() const { return uint32_t(cone_base.size()); }
  uint32_t cone_first_prim() const { return sphere_count() + polygon_count(); }
  uint32_t prim_count() const { return sphere_count() + polygon_count() + cone_count(); }
  uint32_t triangle_count() const { return uint32_t(tri_vertex.size()); }
  std::span<const Vec3> polygon_vertices(uint32_t p) const {
    return {vertex.data() + poly_first[p], poly_first[p + 1] - poly_first[p]};
  }
  uint32_t material_id_of_prim(uint32_t prim) const {
    if (prim < sphere_count()) return sphere_material[prim];
    if (prim < cone_first_prim()) return poly_material[prim - sphere_count()];
    return cone_material[prim - cone_first_prim()];
  }
  const Material& material_of_prim(uint32_t prim) const {
    return materials[material_id_of_prim(prim)];
  }
};

// Appends a material and returns its index.
uint32_t add_material(Scene& scene, const Material& m);
void add_sphere(Scene& scene, const Vec3& center, double radius, uint32_t material);
// Appends a cone; radii >= 0, not both 0, base != apex (the NFF reader checks).
void add_cone(Scene& scene, const Vec3& base, double r0, const Vec3& apex, double r1, bool inside,
              uint32_t material);
// Appends a polygon: computes its plane (Newell's method; the facing follows the
// counter-clockwise vertex order, as NFF prescribes) and triangulates it by ear
// clipping so that concave polygons come out right. normals is empty for 'p' and
// one unit normal per vertex for 'pp'.
void add_polygon(Scene& scene, std::span<const Vec3> vertices, std::span<const Vec3> normals,
                 uint32_t material);

// Ear-clipping triangulation of a simple planar polygon (concave allowed),
// projected along the dominant axis of its normal. Returns index triples into
// the given vertices, counter-clockwise with respect to normal. Degenerate
// (zero-area) polygons give no triangles.
std::vector<std::array<uint32_t, 3>> triangulate(std::span<const Vec3> vertices, const Vec3& normal);

// Axis-aligned bounds of everything in the scene (spheres by |radius|, cones by
// the boxes of their end discs).
void scene_bounds(const Scene& scene, Vec3& lo, Vec3& hi);

// Polygons whose plane normal is zero only because the Newell products
// overflowed or underflowed double (|n|^2 of coordinates from about 1e77 up or
// 1e-82 down, measured; checked on the vertices moved to the first and scaled to unit size),
// not because they have no area: every row leaves them out and must say so
// (FrameStats::dropped with kNormalLostToRange; issue #22).
inline constexpr const char* kNormalLostToRange = "polygon normal out of double range (coordinates beyond about 1e76 or below 1e-80)";
bool normal_lost_to_range(std::span<const Vec3> vertices);
uint64_t range_lost_polygons(const Scene& scene);

}  // namespace lockstep
