// lockstep optimized: marching cubes, each cut edge once, slabs over TBB
// threads (optimized/marching_cubes.cpp; the contract: core/marching_cubes.h).
#pragma once

#include "core/family.h"
#include "core/mesh.h"
#include "core/volume.h"

namespace lockstep::opt::simd {

// The reference's surface (reference/marching_cubes.h) as an indexed mesh:
// the same cut points (bit for bit) and triangles, each cut point stored once.
// FrameStats::items = cubes.
Mesh marching_cubes(const Volume& volume, const FrameOptions& options, FrameStats* stats);

}  // namespace lockstep::opt::simd
