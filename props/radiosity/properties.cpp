// lockstep props/radiosity: the radiosity family's properties.
//
// Cases are closed boxes (props: every wall facing in, cut on grids that meet
// along the box's edges, so the patches leave no crack): sides 0.5-4 times a
// scale of 10^-2..10^3, moved up to 10^3 scales from the origin, the camera
// inside looking anywhere, 6-16 pixels a side, 20-150 patches, a random
// form-factor method (rays or exact k = 1-3, hemicube 16-32 pixels) and solver.
//
//   Enclosure.radiosity__<impl>  (part "enclosure") every wall emits E and
//       reflects rho: in a closed enclosure B = E / (1 - rho sum_j F_ij) for
//       every patch, and a correct method's row sums are known: 1 for rays
//       (Lambert's factors from a point inside a closed box partition its
//       hemisphere exactly; no ray is blocked), W = the hemicube's total
//       delta form factor for the hemicube (every pixel sees a wall). Every
//       pixel shows B within kEnclosure (relative; the solve runs to 1e-10).
//       Jacobi and Gauss-Seidel: progressive refinement shoots by
//       reciprocity, which point-to-area factors keep only approximately.
//       |W - 1| is the hemicube's own error (tests/radiosity_rows_test.cpp bounds it).
//   Agree.radiosity__<impl>      (part "agree") the ceiling emits, a block
//       floats inside: every pixel of the row's image equals the
//       reference's within the family's abs (1/255), every method alike
//       (the rays decide in float in the simd row, in double in the
//       reference). Known failure (simd, per hemicube case): a
//       hemicube sample exactly on the edge where two polygons meet sees
//       both at one depth, and each z-buffer rounds that depth its own way
//       (the reference from interpolated 1/z, the simd one from the depth
//       plane): the pixel goes to another patch. Such an image pixel is
//       explained when the two form-factor matrices differ by at most
//       kMaxTiePixels pixels' delta form factors in all and the pixel's
//       difference is within the family's hard bound; the case, one unit of
//       class "hemicube case", then carries the known failure's label (ties
//       cluster in a case: its pixels are not independent trials).
#include <gtest/gtest.h>
#include <rapidcheck.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include "core/error.h"
#include "core/radiosity.h"
#include "io/nff.h"
#include "optimized/radiosity_simd.h"
#include "reference/radiosity.h"
#include "props/gen/numbers.h"
#include "props/pixels.h"
#include "props/property.h"

namespace lockstep::props::radiosity {

namespace {

// B against E / (1 - rho W): float images, a solve to 1e-10.
constexpr double kEnclosure = 1e-5;
// At most this many hemicube pixels may change hands by z-buffer ties in one case.
constexpr int kMaxTiePixels = 4;

struct RadCase {
  int width = 8, height = 8;
  Params params;
  std::string nff;  // the scene, as a file would hold it
};

std::string write_case(const RadCase& c) {
  std::string s = "size " + std::to_string(c.width) + " " + std::to_string(c.height) + "\nparams";
  for (const auto& [k, v] : c.params.items) s += " " + k + "=" + v;
  return s + "\n" + c.nff;
}

RadCase read_case(const std::string& text, const std::string& file) {
  RadCase c;
  // The counterexample file's own comment lines come first.
  size_t start = 0;
  while (text.compare(start, 2, "# ") == 0 && text.find('\n', start) != std::string::npos)
    start = text.find('\n', start) + 1;
  std::istringstream in(text.substr(start));
  std::string word, line;
  if (!(in >> word >> c.width >> c.height) || word != "size") throw InputError(file, 1, "expected 'size W H'");
  std::getline(in, line);
  std::getline(in, line);
  std::istringstream p(line);
  p >> word;
  if (word != "params") throw InputError(file, 2, "expected 'params k=v ...'");
  while (p >> word) {
    const size_t eq = word.find('=');
    if (eq == std::string::npos) throw InputError(file, 2, "expected k=v, got '" + word + "'");
    c.params.set(word.substr(0, eq), word.substr(eq + 1));
  }
  c.nff = text.substr(start + size_t(in.tellg()));
  return c;
}

std::string num(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}
std::string vec(const Vec3& v) { return num(v.x) + " " + num(v.y) + " " + num(v.z) + "\n"; }

// A quad as NFF text, corners in order (counter-clockwise about its facing).
std::string quad(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return "p 4\n" + vec(a) + vec(b) + vec(c) + vec(d);
}

// The six faces of the box [lo, hi], facing in (inward) or out.
std::string box(const Vec3& lo, const Vec3& hi, bool inward, const std::string& ceiling_material) {
  const Vec3 p[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
                     {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  // Outward-facing faces (counter-clockwise seen from outside); reversed for inward.
  const int f[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
  std::string s;
  for (int k = 0; k < 6; ++k) {
    if (k == 3 && !ceiling_material.empty()) s += ceiling_material;  // y = hi: the ceiling
    if (inward)
      s += quad(p[f[k][3]], p[f[k][2]], p[f[k][1]], p[f[k][0]]);
    else
      s += quad(p[f[k][0]], p[f[k][1]], p[f[k][2]], p[f[k][3]]);
  }
  return s;
}

enum class Kind { enclosure, occluded };

rc::Gen<RadCase> case_gen(Kind kind) {
  return rc::gen::exec([kind] {
    RadCase c;
    const double scale = *gen::log_uniform(1e-2, 1e3);
    const Vec3 size{*gen::uniform(0.5, 4) * scale, *gen::uniform(0.5, 4) * scale, *gen::uniform(0.5, 4) * scale};
    const Vec3 lo{*gen::uniform(-1e3, 1e3) * scale, *gen::uniform(-1e3, 1e3) * scale, *gen::uniform(-1e3, 1e3) * scale};
    const Vec3 hi = lo + size;
    c.width = int(*gen::int_in(6, 16));
    c.height = int(*gen::int_in(6, 16));
    // The camera inside, looking anywhere.
    const Vec3 eye = lo + Vec3{size.x * *gen::uniform(0.3, 0.7), size.y * *gen::uniform(0.3, 0.7),
                               size.z * *gen::uniform(0.3, 0.7)};
    const Vec3 dir = *gen::unit_dir();
    const Vec3 up = std::abs(dir.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
    std::string s = "v\nfrom " + vec(eye) + "at " + vec(eye + dir * scale) + "up " + vec(up) + "angle " +
                    num(*gen::uniform(40, 100)) + "\nhither " + num(1e-3 * scale) + "\nresolution " +
                    std::to_string(c.width) + " " + std::to_string(c.height) + "\nb 0 0 0\n";
    const Vec3 rho{*gen::uniform(0, 0.9), *gen::uniform(0, 0.9), *gen::uniform(0, 0.9)};
    const std::string wall = "f " + num(rho.x) + " " + num(rho.y) + " " + num(rho.z) + " 1 0 1 0 1\n";
    if (kind == Kind::enclosure) {
      const Vec3 e{*gen::uniform(0.1, 10), *gen::uniform(0.1, 10), *gen::uniform(0.1, 10)};
      s += wall + "#lockstep emit " + vec(e) + box(lo, hi, true, "");
    } else {
      s += wall + box(lo, hi, true, "f 0.5 0.5 0.5 1 0 1 0 1\n#lockstep emit 5 5 5\n");
      // A block floating in the middle of the box, facing out.
      const Vec3 blo = lo + Vec3{size.x * *gen::uniform(0.15, 0.4), size.y * *gen::uniform(0.15, 0.4),
                                 size.z * *gen::uniform(0.15, 0.4)};
      const Vec3 bhi = lo + Vec3{size.x * *gen::uniform(0.6, 0.85), size.y * *gen::uniform(0.6, 0.85),
                                 size.z * *gen::uniform(0.6, 0.85)};
      s += "f 0.6 0.3 0.2 1 0 1 0 1\n" + box(blo, bhi, false, "");
    }
    c.nff = s;
    const double area = 2 * (size.x * size.y + size.y * size.z + size.z * size.x);
    c.params.set("patch_area", num(area / *gen::uniform(20, 120)));
    // Half the cases hemicube: its known failure (ties) is rare and clusters
    // in a case, and its stated rate was measured on this share.
    if (const int m = *gen::int_in(0, 3); m < 2) {
      c.params.set("form_factors", m == 0 ? "rays" : "exact");
      c.params.set("rays", std::to_string(*gen::int_in(1, 3)));
    } else {
      c.params.set("form_factors", "hemicube");
      c.params.set("hemicube", std::to_string(2 * *gen::int_in(8, 16)));
    }
    // Progressive refinement shoots row i's energy to j by reciprocity
    // (F_ji = A_i F_ij / A_j), which point-to-area factors keep only
    // approximately (tests/radiosity_rows_test.cpp: the gap measured): its
    // enclosure is not E / (1 - rho W), so it is judged by agreement only.
    static const char* kSolvers[] = {"jacobi", "gauss-seidel", "progressive"};
    c.params.set("solver", kSolvers[*gen::int_in(0, kind == Kind::enclosure ? 1 : 2)]);
    c.params.set("tolerance", "1e-10");
    // A third of the rays and exact agreement cases refine (--error): the
    // rows' solutions agree to rounding, so their cuts do. (Not the
    // hemicube's: its tie rule compares the unrefined meshes.)
    if (kind != Kind::enclosure && c.params.get("form_factors") != "hemicube" && *gen::int_in(0, 2) == 0)
      c.params.set("error", num(*gen::uniform(0.05, 0.3)));
    return c;
  });
}

Image run(const FamilyImpl& impl, const RadCase& c) {
  Input in;
  in.value = std::shared_ptr<const Scene>(std::make_shared<Scene>(parse_nff(c.nff, "case.nff")));
  in.source = "case.nff";
  FrameOptions o;
  o.width = c.width;
  o.height = c.height;
  o.threads = 1;
  o.params = c.params;
  FrameStats st;
  return impl.run_as<Image>(in, o, &st);
}

// The hemicube's total delta form factor.
double hemicube_total(int res) {
  const HemicubeWeights w = hemicube_weights(res);
  double t = 0;
  for (double x : w.top) t += x;
  double side = 0;
  for (double x : w.side) side += x;
  return t + 4 * side;
}

Verdict enclosure(const FamilyImpl& impl, const RadCase& c) {
  const Image image = run(impl, c);
  const Scene scene = parse_nff(c.nff, "case.nff");
  const Material& m = scene.materials[scene.poly_material[0]];
  const double w = c.params.get("form_factors") == "hemicube" ? hemicube_total(std::stoi(c.params.get("hemicube"))) : 1;
  const Vec3 rho = m.color * m.kd;
  const Vec3 expect{m.emission.x / (1 - rho.x * w), m.emission.y / (1 - rho.y * w), m.emission.z / (1 - rho.z * w)};
  Image want(image.width, image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) want.set(x, y, expect);
  // Relative: B ranges over 0.1..100.
  const double scale = std::max({expect.x, expect.y, expect.z});
  Image a = image, b = want;
  for (float& v : a.rgba) v = float(v / scale);
  for (float& v : b.rgba) v = float(v / scale);
  return compare_pixels(b, a, kEnclosure, "enclosure", [&](int x, int y, double err) {
    return c.params.str() + " pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): E / (1 - rho W) " +
           pixel_text(want.pixel(x, y)) + ", " + std::string(impl.name) + " " + pixel_text(image.pixel(x, y)) +
           ", relative error " + std::to_string(err) + " > " + std::to_string(kEnclosure);
  });
}

// Whether two hemicube form-factor matrices differ only as z-buffer ties
// do: by at most kMaxTiePixels pixels' delta form factors in all. (A sample
// exactly on the edge where two polygons meet sees both at one depth; each
// z-buffer rounds that depth its own way, and keeps its own. Vertices are
// snapped to 1/256 pixel, so edges pass through sample points often.)
bool hemicube_ties_only(const RadCase& c, const FamilyImpl& impl) {
  if (c.params.get("form_factors") != "hemicube" || impl.name != "simd") return false;
  const Scene scene = parse_nff(c.nff, "case.nff");
  const RadiositySettings rs = radiosity_settings(c.params, "case");
  const PatchMesh mesh = mesh_scene(scene, rs.patch_area);
  const FormFactors a = ref::form_factors_hemicube(mesh, rs.hemicube);
  const FormFactors b = opt::simd::radiosity_form_factors_hemicube(mesh, rs.hemicube, 1);
  const HemicubeWeights w = hemicube_weights(rs.hemicube);
  const double pixel = *std::max_element(w.top.begin(), w.top.end());
  // A pixel that changes hands moves its weight out of one entry and into
  // another (or none: a face seen from behind).
  double moved = 0;
  for (size_t k = 0; k < a.size(); ++k) moved += std::abs(a[k] - b[k]);
  return moved <= 2 * kMaxTiePixels * pixel * (1 + 1e-9);
}

Verdict agree(const Family& family, const FamilyImpl& ref, const FamilyImpl& impl, const RadCase& c) {
  const Image a = run(ref, c), b = run(impl, c);
  const Tolerance& tol = impl.tolerance(family.tol);
  Verdict v = compare_pixels(a, b, tol.abs, "disagree", [&](int x, int y, double err) {
    return c.params.str() + " pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): reference " +
           pixel_text(a.pixel(x, y)) + ", " + std::string(impl.name) + " " + pixel_text(b.pixel(x, y)) +
           ", error " + std::to_string(err) + " > " + std::to_string(tol.abs);
  });
  if (c.params.get("form_factors") != "hemicube") return v;
  // Hemicube cases: the pixels a z-buffer tie moved are explained (at most
  // kMaxTiePixels hemicube pixels changed hands, none over the hard bound),
  // and the case is the unit of the known failure's rate: ties cluster in a
  // case (one edge through a column of sample points), so its pixels are not
  // independent trials (measured per pixel: 0% to 0.12% over four seeds).
  bool tied = false;
  if (!v.passed() && !impl.known.label.empty() && hemicube_ties_only(c, impl))
    for (Outcome& o : v.rays)
      if (o.kind == Outcome::unexplained && o.err <= tol.hard) {
        o.kind = Outcome::explained;
        o.label = "hemicube_tie_pixel";
        tied = true;
      }
  Outcome whole;
  whole.cls = "hemicube case";
  whole.unit = "hemicube cases";
  if (tied) {
    whole.kind = Outcome::explained;
    whole.label = known_label(std::string(impl.name), impl.known);
    whole.detail = c.params.str() + ": pixels moved by hemicube z-buffer ties";
  }
  v.rays.push_back(whole);
  return v;
}

Property property(const Family& family, const FamilyImpl& impl, const char* suite, const char* check,
                  const char* generator, rc::Gen<RadCase> gen, std::function<Verdict(const RadCase&)> judge,
                  const char* unit) {
  return case_property<RadCase>(family, impl, suite, check, generator, unit, "pixels", std::move(gen), std::move(judge),
                                write_case, read_case);
}

}  // namespace

FamilyProperties properties(const Family& family, RunResources&) {
  FamilyProperties out;
  const FamilyImpl& ref = family.reference();
  for (const FamilyImpl& impl : family.impls) {
    const FamilyImpl* ip = &impl;
    if (family.has_property("enclosure")) {
      Property p = property(family, impl, "Enclosure", "enclosure", "closed_box", case_gen(Kind::enclosure),
                            [ip](const RadCase& c) { return enclosure(*ip, c); }, "relative radiosity error");
      p.bound = kEnclosure;
      out.properties.push_back(std::move(p));
    }
    if (family.has_property("agree") && ip != &ref) {
      Property p = property(family, impl, "Agree", "agree", "box_with_block", case_gen(Kind::occluded),
                            [&family, &ref, ip](const RadCase& c) { return agree(family, ref, *ip, c); },
                            "channel difference");
      p.bound = family.tol.abs;
      p.known = impl.known;
      out.properties.push_back(std::move(p));
    }
  }
  return out;
}

}  // namespace lockstep::props::radiosity
