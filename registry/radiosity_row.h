// lockstep registry: the radiosity family's row (an NFF scene with emitters -> an image).
#pragma once

#include "core/family.h"

namespace lockstep {

// reference, simd (issue #33).
Family radiosity_family();

}  // namespace lockstep
