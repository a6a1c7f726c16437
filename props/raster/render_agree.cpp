// lockstep props/raster: an implementation's whole frame (its own set-up,
// culling, raster and shading) against the reference's, pixel for pixel.
//
//   RenderAgree.zbuffer__simd   random shaded scenes (shaded_soup: flat `p`
//       triangles, `pp` triangles and planar quads with curved vertex normals,
//       point, attenuated and spot lights; flat, Gouraud, Phong or Blinn
//       shading; one sample per pixel, float depth), rendered by the
//       implementation and by the reference. Per pixel: coverage identical
//       (the same snapped mesh and exact edge functions), colour within the
//       implementation's accuracy (1/255). Explained, and capped like a known
//       failure (kImageTie: measured rate plus margin, a binomial test):
//       another triangle visible where the two candidates' depths at the pixel
//       are within the depth format's tie band (`depth_tie`, the simd raster
//       computes depth in float). Also explained, uncapped: a pixel whose
//       shaded point lies within the float band of a spot light's cone edge
//       (`spot_edge`; inside and outside the cone differ by the whole light).
//
// image_agree() is also what CullingAgree judges a non-reference
// implementation with (culling.cpp).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/shading.h"
#include "props/raster/parts.h"
#include "props/raster/visibility.h"
#include "reference/raster.h"

namespace lockstep::props::raster {

namespace {

// The stored depth as the reference computes it: props/raster/visibility.h.
using vis::ref_depth;

// Whether mesh triangle t owns sample (px, py): the top-left rule on the exact
// edge functions (a ScreenTri has positive area).
bool owns(const ScreenMesh& m, uint32_t t, int64_t px, int64_t py) {
  const auto& v = m.tris[t].v;
  for (int e = 0; e < 3; ++e) {
    const auto& a = v[size_t((e + 1) % 3)];
    const auto& b = v[size_t((e + 2) % 3)];
    const int64_t E = int64_t(b.x - a.x) * (py - a.y) - int64_t(b.y - a.y) * (px - a.x);
    const bool top_left = (b.y == a.y && b.x > a.x) || b.y < a.y;
    if (!(E > 0 || (E == 0 && top_left))) return false;
  }
  return true;
}

// The tie band of the depth formats: twice CoverageAgreement's depth bound
// (3 float ulps of |d| + 16 |dd/dx|, one fixed24 code, 3 double ulps of the
// plane's terms), so that each of two candidates may be off by its bound.
bool tied(const ScreenMesh& m, const RasterSettings& s, uint32_t a, uint32_t b, int64_t px, int64_t py,
          double* gap_out) {
  const double da = ref_depth(m, s, a, px, py), db = ref_depth(m, s, b, px, py);
  double gap = std::abs(da - db);
  if (s.depth != DepthFormat::kFixed24) {
    double scale = 0;
    for (const uint32_t t : {a, b}) {
      const double d = ref_depth(m, s, t, px, py);
      const double gx = std::abs(ref_depth(m, s, t, px + kSubpixel, py) - d);
      const double gy = std::abs(ref_depth(m, s, t, px, py + kSubpixel) - d);
      double far = 16 * gx;
      if (s.depth == DepthFormat::kDouble)
        for (const auto& v : m.tris[t].v)
          far = std::max(far, (gx * std::abs(double(px - v.x)) + gy * std::abs(double(py - v.y))) / kSubpixel);
      scale = std::max(scale, std::abs(d) + far);
    }
    gap /= (s.depth == DepthFormat::kDouble ? 0x1p-52 : 0x1p-24) * scale;
  }
  *gap_out = gap;
  return gap <= 6;
}

// The world point of mesh triangle t at sample (px, py): perspective-correct barycentrics.
Vec3 world_point(const ScreenMesh& m, uint32_t t, int64_t px, int64_t py) {
  const auto& v = m.tris[t].v;
  double l[3], sum = 0;
  for (int e = 0; e < 3; ++e) {
    const auto& a = v[size_t((e + 1) % 3)];
    const auto& b = v[size_t((e + 2) % 3)];
    l[e] = double(int64_t(b.x - a.x) * (py - a.y) - int64_t(b.y - a.y) * (px - a.x)) / v[size_t(e)].z;
    sum += l[e];
  }
  Vec3 p{};
  for (int e = 0; e < 3; ++e) p += (l[e] / sum) * v[size_t(e)].world;
  return p;
}

// Whether point p is within the float band of a spot light's cone edge (the
// simd shader decides the cone in float: the cosine of the angle to the axis,
// against the cut-off's, each a few float ulps off, plus the point's own
// position error from float interpolation across the triangle).
bool near_spot_edge(const Scene& scene, const Vec3& p, const Vec3& eye) {
  for (const Light& l : scene.lights) {
    if (!l.spot) continue;
    const Vec3 d = p - l.position;
    const double dist = length(d);
    if (!(dist > 0)) return true;
    const double c = dot(d / dist, l.spot_dir), cut = spot_cos_cutoff(l);
    const double band = 64 * 0x1p-24 * (1 + (length(p - eye) + length(l.position - eye)) / dist);
    if (std::abs(c - cut) <= band) return true;
  }
  return false;
}

}  // namespace

Verdict image_agree(const FamilyImpl& impl, const FamilyImpl& reference, const RasterCase& c, double color_abs,
                    const KnownFailure& tie) {
  const auto scene = c.scene();
  const Input in = make_input<Scene>(*scene, "<case>", c.width, c.height, scene->background);
  const FrameOptions o = c.options();
  FrameStats st;
  const Image r = reference.run_as<Image>(in, o, &st);
  const Image g = impl.run_as<Image>(in, o, &st);
  const RasterSettings s = raster_settings(c.params, "<case>");
  const ScreenMesh mesh = lockstep::view_scene(*scene, c.width, c.height, s);
  Visibility vis;
  ref::zbuffer_visibility(mesh, s, vis);
  const auto off = sample_offsets(s);
  const int spp = int(off.size());
  const std::string coverage_label = impl.known.label == "coverage" ? known_label(std::string(impl.name), impl.known) : "";
  Verdict v;
  for (int j = 0; j < c.height; ++j)
    for (int i = 0; i < c.width; ++i) {
      const size_t k = size_t(j) * size_t(c.width) + size_t(i);
      const bool cr = std::isfinite(r.depth[k]), cg = std::isfinite(g.depth[k]);
      double diff = 0;
      for (int ch = 0; ch < 3; ++ch)
        diff = std::max(diff, std::abs(double(g.rgba[4 * k + size_t(ch)]) - double(r.rgba[4 * k + size_t(ch)])));
      Outcome out;
      out.cls = std::string(tie.per);
      std::ostringstream d;
      d << "pixel (" << i << ", " << j << "): " << impl.name << " rgb " << g.rgba[4 * k] << " " << g.rgba[4 * k + 1]
        << " " << g.rgba[4 * k + 2] << " depth " << g.depth[k] << "; reference rgb " << r.rgba[4 * k] << " "
        << r.rgba[4 * k + 1] << " " << r.rgba[4 * k + 2] << " depth " << r.depth[k] << "; colour error " << diff;
      if (cr != cg) {
        out.kind = coverage_label.empty() ? Outcome::unexplained : Outcome::explained;
        out.label = coverage_label.empty() ? "coverage" : coverage_label;
        out.err = kInfinity;
      } else if (!(diff <= color_abs)) {
        out.err = diff;
        // Which triangles own the pixel's samples, and whether the visible one
        // had a rival within the tie band; the oracle's own ownership test must
        // count what the reference counted.
        std::string label;
        for (int q = 0; q < spp && label != "oracle"; ++q) {
          const size_t at = k * size_t(spp) + size_t(q);
          const int64_t px = int64_t(i) * kSubpixel + off[size_t(q)][0], py = int64_t(j) * kSubpixel + off[size_t(q)][1];
          int count = 0;
          for (uint32_t t = 0; t < mesh.tris.size(); ++t) {
            if (!owns(mesh, t, px, py)) continue;
            ++count;
            double gap = 0;
            if (t != vis.tri[at] && vis.tri[at] != Visibility::kNone && tied(mesh, s, t, vis.tri[at], px, py, &gap)) {
              label = known_label(std::string(impl.name), tie);
              d << "; triangles " << vis.tri[at] << " and " << t << " tie at sample " << q << " (gap " << gap
                << " in the bound's units)";
            }
          }
          if (count != int(vis.count[at])) {
            label = "oracle";
            d << "; the check's ownership test counts " << count << " triangles, the reference " << vis.count[at];
          }
          if (label.empty() && vis.tri[at] != Visibility::kNone &&
              near_spot_edge(*scene, world_point(mesh, vis.tri[at], px, py), mesh.camera.eye)) {
            label = "spot_edge";
            d << "; the shaded point is within the float band of a spot cone's edge";
          }
        }
        out.kind = label.empty() || label == "oracle" ? Outcome::unexplained : Outcome::explained;
        out.label = label.empty() ? "colour" : label;
      }
      out.measured = cr && cg;
      if (out.measured && out.err == 0) out.err = diff;
      if (out.kind != Outcome::ok) out.detail = d.str();
      v.rays.push_back(std::move(out));
    }
  return v;
}

// A tie between two triangles' depths, per pixel. Measured (deep mode, three
// seeds): 0 of 1066645 pixels; the cap is the rate's 95% upper bound (3 /
// 1066645 = 2.8e-6) rounded up. The driver's floor (a factor 4) cannot bite
// at this rate: a run long enough to expect ties would.
const KnownFailure kImageTie{"depth_tie", 3e-6, "pixel"};

void render_agree_part(const Family& family, FamilyProperties& out) {
  const FamilyImpl& reference = family.reference();
  for (const FamilyImpl& impl : family.impls) {
    if (impl.name != "simd") continue;  // llvmpipe: flat and Gouraud only, its edges its own (LlvmpipeCoverage)
    const double tol = family.tol.abs;
    Property p = case_property(family, impl, "RenderAgree", "shaded_soup", shaded_soup(), tol, "colour",
                               [&impl, &reference, tol](const RasterCase& c) {
                                 return image_agree(impl, reference, c, tol, kImageTie);
                               });
    p.known = kImageTie;
    out.properties.push_back(std::move(p));
  }
}

}  // namespace lockstep::props::raster
