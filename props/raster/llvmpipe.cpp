// lockstep props/raster: the llvmpipe peer's coverage against the reference's.
//
//   LlvmpipeCoverage.zbuffer__llvmpipe   The same random triangle soup
//       (triangle_soup, drawn with shading=flat, which llvmpipe can draw) through
//       ref::zbuffer and opt::llvmpipe::zbuffer: one outcome per pixel, ok when
//       both cover it or neither does. A pixel covered by one only is the row's
//       known failure (pairs/raster.cpp: `coverage`, per pixel): llvmpipe
//       transforms the vertices in float and snaps them itself (8 subpixel bits,
//       as view_scene), so a pixel centre within a snapping step of a silhouette
//       edge may fall on the other side; and its fill rule decides centres that
//       lie exactly on an edge. The driver fails the run when such pixels are
//       more than the row's stated rate (a binomial test at 1e-6; 3e-5 per
//       pixel, measured 1.48e-5), and a run long enough to tell whose rate is
//       below a quarter of it (the cap would hide a regression).
//
// Only coverage is judged here. Depth and colour agreement on the SPD scenes is
// measured by tools/llvmpipe_check.cpp and written in the row's comment.
#include <cmath>
#include <sstream>

#include "props/raster/parts.h"

namespace lockstep::props::raster {

namespace {

Verdict coverage_agree(const FamilyImpl& impl, const FamilyImpl& reference, const RasterCase& c) {
  const auto scene = c.scene();
  const Input in = make_input<Scene>(*scene, "<case>", c.width, c.height, scene->background);
  const FrameOptions o = c.options();
  FrameStats st;
  const Image r = reference.run_as<Image>(in, o, &st);
  const Image l = impl.run_as<Image>(in, o, &st);
  const std::string label = known_label(std::string(impl.name), impl.known);
  Verdict v;
  for (int j = 0; j < c.height; ++j)
    for (int i = 0; i < c.width; ++i) {
      const size_t k = size_t(j) * size_t(c.width) + size_t(i);
      const bool cr = std::isfinite(r.depth[k]), cl = std::isfinite(l.depth[k]);
      Outcome out;
      out.cls = std::string(impl.known.per);
      if (cr != cl) {
        out.kind = impl.known.label.empty() ? Outcome::unexplained : Outcome::explained;
        out.label = impl.known.label.empty() ? "coverage" : label;
        out.err = 1;
        std::ostringstream d;
        d << "pixel (" << i << ", " << j << "): reference " << (cr ? "covers" : "does not cover")
          << " it (depth " << r.depth[k] << "), " << impl.name << " "
          << (cl ? "covers" : "does not") << " (depth " << l.depth[k] << ")";
        out.detail = d.str();
      }
      v.rays.push_back(out);
    }
  return v;
}

// triangle_soup's scenes with the flat shading llvmpipe draws.
rc::Gen<RasterCase> flat_soup() {
  return rc::gen::map(triangle_soup(), [](RasterCase c) {
    c.params.set("shading", "flat");
    return c;
  });
}

}  // namespace

void llvmpipe_part(const Family& family, FamilyProperties& out) {
  const FamilyImpl& reference = family.reference();
  for (const FamilyImpl& impl : family.impls) {
    if (impl.name != "llvmpipe") continue;  // registered only where OSMesa was found
    Property p = case_property(
        family, impl, "LlvmpipeCoverage", "flat_soup", flat_soup(), impl.known.max_rate, "coverage",
        [&impl, &reference](const RasterCase& c) { return coverage_agree(impl, reference, c); });
    p.known = impl.known;
    out.properties.push_back(std::move(p));
  }
}

}  // namespace lockstep::props::raster
