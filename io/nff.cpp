#include "io/nff.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "core/error.h"
#include "io/text.h"
#include "io/tokenizer.h"

namespace lockstep {

namespace {

constexpr std::string_view kExtension = "#lockstep";

// The tokenizer (io/tokenizer.h) with NFF's field readers: every error names a line.
class Lines : public text::Tokenizer {
 public:
  Lines(std::string_view text, const std::string& name)
      : Tokenizer(text, name, {.comments = text::Comments::anywhere, .directive = kExtension}) {}

  int line() const { return line_no(); }
  double number(size_t i) const {
    const std::string_view s = words().at(i);
    double v = 0;
    if (!text::parse_double(s, v)) fail("not a number: '" + std::string(s) + "'");
    // ERANGE also flags underflow (1e-320 reads as a denormal or 0): only overflow is an error.
    if (!std::isfinite(v)) fail("number out of range (NaN, Inf or overflow): '" + std::string(s) + "'");
    return v;
  }
  long integer(size_t i) const {
    const std::string_view s = words().at(i);
    long v = 0;
    if (!text::parse_long(s, v)) fail("not an integer: '" + std::string(s) + "'");
    return v;
  }
  Vec3 vec3(size_t i) const { return {number(i), number(i + 1), number(i + 2)}; }
};

// A #lockstep line that does not follow what it modifies (a light; for
// emit, a material).
[[noreturn]] void misplaced_extension(const Lines& in) {
  const std::string what = in.words().size() > 1 ? " " + std::string(in.words()[1].substr(0, 32)) : "";
  if (what == " emit") in.fail("'#lockstep emit' does not follow a material: it must come right after an 'f' line");
  in.fail("'#lockstep" + what + "' does not follow a light: it must come right after an 'l' line");
}

// Reads a "#lockstep emit r g b" line into the material it follows (the
// emitted radiosity of the surfaces that use it; radiosity's emitters).
// seen_emit catches a second line. Other keywords are a light's, misplaced.
void read_material_extension(const Lines& in, Material& m, int material_line, bool& seen_emit) {
  const auto& w = in.words();
  if (w.size() < 2) in.fail("'#lockstep' without a keyword (expected 'emit' after a material)");
  if (w[1] == "atten" || w[1] == "spot") misplaced_extension(in);
  if (w[1] != "emit") {
    std::string shown(w[1].substr(0, 32));
    for (char& ch : shown)
      if (!std::isprint(static_cast<unsigned char>(ch))) ch = '?';
    in.fail("unknown '#lockstep' keyword '" + shown + "' after a material (expected 'emit')");
  }
  in.expect_count(5, "#lockstep emit r g b");
  if (seen_emit) in.fail("a second '#lockstep emit' for the material on line " + std::to_string(material_line));
  seen_emit = true;
  const Vec3 e{in.number(2), in.number(3), in.number(4)};
  if (e.x < 0 || e.y < 0 || e.z < 0)
    in.fail("emission must not be negative, got " + std::string(w[2]) + " " + std::string(w[3]) + " " +
            std::string(w[4]));
  m.emission = Vec3{e.x == 0 ? 0.0 : e.x, e.y == 0 ? 0.0 : e.y, e.z == 0 ? 0.0 : e.z};  // -0 reads as 0
}

// Reads a "#lockstep atten|spot ..." line into the light it follows (the
// extension is described in io/nff.h). light_line is the 'l' line's number;
// seen_atten/seen_spot catch a second line of the same kind.
void read_extension(const Lines& in, Light& light, int light_line, bool& seen_atten, bool& seen_spot) {
  const auto& w = in.words();
  if (w.size() < 2) in.fail("'#lockstep' without a keyword (expected 'atten' or 'spot')");
  const std::string_view key = w[1];
  if (key == "emit") misplaced_extension(in);
  auto twice = [&](bool& seen) {
    if (seen)
      in.fail("a second '#lockstep " + std::string(key) + "' for the light on line " + std::to_string(light_line));
    seen = true;
  };
  auto number = [&](size_t i) {
    const double x = in.number(i);
    return x == 0 ? 0.0 : x;  // -0 reads as 0
  };
  if (key == "atten") {
    in.expect_count(5, "#lockstep atten c1 c2 c3");
    twice(seen_atten);
    const Vec3 c{number(2), number(3), number(4)};
    if (c.x < 0 || c.y < 0 || c.z < 0)
      in.fail("attenuation coefficients must not be negative, got " + std::string(w[2]) + " " + std::string(w[3]) +
              " " + std::string(w[4]));
    if (c.x == 0 && c.y == 0 && c.z == 0) in.fail("attenuation coefficients are all 0");
    light.atten = c;
  } else if (key == "spot") {
    in.expect_count(7, "#lockstep spot dx dy dz cutoff_degrees exponent");
    twice(seen_spot);
    const Vec3 d{number(2), number(3), number(4)};
    // Scale by the largest component first, so that any non-zero finite
    // direction normalises without underflow or overflow.
    const double m = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
    if (m == 0) in.fail("spot direction is zero");
    const double cutoff = number(5);
    if (!(cutoff > 0 && cutoff <= 90))
      in.fail("spot cutoff must be in (0, 90] degrees, got " + std::string(w[5]));
    const double exponent = number(6);
    if (exponent < 0) in.fail("spot exponent must not be negative, got " + std::string(w[6]));
    light.spot = true;
    light.spot_dir = normalize(d / m);
    light.spot_cutoff = cutoff;
    light.spot_exponent = exponent;
  } else {
    std::string shown(key.substr(0, 32));
    for (char& ch : shown)
      if (!std::isprint(static_cast<unsigned char>(ch))) ch = '?';
    in.fail("unknown '#lockstep' keyword '" + shown + "' (expected 'atten' or 'spot')");
  }
}

void read_view(Lines& in, View& v) {
  const int v_line = in.line();
  in.expect_count(1, "v");
  bool seen[6] = {};
  const char* keys[6] = {"from", "at", "up", "angle", "hither", "resolution"};
  for (int k = 0; k < 6; ++k) {
    in.require_next("the viewpoint's 'from', 'at', 'up', 'angle', 'hither', 'resolution' lines");
    const auto& w = in.words();
    if (w[0] == kExtension) misplaced_extension(in);
    int which = -1;
    for (int q = 0; q < 6; ++q)
      if (w[0] == keys[q]) which = q;
    if (which < 0) in.fail("expected one of from/at/up/angle/hither/resolution, got '" + std::string(w[0]) + "'");
    if (seen[which]) in.fail("'" + std::string(w[0]) + "' given twice in one viewpoint");
    seen[which] = true;
    switch (which) {
      case 0: in.expect_count(4, "from x y z"); v.from = in.vec3(1); break;
      case 1: in.expect_count(4, "at x y z"); v.at = in.vec3(1); break;
      case 2: in.expect_count(4, "up x y z"); v.up = in.vec3(1); break;
      case 3:
        in.expect_count(2, "angle degrees");
        v.angle = in.number(1);
        if (!(v.angle > 0 && v.angle < 180)) in.fail("camera angle must be between 0 and 180 degrees, got " + std::string(w[1]));
        break;
      case 4:
        in.expect_count(2, "hither distance");
        v.hither = in.number(1);
        if (v.hither < 0) in.fail("hither must not be negative, got " + std::string(w[1]));
        break;
      case 5: {
        in.expect_count(3, "resolution w h");
        const long w_ = in.integer(1), h_ = in.integer(2);
        if (w_ < 1 || h_ < 1 || w_ > kMaxResolution || h_ > kMaxResolution)
          in.fail("resolution " + std::to_string(w_) + " x " + std::to_string(h_) +
                  " is out of range (1 .. " + std::to_string(kMaxResolution) + ")");
        v.xres = int(w_);
        v.yres = int(h_);
        break;
      }
    }
  }
  validate_view(v, in.name(), v_line);
}

// A cone or cylinder: 'c' then "x y z r" for the base and the apex on lines of
// their own (the NFF spec), or all eight numbers on the 'c' line (what the SPD
// programs write: ../shared/spd/README.md). Both radii negative means only the
// inside is visible (the spec; as a sphere's negative radius): a negative base
// radius negates both, and a sign left negative after that is an error (mixed
// signs mean nothing in NFF). Radii both 0 or a zero-length axis leave no surface.
void read_cone(Lines& in, Scene& scene, uint32_t material) {
  const int c_line = in.line();
  Vec3 end[2];
  double r[2];
  if (in.words().size() == 9) {
    for (int k = 0; k < 2; ++k) {
      end[k] = in.vec3(1 + 4 * k);
      r[k] = in.number(4 + 4 * k);
    }
  } else {
    if (in.words().size() != 1)
      in.fail("expected 'c' alone (base and apex on the next two lines) or 'c bx by bz br ax ay az ar', got " +
              std::to_string(in.words().size() - 1) + " numbers");
    const char* which[2] = {"base", "apex"};
    for (int k = 0; k < 2; ++k) {
      if (!in.next())
        in.fail_at_end(std::string("file ends early: expected the ") + which[k] + " 'x y z r' of the cone on line " +
                       std::to_string(c_line));
      if (in.words()[0] == kExtension) misplaced_extension(in);
      in.expect_count(4, k == 0 ? "base x y z radius" : "apex x y z radius");
      end[k] = in.vec3(0);
      r[k] = in.number(3);
    }
  }
  // Errors about the radii and the axis name the 'c' line when all is on it, else
  // the apex line (the last one read).
  const bool inside = r[0] < 0;
  if (inside) r[0] = -r[0], r[1] = -r[1];
  if (r[1] < 0)
  {
    char buf[96];
    std::snprintf(buf, sizeof buf, "cone radii of mixed signs (%g, %g)", inside ? -r[0] : r[0], inside ? -r[1] : r[1]);
    in.fail(std::string(buf) + ": both negative means only the inside is visible, mixed means nothing");
  }
  if (r[0] == 0 && r[1] == 0) in.fail("cone with both radii 0");
  if (end[0].x == end[1].x && end[0].y == end[1].y && end[0].z == end[1].z)
    in.fail("cone with a zero-length axis (base and apex coincide)");
  if (!std::isfinite(length(end[1] - end[0]))) in.fail("cone axis too long (overflow)");
  add_cone(scene, end[0], r[0] == 0 ? 0.0 : r[0], end[1], r[1] == 0 ? 0.0 : r[1], inside, material);
}

}  // namespace

void validate_view(const View& v, const std::string& file, int line) {
  auto fail = [&](const std::string& what) { throw InputError(file, line, what); };
  const Vec3 dir = v.at - v.from;
  if (length(dir) == 0) fail("degenerate camera: 'from' equals 'at'");
  const Vec3 side = cross(normalize(dir), v.up);
  if (!(length(side) > 1e-9 * length(v.up))) fail("degenerate camera: 'up' is zero or parallel to the view direction");
  if (!(v.angle > 0 && v.angle < 180)) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", v.angle);
    fail(std::string("camera angle must be between 0 and 180 degrees, got ") + buf);
  }
  if (v.hither < 0) fail("hither must not be negative");
  if (v.xres < 1 || v.yres < 1 || v.xres > kMaxResolution || v.yres > kMaxResolution)
    fail("resolution out of range (1 .. " + std::to_string(kMaxResolution) + ")");
}

Scene parse_nff(std::string_view text, const std::string& name) {
  Scene scene;
  scene.source = name;
  Lines in(text, name);
  bool have_view = false;
  bool have_material = false;
  uint32_t material = 0;
  auto current_material = [&]() {
    if (!have_material) {  // objects before any 'f' get a plain white diffuse material
      material = add_material(scene, Material{});
      have_material = true;
    }
    return material;
  };
  std::vector<Vec3> verts, normals;
  // The light the next #lockstep line may modify: set by 'l', cleared by every
  // other entity (the extension modifies the light immediately before it).
  bool after_light = false;
  int light_line = 0;
  bool seen_atten = false, seen_spot = false;
  // The same for the material an 'f' line made (#lockstep emit).
  bool after_material = false, seen_emit = false;
  int material_line = 0;

  if (text.empty()) throw InputError(name, 0, "file is empty");
  while (in.next()) {
    const auto& w = in.words();
    const std::string_view e = w[0];
    if (e == kExtension) {
      if (after_light) read_extension(in, scene.lights.back(), light_line, seen_atten, seen_spot);
      else if (after_material) read_material_extension(in, scene.materials[material], material_line, seen_emit);
      else misplaced_extension(in);
      continue;
    }
    after_light = e == "l";
    after_material = e == "f";
    if (e == "v") {
      if (have_view) in.fail("a second viewpoint ('v'); NFF allows one");
      read_view(in, scene.view);
      have_view = true;
    } else if (e == "b") {
      in.expect_count(4, "b r g b");
      scene.background = in.vec3(1);
    } else if (e == "l") {
      if (w.size() != 4 && w.size() != 7) in.fail("expected 'l x y z' or 'l x y z r g b'");
      Light l;
      l.position = in.vec3(1);
      if (w.size() == 7) {
        l.color = in.vec3(4);
        l.has_color = true;
      }
      scene.lights.push_back(l);
      light_line = in.line();
      seen_atten = seen_spot = false;
    } else if (e == "f") {
      in.expect_count(9, "f r g b Kd Ks Shine T index_of_refraction");
      Material m;
      m.color = in.vec3(1);
      m.kd = in.number(4);
      m.ks = in.number(5);
      m.shine = in.number(6);
      m.transmittance = in.number(7);
      m.ior = in.number(8);
      m.line = in.line();
      material = add_material(scene, m);
      have_material = true;
      material_line = in.line();
      seen_emit = false;
    } else if (e == "s") {
      in.expect_count(5, "s x y z radius");
      const double r = in.number(4);
      if (r == 0) in.fail("sphere of radius 0");
      add_sphere(scene, in.vec3(1), r, current_material());
    } else if (e == "p" || e == "pp") {
      const bool patch = e == "pp";
      in.expect_count(2, patch ? "pp vertex_count" : "p vertex_count");
      const long n = in.integer(1);
      if (n < 3) in.fail("polygon with " + std::to_string(n) + " vertices (at least 3 needed)");
      if (n > kMaxPolygonVertices) in.fail("polygon with " + std::to_string(n) + " vertices is absurd");
      verts.clear();
      normals.clear();
      const int poly_line = in.line();
      for (long i = 0; i < n; ++i) {
        if (!in.next())
          in.fail_at_end("file ends early: expected vertex " + std::to_string(i + 1) + " of " + std::to_string(n) +
                         " of the " + (patch ? "patch" : "polygon") + " on line " + std::to_string(poly_line));
        if (in.words()[0] == kExtension) misplaced_extension(in);
        in.expect_count(patch ? 6 : 3, patch ? "x y z nx ny nz" : "x y z");
        verts.push_back(in.vec3(0));
        if (patch) {
          const Vec3 nv = in.vec3(3);
          if (length(nv) == 0) in.fail("zero vertex normal");
          normals.push_back(nv);
        }
      }
      add_polygon(scene, verts, normals, current_material());
    } else if (e == "c") {
      read_cone(in, scene, current_material());
    } else {
      std::string shown(e.substr(0, 32));
      for (char& ch : shown)
        if (!std::isprint(static_cast<unsigned char>(ch))) ch = '?';
      in.fail("unknown entity '" + shown + "'");
    }
  }
  if (!have_view) throw InputError(name, 0, "no viewpoint ('v') in the file");
  return scene;
}

Scene read_nff(const std::string& path) {
  const std::string text = text::read_text_file(
      path, {.folder = "is a folder, not an NFF file", .unreadable = "cannot open file"}, SIZE_MAX);
  return parse_nff(text, path);
}

}  // namespace lockstep
