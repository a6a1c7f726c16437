// lockstep props: what a check says about one case, for every family.
//
// A check runs one implementation on one generated case and returns a Verdict:
// one Outcome per judged unit (a ray, a pixel, a pixel row):
//   ok           right within the implementation's bound
//   explained    wrong, and classified: the oracle's conditioning (or a known,
//                documented failure with a rate cap) predicts it; labelled with the cause
//   unexplained  wrong where the oracle says it should be right: a bug, or a wrong bound
//   skipped      not judged (e.g. accuracy only looks at well-conditioned input)
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace lockstep::props {

struct Outcome {
  enum Kind { ok, explained, unexplained, skipped } kind = ok;
  std::string label;   // cause: ok, grazing, cancellation, near_edge, leak_edge, nan, ...
  double err = 0;      // the error, in the property's unit (ray casting: relative error of t); inf: hit/miss differ
  bool measured = false;  // err is a measured error (both hit, both finite...): counted in max and p99
  std::string unit;    // err's unit when it is not the property's (Property::unit); groups the statistics
  std::string cls;     // the unit's class, for rates per class (watertight: vertex, edge, face rays); "" = none
  std::string detail;  // input as hexfloats, both outputs, the oracle, the error
};

struct Verdict {
  std::vector<Outcome> rays;
  size_t count(Outcome::Kind k) const {
    return size_t(std::count_if(rays.begin(), rays.end(), [k](const Outcome& o) { return o.kind == k; }));
  }
  bool passed() const { return count(Outcome::unexplained) == 0; }
  // The first unexplained outcome's detail (or "").
  std::string first_failure() const {
    for (const Outcome& o : rays)
      if (o.kind == Outcome::unexplained) return o.detail;
    return "";
  }
  // The index of the first outcome (any kind but ok/skipped) with the given label, or -1.
  int first_with_label(const std::string& label) const {
    for (size_t i = 0; i < rays.size(); ++i)
      if ((rays[i].kind == Outcome::explained || rays[i].kind == Outcome::unexplained) && rays[i].label == label)
        return int(i);
    return -1;
  }
};

}  // namespace lockstep::props
