// lockstep props/ray_trace: the ray-tracing family's properties (core/ray_trace.h).
//
// Cases are small NFF scenes written by the generators with every number as a
// hex float, so a counterexample file (header, then `nff`, then the scene)
// replays bit for bit. The typed row of registry/ray_trace_row.h gives each
// implementation's frame and its one-pixel ray tree (TracePixelFn).
//
//   Laws.ray_trace__reference       (part "laws") reflect() and refract() of
//       core/ray_trace.h, the laws both implementations use, against an
//       oracle in long double from the same double inputs: unit length, the
//       mirror direction, Snell's law (eta |d x n| = |t x n|) and the TIR
//       decision (k = 1 - eta^2 (1 - (d.n)^2) < 0). Directions are drawn
//       anywhere and densely within 1e-12..1e-3 (relative) of the critical
//       angle; a TIR decision that differs from the oracle's is explained only
//       when |k| is below 1e-15 (k's own rounding), and the direction bound
//       1e-14 grows by 1e-15 eta^2 / sqrt(k) near the critical angle (k's
//       rounding through sqrt's conditioning).
//   Slab.ray_trace__<impl>          (part "slab") a glass slab (two parallel
//       transmitting quads of half-size 20, T = 1, Ks = 0, random ior,
//       thickness 1e-2..2, orientation,
//       view direction at up to 78 degrees from its normal): the ray leaving
//       the slab runs parallel to the primary ray, within 1e-13 (measured
//       1e-14 over 3000 cases).
//   Tir.ray_trace__<impl>           (part "tir") the eye inside a glass ball
//       (or under a glass plane) looks out at normal incidence or within
//       1e-12..1e-3 of the critical angle: the implementation's TIR decision
//       equals the reference's and the long-double oracle's, except within
//       the band where the hit normals' rounding (1e-12 relative in k) can
//       decide (explained: tir_critical).
//   Weights.ray_trace__<impl>       (part "weights") random scenes (spheres and
//       a transmitting triangle over a floor, Ks and T in [0, 1]): every ray
//       of the trees of 8 pixels has weight <= 1 and <= its parent's.
//   Hidden.ray_trace__<impl>        (part "hidden") objects behind an opaque
//       wall that covers the view (lights on the eye's side) change no pixel:
//       the frames with and without them are equal, bit for bit.
//   Pixel.ray_trace__<impl>         (part "pixel") the frame against the
//       one-pixel computation (TracePixelFn, whose ray tree `lockstep trace`
//       prints) on 16 pixels of random scenes (gen_scene): equal bit for bit.
//       The embree frame traces a tile breadth first in streams (rtcIntersect1M,
//       rtcOccluded1M: Embree's packet kernels), the pixel depth first one ray
//       at a time (rtcIntersect1): Embree's packet and single-ray sphere tests
//       round t differently (by an ulp, measured), which t's refinement in
//       double erases unless it changes which surface is nearest or whether a
//       sphere is hit at all. A pixel that differs is explained (float_tie)
//       only when its tree has a ray whose two nearest surfaces (the
//       reference's roots, in double) are within 1e-6 relative of each other,
//       or that passes a sphere's silhouette within float's rounding (the
//       band of Agree's diverge); anything else is unexplained.
//   Far.ray_trace__<impl>           (part "far") gen_scene's kind of scene,
//       opaque, at depth 1, scaled by 10^-2..10^2, moved 0 or 10^0..10^7 from
//       the origin and seen from 10^0..10^7 away (a telephoto view: the
//       angle narrowed to frame the same): every shadow ray of 16 pixels'
//       trees (the row's own offset, or robust=1) answers as an exact long
//       double segment test from the point the row shades; answers within
//       1e-3 of the scene's scale of a boundary are skipped (issue #30).
//   Agree.ray_trace__embree         (part "agree") the frame of every
//       non-reference row against the reference's on random scenes (16 x 16),
//       per pixel within the family's 1/255. A pixel over it has diverging
//       ray trees, and is classified:
//         offset_method  the reference traced with the implementation's
//                        offset method (robust) makes every decision the
//                        implementation makes: the two self-intersection
//                        offsets (fixed eps against robust) decide it;
//         diverge        (the row's known failure, capped per pixel) at the
//                        first node where the trees still differ, the
//                        reference replaying the implementation's own ray
//                        in double decides as the implementation did (the
//                        ray started elsewhere: an earlier bounce's float
//                        rounding), or that ray passes a sphere's silhouette
//                        within float's rounding (4 x 2^-24 |o - c|^2 / 2r:
//                        Embree decides the hit in float), or one tree has
//                        a shadow ray the other
//                        does not and that light is within 1e-4 (|n.l|) of
//                        the hit's tangent plane (n.l > 0 decided on hit
//                        points that differ by rounding);
//         tir_critical   TIR decided differently with |k| < 1e-9 (k from the
//                        reference's ray and normal); a TIR decision that
//                        the reference replays on the implementation's own
//                        incoming ray and normal is `diverge`;
//       anything else (the same ray answered otherwise, or the same
//       decisions with another colour) is unexplained.
#include <memory>
#include <string>

#include "props/property.h"
#include "props/ray_trace/case.h"
#include "props/ray_trace/checks.h"
#include "props/ray_trace/generators.h"
#include "registry/ray_trace_row.h"

namespace lockstep::props::ray_trace {

namespace {

// ---------------------------------------------------------------- properties
template <class Case>
Property property(const Family& f, std::string_view impl, std::string suite, std::string check,
                  std::string generator, rc::Gen<Case> gen, double bound,
                  std::function<Verdict(const Case&)> judge, std::string (*write)(const Case&),
                  Case (*read)(const std::string&, const std::string&),
                  std::string units = "pixels") {
  Property p;
  p.family = std::string(f.name);
  p.check = std::move(check);
  p.suite = std::move(suite);
  p.name = std::string(f.name) + "__" + std::string(impl);
  p.generator = std::move(generator);
  p.pair = "ray_trace";
  p.impl = std::string(impl);
  p.bound = bound;
  p.unit = "error";
  p.units = std::move(units);
  set_case_runner<Case>(p, std::move(gen), std::move(judge), write, read);
  return p;
}

}  // namespace

FamilyProperties properties(const Family& family, RunResources& run) {
  FamilyProperties out;
  const KernelRow<TracerFns>& row = ray_trace_row();
  // Each row's run, shared by its properties (the embree row: the process's
  // one device, also the ray_cast embree row's, released with the properties).
  const auto ref_run = std::make_shared<const TracerRun>(start_run(row.impls.front().fn, run));
  if (family.has_property("laws")) {
    Property p = property<LawCase>(family, "reference", "Laws", "laws", "directions", gen_laws(),
                                   1e-14, check_laws, write_law, read_law, "cases");
    p.unit = "direction error";
    out.properties.push_back(std::move(p));
  }
  for (const Impl<TracerFns>& impl : row.impls) {
    const auto fn_run =
        &impl == &row.impls.front() ? ref_run
                                    : std::make_shared<const TracerRun>(start_run(impl.fn, run));
    const std::string name(impl.name);
    if (family.has_property("slab"))
      out.properties.push_back(property<TraceCase>(
          family, impl.name, "Slab", "slab", "glass_slab", gen_slab(), 1e-13,
          [fn_run](const TraceCase& c) { return check_slab(*fn_run, c); }, write_case, read_case, "cases"));
    if (family.has_property("tir"))
      out.properties.push_back(property<TraceCase>(
          family, impl.name, "Tir", "tir", "critical_angle", gen_tir(), 0,
          [ref_run, fn_run](const TraceCase& c) { return check_tir(*ref_run, *fn_run, c); }, write_case, read_case,
          "cases"));
    if (family.has_property("weights"))
      out.properties.push_back(property<TraceCase>(
          family, impl.name, "Weights", "weights", "scenes", gen_scene(16), 1,
          [fn_run](const TraceCase& c) { return check_weights(*fn_run, c); }, write_case, read_case,
          "rays"));
    if (family.has_property("hidden"))
      out.properties.push_back(property<TraceCase>(
          family, impl.name, "Hidden", "hidden", "behind_wall", gen_hidden(), 0,
          [fn_run](const TraceCase& c) { return check_hidden(*fn_run, c); }, write_case, read_case));
    if (family.has_property("far"))
      out.properties.push_back(property<TraceCase>(
          family, impl.name, "Far", "far", "far_views", gen_far(), 0,
          [fn_run, textbook = &impl == &row.impls.front()](const TraceCase& c) {
            return check_far(*fn_run, c, textbook);
          },
          write_case, read_case, "shadow rays"));
    if (family.has_property("pixel"))
      out.properties.push_back(property<TraceCase>(
          family, impl.name, "Pixel", "pixel", "scenes", gen_scene(16), 0,
          [fn_run](const TraceCase& c) { return check_pixel(*fn_run, c); }, write_case, read_case));
    if (family.has_property("agree") && &impl != &row.impls.front()) {
      const std::string known = known_label(name, impl.known);
      Property p = property<TraceCase>(
          family, impl.name, "Agree", "agree", "scenes", gen_scene(16), family.tol.abs,
          [ref_run, fn_run, known](const TraceCase& c) { return check_agree(*ref_run, *fn_run, known, c); },
          write_case, read_case);
      p.known = impl.known;
      out.properties.push_back(std::move(p));
    }
  }
  return out;
}

}  // namespace lockstep::props::ray_trace
