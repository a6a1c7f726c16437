// lockstep props/composite: the exact oracle of the compositing family.
//
// Every input value is an exact rational: a float as it is, an 8-bit level q
// as q/255. The oracle converts straight layers to premultiplied exactly
// (C*a), composites them with `over` exactly (CGAL::Gmpq, no rounding
// anywhere), both front-to-back and back-to-front and in every two-way
// grouping, and checks those agree exactly (associativity of premultiplied
// over: a self-check of the oracle, reported per pixel). Results leave the
// oracle rounded once, to long double (64-bit mantissa): 2^40 times finer than
// a float ulp and 2^56 times finer than an 8-bit level, so the errors the
// checks measure are exact to far more digits than any bound needs.
//
// Units: for float stacks, values; for unorm8 stacks, 8-bit LEVELS (value*255).
//
// Float errors are measured in ulps of float (err_ulps) relative to
//   max(|exact|, floor, 2^-126)
// where floor is "the largest term", in one of two forms:
//   floor    max over layers k of the layer's premultiplied channel C_k, unweighted.
//            For front-to-back: an implementation computes T = 1 - A from an
//            accumulated alpha A, which carries an ABSOLUTE error of about
//            k 2^-24 after k layers, and that error multiplies the colour behind
//            (a nearly opaque front over an HDR back layer: the error is then
//            what the hidden layer could add, a few ulps of ITS value, not of the
//            result's).
//   floor_w  max over k of T_k C_k, T_k the exact transmittance in front of k.
//            For back-to-front: R = L + (1 - a) R has only non-negative terms and
//            1 - a of an INPUT alpha, so rounding is relative to the terms.
// 2^-126 (FLT_MIN) is the floor of all floats: below it the spacing is 2^-149
// whatever the value, so one "ulp" there is 2^-149.
#pragma once

#include <array>
#include <cstdint>

#include "props/composite/stack_case.h"

namespace lockstep::props::composite {

using LD = long double;
using LD4 = std::array<LD, 4>;

inline constexpr double kU = 0x1p-24;  // unit roundoff of float

// Everything the checks need to know about one pixel of a case, computed exactly.
struct PixelTruth {
  LD4 value{};            // exact composite of every layer (premultiplied; alpha in [3])
  LD4 floor{};            // the largest term, unweighted (front-to-back), per channel (see above)
  LD4 floor_w{};          // the largest term weighted by its exact transmittance (back-to-front)
  LD4 floor_visible{};    // floor over layers 0..stop only (front-to-back)
  LD4 floor_visible_w{};  // floor_w over layers 0..stop only (back-to-front)
  LD4 hidden_max{};  // what the layers behind the stop could add: sum_{k>stop} (T_k + s_k) C_k,
                     // s_k the possible error of a computed transmittance after k layers
                     // (float: 2k 2^-24; 8 bits: k/2 levels / 255)
  int stop =
      -1;  // first layer at which the exact accumulated alpha >= 1 - eps (last layer if none)
  LD4 visible{};                 // exact composite of layers 0..stop (what an early stop shows)
  LD4 hidden{};                  // value - visible: what the layers behind the stop add (>= 0)
  LD alpha_stop = 0;             // exact accumulated alpha of layers 0..stop (levels for unorm8)
  std::array<LD, 3> straight{};  // exact straight colour value/alpha (alpha > 0; else 0)
  bool all_alpha_zero = false;   // every layer's alpha is exactly 0
  bool exact_agree = true;       // ftb == btf == every grouping ((0..j) over (j+1..)), exactly
};

// The truth for pixel px of case c; eps in the case's units of alpha (levels for unorm8).
// groupings: also composite every two-way grouping exactly (O(N^2); sets exact_agree).
PixelTruth truth(const StackCase& c, int px, double eps, bool groupings = false);
// Straight layers add |c| 2^-126 to both floors: the straight formula weighs a
// straight colour c by a product of alphas that may underflow (absolute error
// 2^-150), so its error is c 2^-150 whatever the layer's alpha.
//
// The floor that fits an order (floor for front-to-back, floor_w for back-to-front).
inline const LD4& floor_for(const PixelTruth& t, Order o) {
  return o == Order::front_to_back ? t.floor : t.floor_w;
}
inline const LD4& floor_visible_for(const PixelTruth& t, Order o) {
  return o == Order::front_to_back ? t.floor_visible : t.floor_visible_w;
}

// The loss of the reference's straight accumulator at pixel px: simulated
// exactly, in the reference's order. ref::composite composites a stack of
// straight layers only with the straight formula, and every other stack
// premultiplied (so mixed stacks have no straight accumulator and no loss). Returns "" when none, else the label:
//   additive_at_alpha0   alpha 0 with colour != 0 (premultiplied "emission"): straight
//                        cannot hold it; the colour is dropped (kStraightClear)
//   straight_overflow    |C / alpha| > FLT_MAX: the straight colour is not a float
//   subnormal_alpha      0 < alpha < 2^-102 and C != 0: C / alpha from an alpha with
//                        fewer than 24 significant bits
const char* reference_straight_loss(const StackCase& c, int px);

// ---- kernels, exactly (float inputs, RGBA in [0..3]); straight over: alpha 0 -> (0,0,0,0)
LD4 exact_over_premultiplied(const float* f, const float* b);
LD4 exact_over_straight(const float* f, const float* b);
LD4 exact_premultiply(const float* s);
// (a over b) over c and a over (b over c) are equal in exact arithmetic (asserted) and their value.
bool exact_associative(const float* a, const float* b, const float* c, LD4* value);

// ---- 8 bits, exactly (integer arithmetic: every quantity is a rational with denominator 255 or a)
// x*a/255 in levels, exactly as a rational rounded to long double; and its nearest integer.
// (No ties exist: 2xa is even, 255(2k+1) is odd.)
LD exact_mul255(int x, int a);
int nearest_mul255(int x, int a);
// Whether got is a nearest integer to p*255/a (a > 0; either one on an exact tie).
bool is_nearest_unpremultiply8(int p, int a, int got);
// The derived loss bound of the 8-bit premultiply round trip: c -> p = round(c a/255)
// -> c' = round(p 255/a):  |c' - c| <= 1/2 + (255/a)(1/2)  and, c' - c being an integer,
// |c' - c| <= floor(1/2 + 127.5/a). a = 0 has no colour (bound 255, stated colour 0).
int round_trip8_bound(int a);

// ---- measuring
// Spacing of floats at |x| (2^-149 below FLT_MIN).
LD ulp32(LD x);
// |got - exact| / ulp32(max(|exact|, floor, 2^-126)); +inf when got is not finite.
double err_ulps(float got, LD exact, LD floor);

}  // namespace lockstep::props::composite
