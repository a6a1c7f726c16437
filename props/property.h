// lockstep props: what a family hands to the generic property driver.
//
// A family's properties (props/<family>/) are values of one type-erased Property:
// one check, one generator, one implementation. The driver (props/driver/)
// registers each as its own GoogleTest test, runs it as a RapidCheck property with
// a seed fixed per property, tallies the outcomes, enforces known-failure caps,
// writes counterexample files (header by the driver, case text by the family) and
// replays them. A family never touches RapidCheck's internals: run() draws its case
// with the public `*gen` inside the property the driver runs.
//
// props/families.cpp maps each registry family to its provider; a registered
// family without one gets a failing Registry.<family>_has_properties test.
#pragma once

#include <functional>
#include <memory>
#include <string_view>
#include <string>
#include <vector>

#include <rapidcheck.h>

#include "core/family.h"
#include "props/verdict.h"

namespace lockstep::props {

// One generated case, checked.
struct Ran {
  Verdict verdict;
  // The case's text form (the body of a counterexample file, after the driver's
  // header); unit >= 0: only that unit (ray) of the case, for one-ray files of
  // classified failures (families that set Property::save_classified).
  std::function<std::string(long unit)> text;
};

struct Property {
  std::string family;     // registry family: "ray_cast"
  std::string check;      // "accuracy", "stability", "ftb_equals_btf" (counterexample files, table)
  std::string suite;      // GoogleTest suite: "Accuracy", "FtbEqualsBtf"
  std::string name;       // GoogleTest name: "ray_cast__simd", "grazing_rays__ray_sphere__reference"
  std::string generator;  // the generator's name
  std::string pair;       // the typed row the implementation belongs to: "ray_sphere", "composite"
  std::string impl;       // the implementation's name in that row
  double bound = 0;       // printed beside the measured error
  std::string unit = "relative t error";  // what Outcome::err measures (default unit of the outcomes)
  std::string units = "rays";             // what one Outcome judges, plural (summary lines)
  KnownFailure known;     // a documented failure: explained as known_<impl>_<label>, capped per `per` unit
  bool save_classified = false;  // LOCKSTEP_SAVE_CLASSIFIED applies (textbook implementations)
  bool accuracy_csv = false;     // rows in LOCKSTEP_ACCURACY_CSV
  // Draws one case (inside the driver's RapidCheck property) and checks it.
  std::function<Ran()> run;
  // Checks a case given in its text form (a counterexample file's body).
  std::function<Verdict(const std::string& text, const std::string& file)> replay;

  // The property's identity: its seed and its counterexample files' names
  // ("stability.grazing_rays.ray_sphere.reference").
  std::string id() const { return check + "." + generator + "." + pair + "." + impl; }
  std::string test_name() const { return suite + "." + name; }
};

// Fills p.run and p.replay for a family whose cases are values of type Case
// with a text form: run draws a case from gen and judges it (its counterexample
// text is write(case)); replay judges read(text, file).
template <class Case, class Write, class Read>
void set_case_runner(Property& p, rc::Gen<Case> gen, std::function<Verdict(const Case&)> judge, Write write,
                     Read read) {
  const auto g = std::make_shared<const rc::Gen<Case>>(std::move(gen));
  p.run = [g, judge, write] {
    auto c = std::make_shared<const Case>(**g);
    Ran r;
    r.verdict = judge(*c);
    r.text = [c, write](long) { return write(*c); };
    return r;
  };
  p.replay = [judge, read](const std::string& text, const std::string& file) { return judge(read(text, file)); };
}

// A property of one of family's rows whose cases are values of type Case with
// a text form: the names every family's properties share (the GoogleTest
// name family__impl, the pair the family), its unit and units, and
// set_case_runner's run and replay.
template <class Case, class Write, class Read>
Property case_property(const Family& family, const FamilyImpl& impl, std::string suite, std::string check,
                       std::string generator, std::string unit, std::string units, rc::Gen<Case> gen,
                       std::function<Verdict(const Case&)> judge, Write write, Read read) {
  Property p;
  p.family = std::string(family.name);
  p.check = std::move(check);
  p.suite = std::move(suite);
  p.name = std::string(family.name) + "__" + std::string(impl.name);
  p.generator = std::move(generator);
  p.pair = std::string(family.name);
  p.impl = std::string(impl.name);
  p.unit = std::move(unit);
  p.units = std::move(units);
  set_case_runner<Case>(p, std::move(gen), std::move(judge), write, read);
  return p;
}

// A plain test of the family that is not a random property (e.g. an exhaustive sweep).
struct FixedTest {
  std::string suite, name;
  std::function<void()> body;  // GoogleTest assertions
};

// A deliberately broken implementation: its properties must fail caught_by (a
// Property::check), or, with caught_by empty, pass every property.
struct Mutant {
  std::string name, what, caught_by;
  std::vector<Property> properties;
};

struct FamilyProperties {
  std::vector<Property> properties;
  std::vector<FixedTest> fixed;
  std::vector<Mutant> mutants;
};

// A family's property provider, given the family's registry row and the
// binary's run (core/run_resources.h): what its properties may share with
// other families' (the embree rows of ray_cast and ray_trace: one Embree
// device per process). The properties keep what they take from it.
using PropertyProvider = FamilyProperties (*)(const Family&, RunResources&);

struct ProviderRow {
  std::string_view family;
  PropertyProvider provide;
};
// props/families.cpp: one row per family with properties.
const std::vector<ProviderRow>& property_providers();

// The label a known failure is reported under ("known_embree_leak_vertex").
inline std::string known_label(const std::string& impl, const KnownFailure& k) {
  return "known_" + impl + "_" + std::string(k.label);
}

}  // namespace lockstep::props
