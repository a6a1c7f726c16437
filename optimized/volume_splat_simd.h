// lockstep optimized: splatting with footprint tables, SIMD accumulation over
// the footprint's pixel rows and TBB image tiles (optimized/volume_splat_simd.cpp;
// the contract: core/volume_render.h, the reference: reference/volume_splat.cpp).
#pragma once

#include "core/family.h"
#include "core/image.h"
#include "core/volume.h"

namespace lockstep::opt::simd {

// The reference's image within a stated bound (registry/volume_rows.cpp splat_family):
// the same voxels in the same depth order and sheets, the same footprint
// cut-off pixel for pixel (decided in double by the reference's expression),
// the Gaussian looked up in tables instead of exp, accumulated and composited
// in float. No one-shot cost: FrameStats::build_seconds is 0.
Image volume_splat(const Volume& volume, const FrameOptions& options, FrameStats* stats);

}  // namespace lockstep::opt::simd
