// lockstep props: the checks, shared by the properties and the counterexample replay.
//
// Every check runs one implementation (taken from the pair table) on one Case
// and returns a Verdict: one Outcome per ray (or per pixel row, for renders).
//
//   ok           right: hit/miss as the oracle (or the reference), t within the bound
//   explained    wrong, and the oracle's conditioning predicts it (a classified failure):
//                  hit/miss differs only where the decision margin is within the band
//                  (kRobustBand or kTextbookBand ulps of the implementation's arithmetic),
//                  t error within bound * max(1, kappa / kWellKappa),
//                  labelled with the dominating cause (grazing, cancellation, ...)
//   unexplained  wrong where the oracle says it should be right: a bug (or a bound that is wrong)
//   skipped      not judged (accuracy/agreement only look at well-conditioned rays)
//
// Which implementations are "textbook": the reference (first in each pair) and
// every implementation whose name starts with the reference's (reference_f32).
// They are judged with the textbook conditioning (world coordinates plus the
// textbook formula's own cancellation); the others with the local conditioning
// (relative to the ray origin). The decisions' unit roundoff is the table's
// Impl::decide_eps, or else inferred from the implementation's accuracy bound:
// bounds looser than 1e-9 mean float (2^-24), tighter mean double (2^-53).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "pairs/ray_cast.h"
#include "props/ray_cast/case.h"
#include "props/ray_cast/oracle.h"
#include "props/verdict.h"

namespace lockstep::props {

enum class Mode { robust, textbook };

// Decision bands, in ulps of the implementation's arithmetic (stated in props/README.md).
inline constexpr double kRobustBand = 16;
inline constexpr double kTextbookBand = 64;

enum class Kernel { sphere, plane, polygon, frame };

struct ImplInfo {
  std::string pair;  // pair name in the table
  std::string name;  // implementation name
  double bound = 0;  // Impl::oracle_t_rel
  double eps = 0;    // unit roundoff, inferred from bound
  Mode mode = Mode::robust;
  bool is_reference = false;
  double agree_t_rel = 0;       // Impl::agree_t_rel (0 = the pair's tolerance)
  // t refined in a wider type than the decisions (Impl::decide_eps set): t is
  // judged in the frame the refinement computes in (sphere: centre-relative;
  // polygon: the world plane equation), decisions with eps.
  bool refined = false;
  // Impl::known_failure: this label is explained, never hidden, and its count per
  // ray of class known_per is capped at known_max_rate (props_main.cpp).
  std::string known_failure;
  double known_max_rate = 0;
  std::string known_per;
};

// The label a known failure is reported under ("known_embree_leak_vertex").
std::string known_label(const ImplInfo& im);
// Well-conditioned in the frame the implementation computes in: textbook
// implementations in world coordinates (oracle's world view), the others with
// the local decision margins and the kappa of the frame their t comes from.
bool well_in_frame(const OracleHit& o, const ImplInfo& im);
// Why a ray is not well-conditioned for this implementation ("" if it is).
std::string ill_why(const OracleHit& o, const ImplInfo& im);
// The most known failures a run may show: the largest count k with
// P(X >= k) >= 1e-6 for X ~ Binomial(n, max_rate), i.e. more than this is
// evidence (at 1e-6) that the true rate is over max_rate.
long known_failure_cap(long n, double max_rate);

// One implementation of one pair, callable on a Case.
struct Subject {
  ImplInfo info;
  Kernel kernel = Kernel::sphere;
  Tolerance tol;  // the pair's agreement tolerances
  // Kernels: t for every ray of the case (sphere/plane/polygon from the case;
  // polygon index given explicitly for watertightness unions).
  std::function<void(const Case&, uint32_t poly, std::span<double>)> run_kernel;
  TraceFn trace = nullptr;
  RenderFn render = nullptr;
};

// Thrown when an implementation is still a placeholder (std::logic_error("todo")).
struct Placeholder : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Every (pair, implementation) of the table.
std::vector<Subject> all_subjects();
const Subject* find_subject(const std::string& pair, const std::string& impl);
const Subject& reference_of(const std::string& pair);
// Throws Placeholder if the implementation is a placeholder.
void probe(const Subject& s);

// The checks. pair/impl come from the Subject; generator capabilities are the caller's business.
Verdict check_accuracy(const Subject& s, const Case& c);
Verdict check_agreement(const Subject& s, const Case& c);
Verdict check_stability(const Subject& s, const Case& c);
Verdict check_watertight(const Subject& s, const Case& c);
Verdict check_degenerate(const Subject& s, const Case& c);
Verdict check_render(const Subject& s, const Case& c);

// Dispatch by name (the counterexample files' "check" field).
Verdict run_check(const std::string& check, const Subject& s, const Case& c);

// The same case with only ray i (for small counterexample files).
Case with_ray(const Case& c, size_t i);

}  // namespace lockstep::props
