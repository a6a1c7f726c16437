// lockstep props: one generated test case, and its bit-exact text form.
//
// Every generator in generators.h produces a Case: a scene (always valid, so that
// it can be written as NFF and traced), a batch of rays, and which kernel
// subjects it carries (a sphere, a plane, a polygon of the scene). The text form
// writes every double as a C99 hexfloat (%a), so a counterexample file replays
// bit for bit; the scene is embedded as NFF (parse_nff reads hexfloats, and
// add_polygon recomputes planes and triangulations deterministically).
#pragma once

#include <cstdint>
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/scene.h"

namespace lockstep::props::ray_cast {

struct Case {
  std::string generator;
  Scene scene;  // spheres and polygons for trace/polygon kernels; view for render
  std::vector<Ray> rays;
  bool has_sphere = false;
  Sphere sphere;
  bool has_plane = false;
  Plane plane;
  bool has_poly = false;
  uint32_t poly = 0;   // polygon of scene for the ray_polygon kernel
  int render_size = 0; // > 0: the case is also a render case (render_size^2 pixels)
  bool has_cone = false;
  uint32_t cone = 0;  // cone of scene for the ray_cone kernel
};

// Hexfloat text of a double ("0x1.8p+1"; "inf", "-inf", "nan").
std::string hex(double x);
std::string hex(const Vec3& v);
std::string hex(const Ray& r);
// Decimal, for people (17 significant digits).
std::string dec(double x);

// The scene as NFF with every number as a hexfloat.
std::string to_nff(const Scene& scene);

// The case's text form: the body of a counterexample file after the driver's
// header (corpus/counterexamples/README.md): generator, sphere, plane, poly,
// render, cone, one "ray" line per ray, then the scene as NFF up to "end".
void write_case(std::ostream& out, const Case& c);
std::string case_text(const Case& c);
// Throws std::runtime_error (naming `name` and the line) on a malformed text.
Case read_case(const std::string& text, const std::string& name);

// The same case with only ray i (for one-ray counterexample files).
Case with_ray(const Case& c, size_t i);

// For RapidCheck's counterexample printing.
void showValue(const Case& c, std::ostream& os);

}  // namespace lockstep::props::ray_cast
