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

}  // namespace lockstep::opt::volpack
