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
// Its blob: vr::kSplatSigma, vr::kSplatCutoff (core/volume_render.h).

// The isosurface of the trilinear interpolant: first crossing, refined, shaded.
Image volume_iso(const Volume& volume, const FrameOptions& options, FrameStats* stats);

}  // namespace lockstep::ref
