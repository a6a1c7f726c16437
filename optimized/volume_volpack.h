// lockstep optimized: the volume family's production peer, VolPack (Lacroute
// and Levoy, "Fast Volume Rendering Using a Shear-Warp Factorization of the
// Viewing Transformation", SIGGRAPH 1994; Debian libvolpack1-dev), built only
// where CMake finds it (LOCKSTEP_HAVE_VOLPACK). VolPack's header is included
// by optimized/volume_volpack.cpp alone. See that file for what the row does
// and how it differs from the reference's ray casting.
#pragma once

#include <string>

#include "core/family.h"
#include "core/image.h"
#include "core/volume.h"

namespace lockstep::opt::volpack {

// True when this build has the VolPack row; version() then names VolPack's version.
bool available();
std::string version();

// The volume family's contract (core/volume_render.h, settings tf, view, eps;
// step is the reference's sampling step and does not apply: VolPack takes one
// sample per slice) drawn by VolPack's shear-warp from its classified
// run-length volume, one thread. FrameStats::build_seconds: the classification
// (vpClassifyVolume), done per call; FrameStats::items = pixels.
Image volume_raycast(const Volume& volume, const FrameOptions& options, FrameStats* stats);

// VolPack's three ways to draw the same frame, for the hand-run timing tool
// (tools/volpack_timing.cpp): from the classified run-length volume (the
// row's), from the raw voxels classified on the fly, and the raw voxels with a
// min-max octree skipping transparent regions.
enum class Path { kClassified, kRaw, kRawOctree };
struct Times {
  double prepare = 0;   // quantization and tables (ours)
  double classify = 0;  // vpClassifyVolume (kClassified) or vpCreateMinMaxOctree (kRawOctree)
  double render = 0;    // vpRenderClassifiedVolume or vpRenderRawVolume
};
Image render_path(const Volume& volume, const FrameOptions& options, Path path, Times* times);

}  // namespace lockstep::opt::volpack
