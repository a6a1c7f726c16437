// lockstep props/ray_cast: the ray-casting family's properties, for the driver.
//
// For every subject (every implementation of every typed row of registry/ray_cast_row.h):
//   Agreement.<row>__<impl>           non-reference implementations vs the reference, the row's generator
//   Accuracy.<row>__<impl>            every implementation vs the oracle, the row's generator
//   Render.<row>__<impl>              16x16 renders vs the reference (rows whose generator renders)
//   Stability.<gen>__<row>__<impl>    every stability generator that fits the subject
//   Watertight.<gen>__<row>__<impl>   closed meshes (polygon kernels and traces)
//   Degenerate.<gen>__<row>__<impl>   degenerate polygons (polygon kernels and traces)
#include <memory>

#include <gtest/gtest.h>

#include "props/property.h"
#include "props/ray_cast/case.h"
#include "props/ray_cast/checks.h"
#include "props/ray_cast/generators.h"
#include "props/ray_cast/subjects.h"

namespace lockstep::props::ray_cast {

namespace {

std::string generator_of(const std::string& pair) {
  const RayCastRows& t = ray_cast_rows();
  if (pair == t.ray_sphere.name) return std::string(t.ray_sphere.generator);
  if (pair == t.ray_plane.name) return std::string(t.ray_plane.generator);
  if (pair == t.ray_polygon.name) return std::string(t.ray_polygon.generator);
  if (pair == t.ray_cone.name) return std::string(t.ray_cone.generator);
  if (pair == t.ray_cast.name) return std::string(t.ray_cast.generator);
  return "";
}

unsigned kind_bit(Kernel k) {
  switch (k) {
    case Kernel::sphere: return kSphereKernel;
    case Kernel::plane: return kPlaneKernel;
    case Kernel::polygon: return kPolygonKernel;
    case Kernel::cone:
      return kConeKernel;
    default: return kTrace;
  }
}

// subject: shared by the subject's properties (with_session: one session each).
Property property(const std::string& suite, const std::string& check, const Named& g,
                  const std::shared_ptr<const Subject>& subject, bool name_generator) {
  const Subject& s = *subject;
  Property p;
  p.family = "ray_cast";
  p.check = check;
  p.suite = suite;
  p.generator = std::string(g.name);
  p.pair = s.info.pair;
  p.impl = s.info.name;
  p.name = (name_generator ? p.generator + "__" : "") + p.pair + "__" + p.impl;
  p.bound = s.info.bound;
  p.known = s.info.known;
  p.save_classified = s.info.mode == Mode::textbook && check != "render";
  p.accuracy_csv = check == "accuracy" || check == "stability" || check == "watertight";
  const Named* gen = &g;
  p.run = [subject, gen, check] {
    auto c = std::make_shared<const Case>(*gen->gen);
    Ran r;
    r.verdict = run_check(check, *subject, *c);
    r.text = [c](long unit) { return case_text(unit < 0 ? *c : with_ray(*c, size_t(unit))); };
    return r;
  };
  p.replay = [subject, check](const std::string& text, const std::string& file) {
    return run_check(check, *subject, read_case(text, file));
  };
  return p;
}

}  // namespace

FamilyProperties properties(const Family&, RunResources& run) {
  FamilyProperties out;
  auto& props = out.properties;
  for (const Subject& base : all_subjects()) {
    // The embree row's properties share one session, on the run's one device
    // (shared with the ray_trace embree row's properties).
    const auto subject = std::make_shared<const Subject>(with_session(base, run));
    const Subject& s = *subject;
    const Named* well = find_generator(generator_of(s.info.pair));
    if (!well) continue;  // the driver reports the row as untested: see below
    if (!s.info.is_reference) props.push_back(property("Agreement", "agreement", *well, subject, false));
    props.push_back(property("Accuracy", "accuracy", *well, subject, false));
    if (s.render && !s.info.is_reference && (well->kinds & kRender))
      props.push_back(property("Render", "render", *well, subject, false));
    for (const Named& g : generators()) {
      if (!g.stability) continue;
      if (g.kinds & kind_bit(s.kernel)) props.push_back(property("Stability", "stability", g, subject, true));
      if ((g.kinds & kWatertight) && s.answer_polygons)
        props.push_back(property("Watertight", "watertight", g, subject, true));
      if ((g.kinds & kDegenerate) && (s.kernel == Kernel::polygon || s.kernel == Kernel::frame))
        props.push_back(property("Degenerate", "degenerate", g, subject, true));
    }
  }
  // A row naming a generator this family does not have would go untested.
  for (const Subject& s : all_subjects())
    if (!find_generator(generator_of(s.info.pair))) {
      const std::string row = s.info.pair, gen = generator_of(row);
      out.fixed.push_back({"Registry", "ray_cast__" + row + "__" + s.info.name + "_has_a_generator", [row, gen] {
                             FAIL() << "row " << row << " names generator '" << gen
                                    << "', which props/ray_cast/generators.cpp does not have";
                           }});
    }
  return out;
}

}  // namespace lockstep::props::ray_cast
