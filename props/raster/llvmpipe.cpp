// lockstep props/raster: the llvmpipe peer's coverage against the reference's.
//
//   LlvmpipeCoverage.zbuffer__llvmpipe   The same random triangle soup
//       (triangle_soup, drawn with shading=flat, which llvmpipe can draw) through
//       ref::zbuffer and opt::llvmpipe::zbuffer: one outcome per pixel, ok when
//       both cover it or neither does. A pixel covered by one only is the row's
//       known failure (registry/raster_rows.cpp: `coverage`, per pixel): llvmpipe
//       transforms the vertices in float and snaps them itself (8 subpixel bits,
//       as view_scene), so a pixel centre within a snapping step of a silhouette
//       edge may fall on the other side; and its fill rule decides centres that
//       lie exactly on an edge. The driver fails the run when such pixels are
//       more than the row's stated rate (a binomial test at 1e-6; 3e-5 per
//       pixel, measured 1.48e-5), and a run long enough to tell whose rate is
//       below a quarter of it (the cap would hide a regression).
//   LlvmpipeCoverage.zbuffer__llvmpipe_cap_near_rate   The cap's other side,
//       in every run: that floor only bites on runs long enough to see the
//       rate (deep mode); CI's 100 cases hold under 100,000 pixels, where the
//       floor is 0 even for a cap ten times the rate. Here the same flat
//       soups (a fixed seed; 1,000,000 pixels, about 1,300 cases: some 15
//       disagreements at the measured 1.48e-5) are counted outside a property
//       run, and the measured rate times the stated margin kCapMargin = 4 (the
//       driver's kCapSlack) must reach the row's cap, both printed: a cap more
//       than 4 times the rate fails (the stated 3e-5 is the long runs' 1.48e-5
//       times 2).
//
// Only coverage is judged here. Depth and colour agreement on the SPD scenes is
// measured by bench/timing/llvmpipe_check.cpp and written in the row's comment.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
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

// The cap against a measured rate (header comment).
constexpr double kCapMargin = 4;        // the driver's kCapSlack: its floor, made to bite
constexpr long kCapPixels = 1'000'000;  // about 14 s
constexpr uint64_t kCapSeed = 0x11c0feeULL;

void cap_near_rate(const FamilyImpl& impl, const FamilyImpl& reference) {
  const rc::Gen<RasterCase> gen = flat_soup();
  rc::Random random(kCapSeed);
  long n = 0, k = 0, cases = 0;
  std::string first;
  while (n < kCapPixels) {
    const RasterCase c = gen(random.split(), rc::kNominalSize).value();
    const Verdict v = coverage_agree(impl, reference, c);
    for (const Outcome& o : v.rays) {
      ++n;
      if (o.kind == Outcome::ok) continue;
      if (++k == 1) first = o.detail;
    }
    ++cases;
  }
  const double rate = double(k) / double(n);
  const double cap = impl.known.max_rate;
  std::printf(
      "[ lockstep ] LlvmpipeCoverage cap: seed %llu, %ld cases, %ld of %ld pixels disagree: "
      "measured rate "
      "%.3g; stated cap %.3g = %.2f x the rate; margin %g: rate x margin %.3g %s the cap\n",
      (unsigned long long)kCapSeed, cases, k, n, rate, cap, rate > 0 ? cap / rate : 0.0, kCapMargin,
      rate * kCapMargin, rate * kCapMargin >= cap ? ">=" : "<");
  EXPECT_GE(rate * kCapMargin, cap)
      << impl.name << "'s coverage cap (registry/raster_rows.cpp, known failure '" << impl.known.label
      << "') is " << cap << " per pixel, but the measured rate is " << rate << " (" << k << " of "
      << n << " pixels, " << cases << " flat_soup cases, seed " << kCapSeed << "): more than "
      << kCapMargin
      << " times the rate, a cap that would hide a regression; first disagreement: " << first;
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
    out.fixed.push_back({"LlvmpipeCoverage", std::string(family.name) + "__llvmpipe_cap_near_rate",
                         [&impl, &reference] { cap_near_rate(impl, reference); }});
  }
}

}  // namespace lockstep::props::raster
