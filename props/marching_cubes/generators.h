// lockstep props/marching_cubes: the named case generators, and the fixed
// cases of the fixed tests.
#pragma once

#include <rapidcheck.h>

#include "props/marching_cubes/case.h"

namespace lockstep::props::marching_cubes {

// Samples 0..8 (integers), iso k + 1/2; border: +1 all border samples 9 (above),
// -1 all 0 (below, iso >= 1/2), 0 anything.
// ties: iso values equal to samples too, and iso values no float equals with
// samples at the floats around them.
rc::Gen<McCase> field(int border, bool ties);
// Integer samples at an integer iso value that many of them equal (issue 30,
// section 4: CT data at an integer iso value): iso 2..6, the inner samples
// iso - 2 .. iso + 2 (a fifth equal to iso), or 0..8 in a quarter of the
// cases; the border 9 (above) or -1 (below), so the surface stays inside.
rc::Gen<McCase> ties_field(int border);

// One cube's configuration `bits` (bit v: corner v below) in a 4x4x4 grid whose
// other samples are above (or, complemented, below).
McCase single_cube(int bits, bool complement);
// A hand-made field where many samples equal the iso value 2 (integers 0..4,
// the border 0): a plateau of 2s (every cut point of its surface on a sample
// before the tie rule), a diamond |i - 10| + |j - 6| + |k - 6| <= 2 of values
// 4 - that distance (its shell equal to 2), and a patch of 1, 2, 3 mixed by
// (7 i + 3 j + 5 k) mod 3.
McCase hand_made_ties();

}  // namespace lockstep::props::marching_cubes
