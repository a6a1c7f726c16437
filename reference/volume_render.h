// lockstep reference: volume rendering, the textbook methods (core/volume_render.h
// holds the contract: settings, view, sampling, opacity correction, shading).
// Each takes the family's settings from FrameOptions::params, draws
// options.width x options.height premultiplied RGBA, single-threaded.
// FrameStats::items = pixels.
#pragma once

#include "core/family.h"
#include "core/image.h"
#include "core/volume.h"

namespace lockstep::ref {

// V-buffer ray casting: front-to-back compositing of classified samples.
Image volume_raycast(const Volume& volume, const FrameOptions& options, FrameStats* stats);
// Splatting: Gaussian footprints of classified voxels, composited in depth order.
Image volume_splat(const Volume& volume, const FrameOptions& options, FrameStats* stats);
// Its blob's standard deviation, in spacings, and the footprint's cut-off, in
// standard deviations (reference/volume_splat.cpp says why; the simd row
// draws the same footprints).
inline constexpr double kSplatSigma = 0.6;
inline constexpr double kSplatCutoff = 3.0;

// The isosurface of the trilinear interpolant: first crossing, refined, shaded.
Image volume_iso(const Volume& volume, const FrameOptions& options, FrameStats* stats);

}  // namespace lockstep::ref
