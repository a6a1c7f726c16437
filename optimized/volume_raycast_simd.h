// lockstep optimized: volume ray casting and the interpolant's isosurface in
// float SIMD ray packets, with early ray termination and empty-space skipping
// over a min/max macro-cell grid (optimized/volume_raycast.cpp; the contract:
// core/volume_render.h, the references: reference/volume_raycast.cpp and
// reference/volume_iso.cpp).
#pragma once

#include "core/family.h"
#include "core/image.h"
#include "core/volume.h"

namespace lockstep::opt::simd {

// Whether the two below draw this volume: at least two samples on every axis
// (one cell). A slice or a line has no cell; the registry's simd rows hand
// such volumes to the reference (registry/volume_rows.cpp), and the two below
// throw std::invalid_argument for them.
bool volume_cast_handles(const Volume& volume);

// The reference's image (same rays, same samples k dt on the shared planes,
// same opacity correction, compositing order and termination rule), computed
// in float. FrameStats::build_seconds = the macro-cell grid's build and the
// transfer function's transparency table (one-shot costs, inside the run).
Image volume_raycast(const Volume& volume, const FrameOptions& options, FrameStats* stats);

// The reference's isosurface: the bracketing samples found in float SIMD, each
// decision within a margin of the iso value redone in double the reference's
// way (so the same bracket), then the reference's bisection and shading.
Image volume_iso(const Volume& volume, const FrameOptions& options, FrameStats* stats);

}  // namespace lockstep::opt::simd
