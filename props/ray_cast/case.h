// lockstep props: one generated test case, and its bit-exact text form.
//
// Every generator in props/gen produces a Case: a scene (always valid, so that
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

namespace lockstep::props {

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
};

// Hexfloat text of a double ("0x1.8p+1"; "inf", "-inf", "nan").
std::string hex(double x);
std::string hex(const Vec3& v);
std::string hex(const Ray& r);
// Decimal, for people (17 significant digits).
std::string dec(double x);

// The scene as NFF with every number as a hexfloat.
std::string to_nff(const Scene& scene);

// A counterexample file: the case plus what to check and what to expect.
struct Record {
  std::string property;  // e.g. stability.far_small_spheres.ray_sphere.reference_f32
  std::string check;     // agreement | accuracy | stability | watertight | degenerate | render
  std::string pair;      // ray_sphere | ray_plane | ray_polygon | ray_cast
  std::string impl;
  std::string expect = "pass";  // "pass" or "classified <label>"
  std::string seed;
  std::vector<std::string> notes;  // informational: outputs, errors (ignored on replay)
  Case c;
};

void write_record(std::ostream& out, const Record& r);
// Throws std::runtime_error on a malformed file.
Record read_record(std::istream& in, const std::string& name);

// For RapidCheck's counterexample printing.
void showValue(const Case& c, std::ostream& os);

}  // namespace lockstep::props
