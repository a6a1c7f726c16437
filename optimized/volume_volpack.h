// lockstep optimized: the volume family's production peer, VolPack (Lacroute
// and Levoy, "Fast Volume Rendering Using a Shear-Warp Factorization of the
// Viewing Transformation", SIGGRAPH 1994; Debian libvolpack1-dev), built only
// where CMake finds it (LOCKSTEP_HAVE_VOLPACK). VolPack's header is included
// by optimized/volume_volpack_module.cpp alone, built as the module
// lockstep_peer_volpack.so and opened when the row runs
// (optimized/peer_module.h). See optimized/volume_volpack.cpp (the host side:
// quantization, tables, view) for what the row does and how it differs from
// the reference's ray casting.
#pragma once

#include <cstdint>
#include <string>

#include "core/family.h"
#include "core/image.h"
#include "core/volume.h"

namespace lockstep::opt::volpack {

// True when this build has the VolPack row (and its module is beside the
// binary); version() then names VolPack's version, as recorded beside the module.
bool available();
std::string version();

// The volume family's contract (core/volume_render.h, settings tf, view, eps;
// step is the reference's sampling step and does not apply: VolPack takes one
// sample per slice) drawn by VolPack's shear-warp from its classified
// run-length volume, one thread. FrameStats::build_seconds: the classification
// (vpClassifyVolume), done per call; FrameStats::items = pixels.
Image volume_raycast(const Volume& volume, const FrameOptions& options, FrameStats* stats);

// VolPack's three ways to draw the same frame, for the hand-run timing tool
// (bench/timing/volpack_timing.cpp): from the classified run-length volume (the
// row's), from the raw voxels classified on the fly, and the raw voxels with a
// min-max octree skipping transparent regions.
enum class Path { kClassified, kRaw, kRawOctree };
struct Times {
  double prepare = 0;   // quantization and tables (ours)
  double classify = 0;  // vpClassifyVolume (kClassified) or vpCreateMinMaxOctree (kRawOctree)
  double render = 0;    // vpRenderClassifiedVolume or vpRenderRawVolume
};
Image render_path(const Volume& volume, const FrameOptions& options, Path path, Times* times);

// The module's table (lockstep_peer_api() in lockstep_peer_volpack.so); abi must match kAbi.
struct Request {
  const uint16_t* voxels = nullptr;  // nx ny nz quantized values, x fastest
  int nx = 0, ny = 0, nz = 0;
  int qmax = 0;                    // largest value
  const float* opacity = nullptr;  // qmax + 1 classifier entries
  const float* colour = nullptr;   // (qmax + 1) x 3, 0..255
  double model[4][4] = {};     // voxel index -> VolPack's clip coordinates, its prematrix undone
  double max_ray_opacity = 1;  // VP_MAX_RAY_OPACITY
  int width = 0, height = 0;
  Path path = Path::kClassified;
};
struct ModuleApi {
  int abi;
  int max_volume_dim;  // VP_MAX_VOLUME_DIM
  // Draws into pixels (width x height x 4 bytes, VolPack's rows bottom-up);
  // classify and render: seconds of those phases. Throws std::runtime_error
  // naming the VolPack call that failed.
  void (*render)(const Request& request, unsigned char* pixels, double* classify, double* render);
};
inline constexpr int kAbi = 1;

}  // namespace lockstep::opt::volpack
