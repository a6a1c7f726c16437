// lockstep props/composite: named RapidCheck generators of StackCases.
//
// Built like props/gen: every number comes from integers that shrink
// meaningfully (props/gen/numbers.h: int_towards, int_in, chance), at full width
// whatever RapidCheck's size. Sizes shrink towards 1x1, layer counts towards 2,
// values towards 1/2 (alpha) and simple colours, and the "which special value"
// choices towards the ordinary value first, so that a shrunk counterexample
// keeps only the special values it needs.
//
//   general         float, 1..8 layers, alpha in [2^-10, 1], colours in [0, 1]
//                   (premultiplied layers C = float(c a)); each layer straight or
//                   premultiplied; ftb/btf; early_stop on/off
//   alpha_edges     float; alpha 0, 1, 2^-149 (one ulp from 0), 1 - 2^-24 (one ulp
//                   from 1), denormal, tiny normal; colours 0, 1, 1 - 2^-24, 2^-149,
//                   denormal, > 1 (up to 2^12; HDR premultiplied colour may exceed alpha)
//   general8        unorm8, levels uniform (premultiplied layers c <= a)
//   edges8          unorm8, levels 0, 1, 254, 255 and uniform
//   opaque_early    float or unorm8; some layer exactly opaque, or two front layers
//                   whose float accumulation rounds to alpha = 1 (1 - 2^-13, 1 - 2^-12:
//                   exact alpha 1 - 2^-25); HDR layers behind
//   nearly_opaque   float or unorm8; 1..3 front layers with alpha >= 1 - 64 2^-24
//                   (levels 254/255), HDR or bright layers behind
#pragma once

#include <rapidcheck.h>

#include <string_view>
#include <vector>

#include "props/composite/stack_case.h"

namespace lockstep::props::composite {

struct NamedGen {
  std::string_view name;
  std::string_view what;
  rc::Gen<StackCase> gen;
};

rc::Gen<StackCase> general();
rc::Gen<StackCase> alpha_edges();
rc::Gen<StackCase> general8();
rc::Gen<StackCase> edges8();
rc::Gen<StackCase> opaque_early();
rc::Gen<StackCase> nearly_opaque();

// Every generator above, by name (a new list each call: no globals).
std::vector<NamedGen> generators();
// One of the named generators (each equally likely); the case records which.
rc::Gen<StackCase> one_of(const std::vector<std::string_view>& names);

}  // namespace lockstep::props::composite
