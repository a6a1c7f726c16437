// lockstep props/ray_cast: each implementation judged in the frame it computes in.
//
//   ok           right: hit/miss and primitive as the oracle, t within the bound
//   explained    wrong, and the oracle's conditioning predicts it (a classified failure):
//                  hit/miss differs only where the decision margin is within the band
//                  (kRobustBand or kTextbookBand ulps of the implementation's arithmetic),
//                  t error within bound * max(1, kappa / kWellKappa),
//                  labelled with the dominating cause (grazing, cancellation, ...)
//   unexplained  wrong where the oracle says it should be right: a bug (or a bound that is wrong)
//
// Textbook implementations are judged with the textbook conditioning (world
// coordinates plus the textbook formula's own cancellation); the others with the
// local conditioning (relative to the ray origin); refined traces take t's
// conditioning from the frame the refinement computes in.
#pragma once

#include <string>

#include "props/ray_cast/oracle.h"
#include "props/ray_cast/subjects.h"
#include "props/verdict.h"

namespace lockstep::props::ray_cast {

// Decision bands, in ulps of the implementation's arithmetic (stated in props/README.md).
inline constexpr double kRobustBand = 16;
inline constexpr double kTextbookBand = 64;

// The conditioning of the decisions as the implementation sees them.
const Conditioning& view_of(const OracleHit& o, Mode m);
// The decision band: kRobustBand or kTextbookBand ulps of the decisions' arithmetic.
double band_of(const ImplInfo& im);
// The conditioning of t in the frame the implementation computes t in.
const Conditioning& t_view(const OracleHit& o, const ImplInfo& im);

// Well-conditioned in the frame the implementation computes in: textbook
// implementations in world coordinates (oracle's world view), the others with
// the local decision margins and the kappa of the frame their t comes from.
bool well_in_frame(const OracleHit& o, const ImplInfo& im);
// Why a ray is not well-conditioned for this implementation ("" if it is).
std::string ill_why(const OracleHit& o, const ImplInfo& im);

// One answer (hit/miss, primitive, t) against the oracle, classified by the
// conditioning (Outcome::detail is left to the caller).
Outcome judge(const OracleTrace& o, const Hit& h, const ImplInfo& im);

}  // namespace lockstep::props::ray_cast
