// lockstep props/composite: the properties of the compositing family, one check each.
//
// A check runs one implementation (a CompositeSubject) on one StackCase and
// judges every pixel against the exact oracle (oracle.h), returning one Outcome
// per pixel (props/verdict.h): ok, explained (a loss the representation really
// has, classified and labelled: never skipped), or unexplained (a bug, or a
// wrong bound). Outcome::err is the pixel's largest error in the check's unit:
// ulps of float (oracle.h: err_ulps) for float stacks, 8-bit levels for unorm8
// stacks. Outcome::detail names the input (hexfloats / levels), every output,
// the oracle's value, the error and the bound.
//
// The checks do not know the test driver: props/composite/properties.cpp wraps
// them as properties of the generic driver (props/driver/).
//
// ---- stated bounds (derivations in README.md)
//  float, vs the oracle (accuracy): float_bound(s, N) = 1/2 + float_ulps (N - 1) ulps of
//        max(|exact|, largest term, 2^-126); largest term = floor (ftb) or floor_w (btf).
//        Premultiplied over f + (1 - a) b rounds 1 - a, the product and the sum, each
//        within 1/2 ulp of the largest term: 1.5 ulps per over (simd, oiio). The
//        reference's straight formula rounds two products, a sum and a division per
//        over, and converts between representations: 3 ulps per over.
//  8 bits, vs the oracle (accuracy): bound8() levels, derived per pixel:
//        back-to-front  sum_k T_k (r_k + d_k),  r_k = 1/2 for every over (k < N-1),
//                       d_k = 1/2 for the colour of a straight layer (premultiply8);
//        front-to-back  sum_{k>=1} (1/2 + e_{k-1} c_k/255) + sum_k T_k d_k, where
//                       e_k = e_{k-1} (1 - a_k/255) + 1/2 bounds the accumulated
//                       alpha's error (alpha channel: e_{N-1});
//        T_k the exact transmittance (levels/255) in front of layer k, c_k its
//        exact premultiplied colour level.
//  agreement with the reference: float float_bound(s, N) + float_bound(reference, N)
//        (the same scale); 8 bits subject.levels8.
//  straight vs premultiplied: each within its accuracy bound (the premultiplied
//        stack +1 ulp for the float premultiply); after unpremultiplying,
//        |s - s*| <= 255 (B_c + s* B_a / 255) / a_out + 1/2 levels (8 bits),
//        (dC + s* da) / a_out (float); ok when within 1 level / 4 accuracy bounds of
//        s*, explained (premul8_loss_*, small_alpha) between that and the bound.
//  ftb == btf: |ftb - btf| <= the two accuracy bounds added; exact in the oracle.
//  associativity: grouped stacks within 3 float_bound(s, N) / the two 8-bit bounds
//        added of the oracle; ref::over_premultiplied triples within kAssocUlps
//        of each other, exactly equal in the oracle.
//  early stop: on == off bit for bit; |out - full| <= b ulps of the visible
//        result + H, H the exact contribution of the layers behind the first
//        layer where the exact alpha >= 1 - eps, eps = 2N 2^-24 (float) or
//        (N-1)/2 levels (8 bits): H <= eps * (sum of the hidden colours).
//  straight alpha 0: no NaN or inf anywhere; an all-straight pixel whose every
//        alpha is 0 is exactly (0, 0, 0, 0) (ref::kStraightClear, premultiplied);
//        ref::over_straight / unpremultiply / unpremultiply8 give kStraightClear.
//  8-bit round trip: p = premultiply8(c, a) correctly rounded; c' =
//        unpremultiply8(p) correctly rounded; |c' - c| <= floor(1/2 + 127.5/a).
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "core/family.h"
#include "io/layers.h"
#include "props/composite/stack_case.h"
#include "props/verdict.h"

namespace lockstep::props::composite {

struct CompositeSubject {
  std::string name;
  std::function<Image(const LayerStack&, const FrameOptions&, FrameStats*)> fn;
  double float_ulps;  // per over, vs the oracle: float_bound() = 1/2 + float_ulps (N - 1) ulps
                      // of max(|exact|, largest term, 2^-126) for N layers
  int levels8;        // 8 bits, vs the reference (levels)
  bool is_reference;
};

// The subjects of the registry's composite family (registry/composite_row.cpp), the
// reference first: name and entry point from the row, float_ulps = the row's
// FamilyImpl::accuracy (float ulps per over), levels8 = the family's agreement
// tolerance in whole levels (0 for the reference itself).
std::vector<CompositeSubject> subjects_of(const Family& family);
// subjects_of(the registry's "composite"), built once.
const std::vector<CompositeSubject>& composite_subjects();

// ref::over_premultiplied: (a over b) over c vs a over (b over c), ulps of
// max(|exact|, largest input channel, 2^-126): each grouping is within 3 of the
// exact value (1 - a, the product and the sum rounded: 3u per over, relative to
// the largest term), so they are within 6 of each other.
inline constexpr double kAssocUlps = 6;

// The float bound of a subject on a stack of `layers` layers (ulps, see above):
// 1/2 for the first layer (a straight layer's premultiply), float_ulps per over.
inline double float_bound(const CompositeSubject& s, size_t layers) {
  return 0.5 + s.float_ulps * double(layers > 0 ? layers - 1 : 0);
}

// The derived 8-bit bound (levels) of channel ch of pixel px against the oracle.
double bound8(const StackCase& c, int px, int ch);

using CheckFn = Verdict (*)(const CompositeSubject& s, const StackCase& c);

Verdict check_accuracy(const CompositeSubject& s, const StackCase& c);
Verdict check_agreement(const CompositeSubject& s, const StackCase& c);
Verdict check_straight_vs_premultiplied(const CompositeSubject& s, const StackCase& c);
Verdict check_ftb_equals_btf(const CompositeSubject& s, const StackCase& c);
Verdict check_associativity(const CompositeSubject& s, const StackCase& c);
Verdict check_early_stop(const CompositeSubject& s, const StackCase& c);
Verdict check_straight_clear(const CompositeSubject& s, const StackCase& c);
Verdict check_round_trip8(const CompositeSubject& s, const StackCase& c);

struct NamedCheck {
  std::string_view name;
  CheckFn fn;
  std::vector<std::string_view> generators;  // composite::generators() names it runs on
  bool needs_reference_peer;                 // only for non-reference subjects (agreement)
};
std::vector<NamedCheck> composite_checks();

}  // namespace lockstep::props::composite
