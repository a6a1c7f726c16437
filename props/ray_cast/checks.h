// lockstep props/ray_cast: the checks, shared by the properties and the counterexample replay.
//
// Every check runs one subject (subjects.h) on one Case and returns a Verdict:
// one Outcome per ray (or per differing pixel, for renders). Each is written once
// for every subject: kernels and traces answer with the same type, their oracles
// with the same trace type (conditioning.h classifies an answer).
//
//   accuracy    well-conditioned rays (in the implementation's frame): hit/miss, the
//               primitive (up to exact ties) and t within Impl::accuracy of the oracle
//   agreement   well-conditioned rays (for both): hit/miss, the primitive (up to
//               exact ties) and t within the row's tolerance of the reference
//   stability   every ray: ok, explained by the conditioning, or unexplained
//   watertight  closed meshes, rays through shared vertices, edges and faces: the
//               nearest hit over every polygon must be at the first contact, on a
//               polygon that contains it
//   degenerate  zero-area and degenerate polygons: never a hit on zero area, else as stability
//   render      16x16 frames vs the reference (subjects that render)
#pragma once

#include <string>

#include "props/ray_cast/case.h"
#include "props/ray_cast/subjects.h"
#include "props/verdict.h"

namespace lockstep::props::ray_cast {

Verdict check_accuracy(const Subject& s, const Case& c);
Verdict check_agreement(const Subject& s, const Case& c);
Verdict check_stability(const Subject& s, const Case& c);
Verdict check_watertight(const Subject& s, const Case& c);
Verdict check_degenerate(const Subject& s, const Case& c);
Verdict check_render(const Subject& s, const Case& c);

// Dispatch by name (Property::check, the counterexample files' "check" field).
Verdict run_check(const std::string& check, const Subject& s, const Case& c);

}  // namespace lockstep::props::ray_cast
