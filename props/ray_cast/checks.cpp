#include "props/ray_cast/checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "core/camera.h"
#include "core/shading.h"
#include "props/property.h"
#include "props/ray_cast/conditioning.h"

namespace lockstep::props::ray_cast {

namespace {

std::string t_text(double t) { return hex(t) + " (" + dec(t) + ")"; }

std::string answer_text(const Hit& h) {
  return h.hit() ? "prim " + std::to_string(h.prim) + " t " + t_text(h.t) : "miss (prim none, t " + hex(h.t) + ")";
}

std::string oracle_text(const OracleTrace& o) {
  std::string s = "oracle: ";
  s += o.best.hit ? "prim " + std::to_string(o.prim) + " " : "";
  s += describe(o.best);
  return s;
}

std::string ray_line(const Case& c, size_t i) { return "ray " + std::to_string(i) + ": " + hex(c.rays[i]); }

bool is_tied(const OracleTrace& o, uint32_t p) { return std::find(o.tied.begin(), o.tied.end(), p) != o.tied.end(); }

// The spot cone's edge is a second decision boundary in a render (io/nff.h):
// inside the cone the light counts, outside it does not. A pixel whose hit
// point p sits on the edge within the implementation's arithmetic may
// legitimately differ. The decision is cos(angle) = -L.D >= cos(cutoff); in
// float, p carries an error of about eps |p - eye| (the frame's origin is near
// the eye) and the light's position eps |light - eye|, each turning L by that
// over |light - p|, plus a few eps of rounding in L and D. Returns the light's
// index when |cos(angle) - cos(cutoff)| is within band times that, else -1.
int on_spot_edge(const Scene& scene, const Vec3& eye, const Vec3& p, double band) {
  for (size_t k = 0; k < scene.lights.size(); ++k) {
    const Light& light = scene.lights[k];
    if (!light.spot) continue;
    const double d = length(light.position - p);
    const Vec3 l = (light.position - p) / d;
    const double margin = std::abs(dot(-l, light.spot_dir) - spot_cos_cutoff(light));
    const double scale = 1.0 + (length(p - eye) + length(light.position - eye)) / d;
    if (margin <= band * scale) return int(k);
  }
  return -1;
}

}  // namespace

Verdict check_accuracy(const Subject& s, const Case& c) {
  Verdict v;
  const ImplInfo& im = s.info;
  const auto hits = s.answer(c);
  for (size_t i = 0; i < c.rays.size(); ++i) {
    const OracleTrace o = s.oracle(c, c.rays[i]);
    Outcome out;
    const Hit& h = hits[i];
    if (!well_in_frame(o.best, im)) {
      out.kind = Outcome::skipped;
      out.label = "ill:" + ill_why(o.best, im);
    } else if (std::isnan(h.t) || h.hit() != o.best.hit) {
      out.kind = Outcome::unexplained;
      out.label = std::isnan(h.t) ? "nan" : (o.best.hit ? "false_miss" : "false_hit");
      out.err = kInfinity;
    } else if (h.hit()) {
      if (!is_tied(o, h.prim)) {
        out.kind = Outcome::unexplained;
        out.label = "wrong_prim";
        out.err = kInfinity;
      } else {
        out.measured = true;
        out.err = rel_error(h.t, o.per_prim[h.prim].t);
        if (!(out.err <= im.bound)) {
          out.kind = Outcome::unexplained;
          out.label = "t_error";
        }
      }
    }
    out.detail = ray_line(c, i) + "; " + im.name + " " + answer_text(h) + "; " + oracle_text(o) + "; rel error " +
                 dec(out.err) + " (bound " + dec(im.bound) + ")";
    v.rays.push_back(out);
  }
  return v;
}

Verdict check_agreement(const Subject& s, const Case& c) {
  Verdict v;
  const Subject& ref = reference_of(s.info.pair);
  const double tol = s.info.agree_t_rel > 0 ? s.info.agree_t_rel : s.tol.t_rel;
  auto rel = [](double a, double b) {
    if (std::isinf(a) && std::isinf(b)) return 0.0;
    return std::abs(a - b) / std::abs(b);
  };
  const auto hits = s.answer(c);
  const auto ref_hits = ref.answer(c);
  for (size_t i = 0; i < c.rays.size(); ++i) {
    const OracleTrace o = s.oracle(c, c.rays[i]);
    Outcome out;
    const Hit& h = hits[i];
    const Hit& r = ref_hits[i];
    if (!well_in_frame(o.best, s.info) || !well_in_frame(o.best, ref.info)) {
      out.kind = Outcome::skipped;
      out.label = "ill";
    } else if (std::isnan(h.t) || h.hit() != r.hit()) {
      out.kind = Outcome::unexplained;
      out.label = std::isnan(h.t) ? "nan" : "hit_miss_differs";
      out.err = kInfinity;
    } else if (h.hit()) {
      if (h.prim != r.prim && !(is_tied(o, h.prim) && is_tied(o, r.prim))) {
        out.kind = Outcome::unexplained;
        out.label = "prim_differs";
        out.err = kInfinity;
      } else {
        out.measured = true;
        out.err = rel(h.t, r.t);
        if (!(out.err <= tol)) {
          out.kind = Outcome::unexplained;
          out.label = "t_differs";
        }
      }
    }
    out.detail = ray_line(c, i) + "; " + s.info.name + " " + answer_text(h) + "; " + ref.info.name + " " +
                 answer_text(r) + "; " + oracle_text(o) + "; rel difference " + dec(out.err) + " (tol " + dec(tol) +
                 ")";
    v.rays.push_back(out);
  }
  return v;
}

Verdict check_stability(const Subject& s, const Case& c) {
  Verdict v;
  const auto hits = s.answer(c);
  for (size_t i = 0; i < c.rays.size(); ++i) {
    const OracleTrace o = s.oracle(c, c.rays[i]);
    Outcome out = judge(o, hits[i], s.info);
    out.detail = ray_line(c, i) + "; " + s.info.name + " " + answer_text(hits[i]) + "; " + oracle_text(o) +
                 "; rel error " + dec(out.err) + " (bound " + dec(s.info.bound) + "); " +
                 (out.kind == Outcome::ok ? "ok" : out.label);
    v.rays.push_back(out);
  }
  return v;
}

Verdict check_watertight(const Subject& s, const Case& c) {
  Verdict v;
  if (!s.answer_polygons) throw std::runtime_error(s.info.pair + " cannot intersect polygons");
  const auto hits = s.answer_polygons(c);
  for (size_t i = 0; i < c.rays.size(); ++i) {
    const OracleContact o = oracle_contact(c.scene, c.rays[i]);
    const Hit& h = hits[i];
    Outcome out;
    const bool hit = h.t < kInfinity;
    std::string touching;
    for (uint32_t p : o.touching) touching += " " + std::to_string(p);
    if (o.contact && o.transversal)
      out.cls = o.touching.size() >= 3 ? "vertex" : (o.touching.size() == 2 ? "edge" : "face");
    if (std::isnan(h.t)) {
      out.kind = Outcome::unexplained;
      out.label = "nan";
    } else if (!o.contact || !o.transversal) {
      out.label = o.contact ? "silhouette" : "no_contact";  // tangent: either answer is right
    } else if (!hit || (h.t > double(o.t) && rel_error(h.t, o.t) > 1e-3)) {
      // No hit, or a hit clearly beyond the first contact (through the surface to the far side).
      out.err = rel_error(h.t, o.t);
      out.label = o.touching.size() >= 3 ? "leak_vertex" : (o.touching.size() == 2 ? "leak_edge" : "leak_face");
      // The textbook crossings test works on a rounded hit point per polygon, so at a
      // point shared by several polygons it may see it outside all of them.
      out.kind = (s.info.mode == Mode::textbook && o.touching.size() >= 2) ? Outcome::explained : Outcome::unexplained;
      // A library's known failure (the row's Impl::known) is reported under its own
      // label; any other leak still fails.
      if (out.kind == Outcome::unexplained && !s.info.known.label.empty() && out.label == s.info.known.label) {
        out.kind = Outcome::explained;
        out.label = known_label(s.info.name, s.info.known);
      }
    } else {
      out.measured = true;
      out.err = rel_error(h.t, o.t);
      const bool prim_ok = std::find(o.touching.begin(), o.touching.end(), h.prim) != o.touching.end();
      // t within the bound, scaled by the condition number of the worst polygon at
      // the contact (in the frame the implementation computes t in), as in Stability.
      double kappa = 1;
      std::string why = "ill_conditioned";
      for (uint32_t p : o.touching) {
        const OracleHit op = oracle_polygon(c.rays[i], c.scene, p - c.scene.sphere_count());
        const Conditioning& tc = t_view(op, s.info);
        if (tc.kappa > kappa) kappa = tc.kappa, why = tc.kappa_why[0] ? tc.kappa_why : "ill_conditioned";
      }
      const double allowed = s.info.bound * std::max(1.0, kappa / kWellKappa);
      if (!prim_ok) {
        out.kind = Outcome::unexplained;
        out.label = "wrong_prim";
      } else if (!(out.err <= allowed)) {
        out.kind = Outcome::unexplained;
        out.label = "t_error";
      } else if (out.err > s.info.bound) {
        out.kind = Outcome::explained;
        out.label = why;
      }
    }
    out.detail = ray_line(c, i) + "; " + s.info.name + " nearest over polygons " + answer_text(h) +
                 "; oracle contact " + (o.contact ? "t " + hex128(o.t) + " (" + dec(double(o.t)) + ")" : "none") +
                 " touching" + touching + (o.transversal ? " transversal" : " not transversal") + "; rel error " +
                 dec(out.err) + "; " + (out.kind == Outcome::ok ? "ok" : out.label);
    v.rays.push_back(out);
  }
  return v;
}

Verdict check_degenerate(const Subject& s, const Case& c) {
  Verdict v;
  const auto hits = s.answer(c);
  for (size_t i = 0; i < c.rays.size(); ++i) {
    const OracleTrace o = s.oracle(c, c.rays[i]);
    const Hit& h = hits[i];
    Outcome out;
    const bool zero = h.hit() && h.prim < o.per_prim.size() && o.per_prim[h.prim].zero_area;
    if (std::isnan(h.t)) {
      out.kind = Outcome::unexplained;
      out.label = "nan";
    } else if (zero) {
      // The exact polygon has no area. The textbook takes its plane from the
      // scene's Newell normal in double, which for vertices that are collinear
      // only in exact arithmetic is a tiny non-zero vector: it then tests the
      // point against a polygon double sees as a sliver, and the crossings test
      // counts a ray through a vertex as inside. That is the method meeting input
      // below its resolution (explained, textbook only); a zero-area polygon
      // whose double normal is exactly zero must never be hit by anyone.
      const uint32_t poly =
          s.kernel == Kernel::polygon ? c.poly : h.prim - uint32_t(c.scene.sphere_count());
      const bool rounded = poly < c.scene.polygon_count() && length(c.scene.poly_plane[poly].n) > 0;
      out.kind = s.info.mode == Mode::textbook && rounded ? Outcome::explained : Outcome::unexplained;
      out.label = out.kind == Outcome::explained ? "zero_area_rounded" : "hit_zero_area";
    } else {
      out = judge(o, h, s.info);
    }
    out.detail = ray_line(c, i) + "; " + s.info.name + " " + answer_text(h) + (zero ? " (zero area)" : "") + "; " +
                 oracle_text(o) + "; " + (out.kind == Outcome::ok ? "ok" : out.label);
    v.rays.push_back(out);
  }
  return v;
}

Verdict check_render(const Subject& s, const Case& c) {
  Verdict v;
  const Subject& ref = reference_of(s.info.pair);
  FrameOptions opts;
  opts.width = opts.height = c.render_size;
  opts.threads = 1;
  if (!s.render) throw std::runtime_error(s.info.pair + "/" + s.info.name + " does not render");
  const Image a = s.render(c.scene, opts, nullptr);
  const Image b = ref.render(c.scene, opts, nullptr);
  const Camera cam = Camera::from_view(c.scene.view, opts.width, opts.height);
  const double band = band_of(s.info);
  std::vector<Outcome> bad;
  size_t total = 0;
  for (int y = 0; y < opts.height; ++y) {
    for (int x = 0; x < opts.width; ++x) {
      ++total;
      const float* pa = a.pixel(x, y);
      const float* pb = b.pixel(x, y);
      double err = 0;
      for (int k = 0; k < 4; ++k) err = std::max(err, std::abs(double(pa[k]) - double(pb[k])));
      if (!(err > s.tol.color_abs)) continue;
      // A pixel whose primary ray sits on a decision boundary (a silhouette, two
      // surfaces at the same depth) may legitimately differ: ask the oracle.
      const Ray ray = cam.primary(x, y);
      const OracleTrace o = oracle_trace(c.scene, ray);
      Outcome out;
      out.err = err;
      out.kind = view_of(o.best, s.info.mode).margin <= band ? Outcome::explained : Outcome::unexplained;
      out.label = out.kind == Outcome::explained ? view_of(o.best, s.info.mode).margin_why : "pixel";
      if (out.kind == Outcome::unexplained && o.best.hit) {
        const int spot = on_spot_edge(c.scene, ray.o, ray.o + to_double(o.best.t) * ray.d, band);
        if (spot >= 0) {
          out.kind = Outcome::explained;
          out.label = "spot_edge";
        }
      }
      char buf[256];
      std::snprintf(buf, sizeof buf, "pixel (%d, %d): %s rgba %.9g %.9g %.9g %.9g; %s rgba %.9g %.9g %.9g %.9g; error %.3g (tol %.3g); ",
                    x, y, s.info.name.c_str(), pa[0], pa[1], pa[2], pa[3], ref.info.name.c_str(), pb[0], pb[1], pb[2],
                    pb[3], err, s.tol.color_abs);
      out.detail = buf + ("primary " + hex(ray)) + "; " + oracle_text(o);
      bad.push_back(out);
    }
  }
  // Pixels not explained by the oracle count against the pair's pixel_fraction.
  const size_t allowed = size_t(std::floor((1.0 - s.tol.pixel_fraction) * double(total) + 1e-9));
  size_t unexplained = 0;
  for (const Outcome& o : bad) unexplained += o.kind == Outcome::unexplained;
  for (Outcome& o : bad) {
    if (o.kind == Outcome::unexplained && unexplained <= allowed) {
      o.kind = Outcome::explained;
      o.label = "pixel_fraction";
    }
  }
  Outcome summary;
  summary.label = "image";
  summary.detail = std::to_string(total - bad.size()) + "/" + std::to_string(total) + " pixels within " +
                   dec(s.tol.color_abs) + ", " + std::to_string(unexplained) + " unexplained (allowed " +
                   std::to_string(allowed) + ")";
  v.rays.push_back(summary);
  for (Outcome& o : bad) v.rays.push_back(o);
  return v;
}

Verdict run_check(const std::string& check, const Subject& s, const Case& c) {
  if (check == "accuracy") return check_accuracy(s, c);
  if (check == "agreement") return check_agreement(s, c);
  if (check == "stability") return check_stability(s, c);
  if (check == "watertight") return check_watertight(s, c);
  if (check == "degenerate") return check_degenerate(s, c);
  if (check == "render") return check_render(s, c);
  throw std::runtime_error("unknown check '" + check + "'");
}

}  // namespace lockstep::props
