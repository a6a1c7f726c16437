// lockstep props/composite: deliberately broken compositors, to show that the
// checks can fail (properties.cpp: Mutants.composite__<bug> must be caught).
//
// Each is a local copy of the textbook premultiplied path (straight layers
// premultiplied first, then over, front-to-back with early stop or
// back-to-front; 8 bits with exact mul255) with one bug put in.
#pragma once

#include <string_view>
#include <vector>

#include "props/composite/checks.h"

namespace lockstep::props::composite {

struct Mutant {
  std::string_view bug;
  std::string_view what;
  std::string_view caught_by;  // the check that must catch it
  CompositeSubject subject;
};

std::vector<Mutant> mutants();

}  // namespace lockstep::props::composite
