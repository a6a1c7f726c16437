// lockstep props/raster: back-face culling in world space against culling in
// projection space (core/viewing.cpp).
//
//   CullingAgree.zbuffer__reference   The same scene drawn with cull=world and
//       cull=projection: every sample shows the same triangle, except where a
//       triangle's two tests disagree -- the sign of N.(eye - v) in world space
//       against the sign of its snapped area on screen. That happens only for
//       faces seen (nearly) edge-on, and the outcome is labelled with who draws
//       the face there: "world_draws" (world space says front, the snapped
//       triangle is turned over or flat) or "projection_draws" (the reverse).
//       Any other difference is unexplained. Which wins: projection space
//       decides on what is actually rasterised, so it never draws a face that
//       snapping turned over; world space is exact for the plane but draws such
//       a face from its back (view_scene reorders it), a sliver of a pixel wide.
//
//   CullingAgree.zbuffer__simd, .zbuffer__llvmpipe   The same cases (in flat
//       shading) drawn by the implementation -- its own set-up and culling, the
//       image path -- under cull=world and cull=projection, each frame against
//       the reference's under the same mode, pixel for pixel (image_agree,
//       render_agree.cpp): coverage identical, colour within 1/255; another
//       triangle visible where two candidates' depths tie is `depth_tie`, per
//       pixel, capped (kCullingTie). llvmpipe draws view_scene's mesh (the
//       reference's culling) with its own raster: coverage only, its known
//       `coverage` failure capped as in LlvmpipeCoverage.
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "props/raster/parts.h"
#include "reference/raster.h"

namespace lockstep::props::raster {

namespace {

// World-space and snapped screen-space facing of scene triangle t (a front
// face has negative snapped area: y points down on screen).
struct Facing {
  bool world_front;
  int64_t snapped_area;
};

Facing facing(const Scene& scene, const Camera& cam, uint32_t tri) {
  const auto& t = scene.tri_vertex[tri];
  const uint32_t poly = scene.tri_poly[tri];
  Facing f;
  f.world_front = dot(scene.poly_plane[poly].n, cam.eye - scene.vertex[t[0]]) > 0;
  int64_t x[3], y[3];
  for (int k = 0; k < 3; ++k) {
    const Vec3 d = scene.vertex[t[k]] - cam.eye;
    const double ze = dot(d, cam.forward);
    x[k] = std::llround((0.5 * cam.width + dot(d, cam.right) / (ze * cam.pitch)) * kSubpixel);
    y[k] = std::llround((0.5 * cam.height - dot(d, cam.up) / (ze * cam.pitch)) * kSubpixel);
  }
  f.snapped_area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
  return f;
}

Verdict culling_agree(const RasterCase& c) {
  const auto scene = c.scene();
  RasterSettings world = raster_settings(c.params, "<case>"), proj = world;
  world.cull = CullMode::kWorld;
  proj.cull = CullMode::kProjection;
  const ScreenMesh mw = view_scene(*scene, c.width, c.height, world);
  const ScreenMesh mp = view_scene(*scene, c.width, c.height, proj);
  Visibility vw, vp;
  ref::zbuffer_visibility(mw, world, vw);
  ref::zbuffer_visibility(mp, proj, vp);
  // The scene triangle a sample shows (source_tri of a polygon), or -1.
  auto shown = [](const ScreenMesh& m, const Visibility& v, size_t k) -> long {
    return v.tri[k] == Visibility::kNone ? -1 : long(m.tris[v.tri[k]].source_tri);
  };
  Verdict verdict;
  for (size_t k = 0; k < vw.tri.size(); ++k) {
    const long a = shown(mw, vw, k), b = shown(mp, vp, k);
    Outcome o;
    if (a == b) {
      verdict.rays.push_back(o);
      continue;
    }
    // The triangle one mode draws here and the other does not draw at all: it
    // is culled by one test only. (The other may show a triangle behind it.)
    auto culled_by_other = [&](long t, const ScreenMesh& other) {
      for (const ScreenTri& st : other.tris)
        if (long(st.source_tri) == t) return false;
      return true;
    };
    std::string label;
    if (a >= 0 && culled_by_other(a, mp)) {
      const Facing f = facing(*scene, mw.camera, uint32_t(a));
      if (f.world_front && f.snapped_area >= 0) label = "world_draws";
    } else if (b >= 0 && culled_by_other(b, mw)) {
      const Facing f = facing(*scene, mp.camera, uint32_t(b));
      if (!f.world_front && f.snapped_area < 0) label = "projection_draws";
    }
    o.kind = label.empty() ? Outcome::unexplained : Outcome::explained;
    o.label = label.empty() ? "differs" : label;
    o.err = 1;
    std::ostringstream d;
    d << "sample " << k << " (pixel " << (k / vw.spp) % c.width << ", " << (k / vw.spp) / c.width
      << "): cull=world shows triangle " << a << ", cull=projection shows " << b;
    o.detail = d.str();
    verdict.rays.push_back(o);
  }
  return verdict;
}

// Another implementation: its frames under cull=world and cull=projection,
// each against the reference's under the same mode (image_agree: coverage
// identical, colour within color_abs, ties labelled). Culling decided any
// other way than the reference's -- e.g. projection space by the world-space
// sign -- draws or drops an edge-on sliver the reference does not.
Verdict culling_agree_impl(const FamilyImpl& impl, const FamilyImpl& reference, const RasterCase& c, double color_abs,
                           const KnownFailure& tie) {
  Verdict v;
  for (const char* mode : {"world", "projection"}) {
    RasterCase m = c;
    m.params.set("cull", mode);
    Verdict one = image_agree(impl, reference, m, color_abs, tie);
    for (Outcome& o : one.rays) {
      if (!o.detail.empty()) o.detail = std::string("cull=") + mode + ": " + o.detail;
      v.rays.push_back(std::move(o));
    }
  }
  return v;
}

// simd's ties between two triangles' float depths, per pixel (both culling
// modes' frames counted). Measured (deep mode, four seeds): 0 of 2.17M
// pixels; the cap is the 95% upper bound (3 / 1.4M, 2.1e-6) rounded up.
const KnownFailure kCullingTie{"depth_tie", 3e-6, "pixel"};
// llvmpipe's coverage on these cases: slivers whose vertices lie within a
// snapping step of pixel centres, where its float snap may turn them over or
// flat, and each owns a run of up to 8 samples. Measured (deep mode, three
// seeds): 336 of 726444, 287 of 697494, 387 of 698836 pixels, pooled 4.8e-4;
// the cap 7e-4 is that with a margin of 1.5 (the runs are clustered: the
// largest run measured 5.5e-4).
const KnownFailure kLlvmpipeCulling{"coverage", 7e-4, "pixel"};

}  // namespace

void culling_part(const Family& family, FamilyProperties& out) {
  const FamilyImpl& ref = family.reference();
  // Half the cases nearly edge-on, half arbitrary.
  out.properties.push_back(case_property(family, ref, "CullingAgree", "edge_on_or_soup",
                                         rc::gen::oneOf(edge_on_soup(), triangle_soup()), 0, "samples",
                                         culling_agree));
  // Every other implementation, in flat shading (what llvmpipe draws; each
  // triangle its own colour). llvmpipe: coverage only (its colours at edges
  // are its own, registry/raster_rows.cpp), its `coverage` known failure capped.
  for (const FamilyImpl& impl : family.impls) {
    if (&impl == &ref) continue;
    const bool peer = impl.known.label == "coverage";
    const double tol = peer ? kInfinity : family.tol.abs;
    const KnownFailure tie = peer ? kLlvmpipeCulling : kCullingTie;
    auto flat = [](RasterCase c) {
      c.params.set("shading", "flat");
      return c;
    };
    Property p = case_property(family, impl, "CullingAgree", "edge_on_or_soup",
                               rc::gen::map(rc::gen::oneOf(edge_on_soup(), triangle_soup()), flat), tol, "colour",
                               [&impl, &ref, tol, tie](const RasterCase& c) {
                                 return culling_agree_impl(impl, ref, c, tol, tie);
                               });
    p.known = tie;
    out.properties.push_back(std::move(p));
  }
}

}  // namespace lockstep::props::raster
