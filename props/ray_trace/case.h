// lockstep props/ray_trace: the ray-tracing family's cases and their text
// forms (counterexample files): a small NFF scene with every number as a hex
// float, so that a case replays bit for bit, and the scene-free Laws case.
#pragma once

#include <string>

#include "core/family.h"
#include "core/math.h"
#include "core/scene.h"

namespace lockstep::props::ray_trace {

struct TraceCase {
  int width = 16, height = 16;
  int px = -1, py = -1;  // one pixel (its tree), or -1: the frame
  std::string params;    // "depth=3 shadows=none"
  std::string nff;       // the scene
  std::string hidden;    // Hidden: objects appended behind the wall
};

std::string write_case(const TraceCase& c);
TraceCase read_case(const std::string& text, const std::string& file);
// The case's params ("depth=3 shadows=none") and scene (with the hidden objects appended).
Params params_of(const TraceCase& c);
Scene scene_of(const TraceCase& c, bool with_hidden = false);

// NFF text, every number a hex float.
std::string v3(const Vec3& v);
std::string view_text(const Vec3& from, const Vec3& at, const Vec3& up, double angle, int w, int h);
std::string material(const Vec3& color, double kd, double ks, double shine, double t, double ior);
// A square of half-size r centred on c with normal m (counter-clockwise seen from m's side).
std::string quad(const Vec3& c, const Vec3& m, double r);
Vec3 some_up(const Vec3& dir);
// Three numbers (hex floats too, which istream's >> does not read) from text.
Vec3 read_v3(const std::string& text);

// Laws: a case is (d, n, eta) in the scene-free text "laws dx dy dz nx ny nz eta".
struct LawCase {
  Vec3 d, n;
  double eta = 1;
};

std::string write_law(const LawCase& c);
LawCase read_law(const std::string& text, const std::string& file);

}  // namespace lockstep::props::ray_trace
