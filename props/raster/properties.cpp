// lockstep props/raster: the raster families' properties, for the driver.
//
//   RayCastCrossCheck.zbuffer__<impl>   a z-buffer frame with per-sample Phong
//       equals the ray-cast frame (reference ray caster) pixel for pixel: both
//       sample pixel centres with the same camera. A pixel may differ only where
//       its centre lies within kEdgeBand pixels of a triangle's projected edge
//       (vertex snapping to 1/256 pixel moves edges by at most sqrt(2)/512 px:
//       the fill rule and the snap decide those), or where two triangles are
//       within a relative depth of kDepthTie at the centre (depth is computed
//       from snapped vertices): the two nearest surfaces' depth intervals over
//       the centre moved by up to 2 kEdgeBand overlap ("depth_tie": the snap moves
//       a steep triangle's depth at a pixel by its depth gradient times the snap).
//       Or the colour is within 1/255 of the ray-cast colours' range over those
//       moved centres ("snap_shading": depth from snapped vertices moves the
//       shaded point along the ray).
//       Anything else is unexplained.
//
// The parts of props/raster (one file each: visibility, painter, scanline,
// interpolation, llvmpipe, ...) are functions `void X_part(const Family&,
// FamilyProperties&)` declared in props/raster/parts.h and listed in kParts
// below by name; a family's row (registry/raster_rows.cpp, Family::properties) names
// the parts that apply to it, and each adds what it tests of that family.
// props/families.cpp maps every raster family (zbuffer, scanline, painter) to
// properties().
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/camera.h"
#include "core/shading.h"
#include "reference/ray_cast.h"
#include "registry/registry.h"
#include "props/property.h"
#include "props/raster/parts.h"
#include "props/raster/raster_case.h"

namespace lockstep::props::raster {

FamilyProperties properties(const Family& family, RunResources&);

namespace {

constexpr double kEdgeBand = 0.003;  // pixels: > sqrt(2)/512 = 0.00276

// Distance, in pixels, from screen point (x, y) to segment a-b.
double segment_distance(double x, double y, double ax, double ay, double bx, double by) {
  const double dx = bx - ax, dy = by - ay;
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0 ? ((x - ax) * dx + (y - ay) * dy) / len2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(x - (ax + t * dx), y - (ay + t * dy));
}

// The ray parameter where the pixel-centre ray meets triangle (a, b, c), or inf.
double ray_triangle(const Ray& r, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a, p = cross(r.d, e2);
  const double det = dot(e1, p);
  if (det == 0) return kInfinity;
  const Vec3 s = r.o - a;
  const double u = dot(s, p) / det;
  const Vec3 q = cross(s, e1);
  const double v = dot(r.d, q) / det;
  const double t = dot(e2, q) / det;
  if (u < -1e-9 || v < -1e-9 || u + v > 1 + 1e-9 || t <= r.tmin) return kInfinity;
  return t;
}

// Why pixel (i, j) may differ between the two frames (the z-buffer's colour
// is got), or "" when nothing explains it.
std::string explain(const Scene& scene, const Camera& cam, int i, int j, const float* got) {
  const double px = i + 0.5, py = j + 0.5;
  auto screen = [&](const Vec3& p, double& x, double& y) {
    const Vec3 d = p - cam.eye;
    const double ze = dot(d, cam.forward);
    if (ze <= 0) return false;
    x = 0.5 * cam.width + dot(d, cam.right) / (ze * cam.pitch);
    y = 0.5 * cam.height - dot(d, cam.up) / (ze * cam.pitch);
    return true;
  };
  const Ray ray = cam.primary(i, j);
  // The ray through the centre moved by (dx, dy) pixels.
  auto moved = [&](double dx, double dy) {
    const Vec3 d = cam.forward + (cam.sx(i) + dx * cam.pitch) * cam.right + (cam.sy(j) - dy * cam.pitch) * cam.up;
    return Ray{cam.eye, d / length(d), 0, kInfinity};
  };
  struct Interval {
    double lo, hi;
  };
  std::vector<Interval> ts;
  for (const auto& t : scene.tri_vertex) {
    double x[3], y[3];
    bool ok = true;
    for (int k = 0; k < 3; ++k) ok = ok && screen(scene.vertex[t[k]], x[k], y[k]);
    if (ok)
      for (int k = 0; k < 3; ++k)
        if (segment_distance(px, py, x[k], y[k], x[(k + 1) % 3], y[(k + 1) % 3]) <= kEdgeBand) return "on_edge";
    const Vec3 &a = scene.vertex[t[0]], &b = scene.vertex[t[1]], &c = scene.vertex[t[2]];
    if (!std::isfinite(ray_triangle(ray, a, b, c))) continue;
    // Depth along the plane over the moved centres (the plane, not the triangle).
    const Vec3 n = cross(b - a, c - a);
    Interval iv{kInfinity, -kInfinity};
    for (double dx : {-2 * kEdgeBand, 0.0, 2 * kEdgeBand})
      for (double dy : {-2 * kEdgeBand, 0.0, 2 * kEdgeBand}) {
        const Ray m = moved(dx, dy);
        const double z = dot(a - m.o, n) / dot(m.d, n) * dot(m.d, cam.forward);
        iv.lo = std::min(iv.lo, z);
        iv.hi = std::max(iv.hi, z);
      }
    ts.push_back(iv);
  }
  std::sort(ts.begin(), ts.end(), [](const Interval& x, const Interval& y) { return x.lo < y.lo; });
  if (ts.size() >= 2 && ts[1].lo <= ts[0].hi) return "depth_tie";
  // The ray-cast colours over the moved centres.
  Vec3 lo{kInfinity, kInfinity, kInfinity}, hi = -lo;
  for (double dx : {-2 * kEdgeBand, 0.0, 2 * kEdgeBand})
    for (double dy : {-2 * kEdgeBand, 0.0, 2 * kEdgeBand}) {
      Ray m = moved(dx, dy);
      m.tmin = scene.view.hither / dot(m.d, cam.forward);
      Hit h;
      ref::trace(scene, std::span<const Ray>(&m, 1), std::span<Hit>(&h, 1), nullptr);
      const Vec3 c = shade(scene, m, h);
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], c[k]);
        hi[k] = std::max(hi[k], c[k]);
      }
    }
  bool within = true;
  for (int k = 0; k < 3; ++k) within = within && got[k] >= lo[k] - 1.0 / 255 && got[k] <= hi[k] + 1.0 / 255;
  if (within) return "snap_shading";
  return "";
}

Verdict cross_check(const FamilyImpl& impl, const RasterCase& c) {
  const auto scene = c.scene();
  const Input in = make_input<Scene>(*scene, "<case>", c.width, c.height, scene->background);
  const FrameOptions o = c.options();
  FrameStats st;
  const Image z = impl.run_as<Image>(in, o, &st);
  const Family* rc_family = registry().find("ray_cast");
  const Image r = rc_family->reference().run_as<Image>(in, o, &st);
  const Camera cam = Camera::from_view(scene->view, c.width, c.height);
  Verdict v;
  for (int j = 0; j < c.height; ++j)
    for (int i = 0; i < c.width; ++i) {
      const float* a = z.pixel(i, j);
      const float* b = r.pixel(i, j);
      double err = 0;
      for (int k = 0; k < 3; ++k) err = std::max(err, double(std::abs(a[k] - b[k])));
      Outcome out;
      out.err = err;
      out.measured = true;
      out.unit = "colour";
      if (err <= 1.0 / 255) {
        v.rays.push_back(out);
        continue;
      }
      const std::string why = explain(*scene, cam, i, j, a);
      out.kind = why.empty() ? Outcome::unexplained : Outcome::explained;
      out.label = why.empty() ? "differs" : why;
      std::ostringstream d;
      d << "pixel (" << i << ", " << j << "): " << impl.name << " (" << a[0] << ", " << a[1] << ", " << a[2]
        << ") vs ray cast (" << b[0] << ", " << b[1] << ", " << b[2] << "), error " << err;
      out.detail = d.str();
      v.rays.push_back(out);
    }
  return v;
}

Property cross_check_property(const Family& family, const FamilyImpl& impl) {
  return case_property(family, impl, "RayCastCrossCheck", "triangle_soup", triangle_soup(), 1.0 / 255, "colour",
                       [&impl](const RasterCase& c) { return cross_check(impl, c); });
}

}  // namespace

Property case_property(const Family& family, const FamilyImpl& impl, std::string suite, std::string generator,
                       rc::Gen<RasterCase> gen, double bound, std::string unit,
                       std::function<Verdict(const RasterCase&)> check) {
  Property p;
  p.family = std::string(family.name);
  // "RayCastCrossCheck" -> "ray_cast_cross_check"
  for (char ch : suite) {
    if (std::isupper(static_cast<unsigned char>(ch)) && !p.check.empty()) p.check += '_';
    p.check += char(std::tolower(static_cast<unsigned char>(ch)));
  }
  p.suite = suite;
  p.name = std::string(family.name) + "__" + std::string(impl.name);
  p.generator = generator;
  p.pair = std::string(family.name);
  p.impl = std::string(impl.name);
  p.bound = bound;
  p.unit = unit;
  p.units = "pixels";
  const auto g = std::make_shared<const rc::Gen<RasterCase>>(std::move(gen));
  p.run = [g, check] {
    auto c = std::make_shared<const RasterCase>(**g);
    Ran r;
    r.verdict = check(*c);
    r.text = [c](long) { return write_case(*c); };
    return r;
  };
  p.replay = [check](const std::string& text, const std::string& file) { return check(read_case(text, file)); };
  return p;
}

void cross_check_part(const Family& family, FamilyProperties& out) {
  // The cross-check shades per pixel (Phong); an implementation that cannot
  // (llvmpipe: flat and Gouraud only) says so through its unsupported().
  const Params phong{{{"shading", "phong"}}};
  for (const FamilyImpl& impl : family.impls)
    if (!impl.unsupported || impl.unsupported(phong).empty())
      out.properties.push_back(cross_check_property(family, impl));
}

// Every part of props/raster, by the name a family's row lists it under
// (Family::properties, registry/raster_rows.cpp): a family gets the parts it names.
FamilyProperties properties(const Family& family, RunResources&) {
  using Part = void (*)(const Family&, FamilyProperties&);
  struct Named {
    std::string_view name;
    Part part;
  };
  static constexpr Named kParts[] = {
      {"cross_check", cross_check_part},
      {"culling", culling_part},
      {"render_agree", render_agree_part},
      {"supersampling", supersampling_part},
      {"scanline", scanline_part},
      {"interpolation", interpolation_part},
      {"visibility", visibility_part},
      {"llvmpipe", llvmpipe_part},
      {"painter", painter_part},
      {"hidden", hidden_part},
      {"shadow_volume", shadow_volume_part},
      {"shadow_map", shadow_map_part},
      {"first_drawn", first_drawn_part},
  };
  FamilyProperties out;
  for (const Named& n : kParts)
    if (family.has_property(n.name)) n.part(family, out);
  // A part the row names that does not exist here would go untested.
  for (std::string_view name : family.properties) {
    bool known = false;
    for (const Named& n : kParts) known = known || n.name == name;
    if (known) continue;
    const std::string fam(family.name), part(name);
    out.fixed.push_back({"Registry", fam + "__" + part + "_is_a_property_part", [fam, part] {
                           FAIL() << "registry/raster_rows.cpp lists property part '" << part << "' for family " << fam
                                  << ", which props/raster/properties.cpp does not have";
                         }});
  }
  return out;
}

}  // namespace lockstep::props::raster
