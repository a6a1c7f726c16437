// lockstep registry: the marching-cubes family's row (a volume -> a mesh).
//
//   reference  reference/marching_cubes.cpp: the textbook method, cube by cube
//   simd       optimized/marching_cubes.cpp: each cut edge once, slabs on TBB
//
// Both read the volumes of io/volume_io.h (NRRD through Teem, analytic
// .field files) and take the iso value as a setting (iso=VALUE).
#pragma once

#include "core/family.h"

namespace lockstep {

Family marching_cubes_family();

}  // namespace lockstep
