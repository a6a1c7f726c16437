// lockstep optimized: splatting with footprint tables, SIMD accumulation over
// the footprint's pixel rows and TBB image tiles (optimized/volume_splat_simd.cpp;
// the contract: core/volume_render.h, the reference: reference/volume_splat.cpp).
#pragma once

#include "core/family.h"
#include "core/image.h"
#include "core/volume.h"

namespace lockstep::opt::simd {

// Whether volume_splat draws this volume in this frame: fewer than 2^32
// voxels, a proper footprint covariance and a footprint at most 4096 pixels
// wide (a handful of voxels in a large frame is wider). The registry's simd
// row hands the rest to the reference (registry/volume_rows.cpp), and
// volume_splat throws std::invalid_argument for it.
bool volume_splat_handles(const Volume& volume, const FrameOptions& options);

// The reference's image within a stated bound (registry/volume_rows.cpp splat_family):
// the same voxels in the same depth order and sheets, the same footprint
// cut-off pixel for pixel (decided in double by the reference's expression),
// the Gaussian looked up in tables instead of exp, accumulated and composited
// in float. No one-shot cost: FrameStats::build_seconds is 0.
Image volume_splat(const Volume& volume, const FrameOptions& options, FrameStats* stats);

}  // namespace lockstep::opt::simd
