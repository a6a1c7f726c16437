// lockstep props/ray_cast: the implementation's frame, and the classification of
// an answer against the oracle's conditioning (see conditioning.h).
#include "props/ray_cast/conditioning.h"

#include <algorithm>
#include <cmath>

namespace lockstep::props::ray_cast {

namespace {

constexpr double kF64Eps = 0x1p-53;

// Judges the t of one primitive against the oracle with the implementation's conditioning view.
Outcome judge_t(const OracleHit& o, double t, const ImplInfo& im) {
  Outcome out;
  const Conditioning& c = view_of(o, im.mode);
  const double band = band_of(im);
  if (std::isnan(t)) {
    out.kind = Outcome::unexplained;
    out.label = "nan";
    out.err = kInfinity;
    return out;
  }
  const bool hit = t < kInfinity;
  if (hit != o.hit) {
    out.err = kInfinity;
    if (c.margin <= band) {
      out.kind = Outcome::explained;
      out.label = c.margin_why;
    } else {
      out.kind = Outcome::unexplained;
      out.label = hit ? "false_hit" : "false_miss";
    }
    return out;
  }
  if (!hit) return out;
  out.measured = true;
  out.err = rel_error(t, o.t);
  if (out.err <= im.bound) return out;
  // A refined implementation keeps its kernel's t where double sees no hit at all
  // (optimized/refine.h): only where that decision is within the band, and then
  // with as many ulps of the decisions' arithmetic as the bound has of double.
  // (Polygons: refine always recomputes t from the plane unless it is parallel.)
  const bool kernel_t = im.refined && o.root >= 0 && c.margin <= band;
  const Conditioning& tr = t_view(o, im);
  const double allowed_refined = im.bound * std::max(1.0, tr.kappa / kWellKappa);
  const double allowed_kernel = im.bound * (im.eps / kF64Eps) * std::max(1.0, o.local.kappa / kWellKappa);
  const bool use_kernel = kernel_t && allowed_kernel > allowed_refined;
  const Conditioning& tc = use_kernel ? o.local : tr;
  const double allowed = use_kernel ? allowed_kernel : allowed_refined;
  const std::string why = c.margin_why;
  if (out.err <= allowed) {
    out.kind = Outcome::explained;
    out.label = tc.kappa_why[0] ? tc.kappa_why : "ill_conditioned";
  } else if (o.root >= 0 && c.margin <= band &&
             (why == "near_tmin" || why == "near_tmax" || why == "near_rim")) {
    // A sphere root within the band of tmin/tmax, or a cone root within the band
    // of a rim (the end of the cone's finite part): the implementation may take
    // the other root. Nothing else excuses a t error: a polygon hit near an edge
    // has one t, and it must be within the bound.
    out.kind = Outcome::explained;
    out.label = c.margin_why;
  } else {
    out.kind = Outcome::unexplained;
    out.label = "t_error";
  }
  return out;
}

}  // namespace

const Conditioning& view_of(const OracleHit& o, Mode m) { return m == Mode::textbook ? o.textbook : o.local; }
double band_of(const ImplInfo& im) { return (im.mode == Mode::textbook ? kTextbookBand : kRobustBand) * im.eps; }

// The conditioning of t in the frame the implementation computes t in (a hit's
// OracleHit: root >= 0 for spheres). Textbook: world plus its own cancellation.
// Robust kernels: relative to the ray/primitive (local). Traces that refine in
// double: the sphere's stable form works relative to its centre (local), the
// polygon's plane equation n.o + d in world coordinates (world).
const Conditioning& t_view(const OracleHit& o, const ImplInfo& im) {
  if (im.mode == Mode::textbook) return o.textbook;
  if (im.refined && o.root < 0) return o.world;
  return o.local;
}

Outcome judge(const OracleTrace& o, const Hit& h, const ImplInfo& im) {
  Outcome out;
  const Conditioning& c = view_of(o.best, im.mode);
  const double band = band_of(im);
  if (std::isnan(h.t) || (h.hit() && h.prim >= o.per_prim.size())) {
    out.kind = Outcome::unexplained;
    out.label = std::isnan(h.t) ? "nan" : "bad_prim";
    out.err = kInfinity;
    return out;
  }
  if (h.hit() != o.best.hit) {
    out.err = kInfinity;
    if (c.margin <= band) {
      out.kind = Outcome::explained;
      out.label = c.margin_why;
    } else {
      out.kind = Outcome::unexplained;
      out.label = h.hit() ? "false_hit" : "false_miss";
    }
    return out;
  }
  if (!h.hit()) return out;
  const bool tied = std::find(o.tied.begin(), o.tied.end(), h.prim) != o.tied.end();
  if (!tied) {
    out.err = kInfinity;
    if (c.margin <= band) {
      out.kind = Outcome::explained;
      out.label = c.margin_why;
    } else {
      out.kind = Outcome::unexplained;
      out.label = "wrong_prim";
    }
    return out;
  }
  // t against the oracle's answer for the prim it chose: the same primitive has
  // one t (or, for a sphere root at tmin, two), whatever the other decisions' margins.
  return judge_t(o.per_prim[h.prim], h.t, im);
}

bool well_in_frame(const OracleHit& o, const ImplInfo& im) { return ill_why(o, im).empty(); }

std::string ill_why(const OracleHit& o, const ImplInfo& im) {
  if (im.mode == Mode::textbook) {
    if (well_conditioned(o)) return "";
    return o.world.margin < kWellMargin ? o.world.margin_why : o.world.kappa_why;
  }
  const Conditioning& tc = o.hit ? t_view(o, im) : o.local;
  if (o.local.margin < kWellMargin) return o.local.margin_why[0] ? o.local.margin_why : "margin";
  if (!(tc.kappa <= kWellKappa)) return tc.kappa_why[0] ? tc.kappa_why : "kappa";
  return "";
}

}  // namespace lockstep::props::ray_cast
