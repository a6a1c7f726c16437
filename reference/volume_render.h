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
// "Model no more than a scene needs": the largest step (4, 2, 1, ... 1/8 voxel)
// whose image differs from the image at step 1/16 by at most `error` per
// channel on average, measured by this ray caster on a preview of at most
// 48 x 48 pixels of the same view (the mean error barely depends on the
// resolution: it is the same integral per ray). Returns the step and, in
// *measured, the preview's error at it (when even 1/8 is over, 1/8 and its error).
double step_for_error(const Volume& volume, const Params& params, int width, int height, double* measured);

// The isosurface of the trilinear interpolant: first crossing, refined, shaded.
Image volume_iso(const Volume& volume, const FrameOptions& options, FrameStats* stats);

}  // namespace lockstep::ref
