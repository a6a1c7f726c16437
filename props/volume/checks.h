// lockstep props/volume: the checks, each rendering one case with an
// implementation of the family and comparing images pixel by pixel (one
// Outcome per pixel: the largest channel difference).
#pragma once

#include "core/family.h"
#include "props/verdict.h"
#include "props/volume/case.h"

namespace lockstep::props::volume {

// Mirror: the largest channel difference between an image and its mirrored
// counterpart. Measured: the reference 0 (its double rays mirror exactly on
// every case drawn), simd 2.9e-4 over 5 x 2000 cases (two float renders, each
// within the family's 6e-4 of the double one): 6e-4, 2x.
inline constexpr double kMirrorTol = 6e-4;

// Agreement: impl's image against the reference's, within the family's tolerance.
Verdict agreement(const Family& family, const FamilyImpl& ref, const FamilyImpl& impl,
                  const VrCase& c);
// SkipChangesNothing: noskip against skip, and eps = 0 against the case's eps.
Verdict skip_changes_nothing(const Family& family, const FamilyImpl& impl, const VrCase& c);
// TransparentGivesBackground: every pixel exactly (0, 0, 0, 0).
Verdict transparent(const Family& family, const FamilyImpl& impl, const VrCase& c);
// Mirror: the mirrored volume seen from the mirrored view gives the mirrored image.
Verdict mirror(const Family& family, const FamilyImpl& impl, const VrCase& c);

}  // namespace lockstep::props::volume
