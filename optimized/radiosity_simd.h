// lockstep optimized: radiosity (issue #33) on TBB threads, Embree's rays and
// the simd z-buffer's hemicubes; the contract of core/radiosity.h, the
// reference's steps (reference/radiosity.h) done fast:
//   rays      Lambert's factors from patch i's centre to 8 patches a vector
//             (optimized/radiosity_simd_kernels.h, double; patches reaching
//             behind the tangent plane by the reference's clipping code);
//             shaft culling by boxes (Haines and Wallace 1994): a pair whose
//             box of rays no other polygon's box enters casts none; the rest
//             of row i's segments in one Embree stream (rtcOccluded1M, float,
//             the scene's triangles, both sides); rows on TBB threads;
//   hemicube  each face through opt::simd's view_scene and z-buffer (one
//             thread each; the depth format the reference's, float, whose
//             ties the two z-buffers break alike), patches on TBB threads;
//   display   the patches through opt::simd's z-buffer, the shared display
//             step (core/radiosity.h radiosity_image).
// The solve is the shared one (core/radiosity.h solve_radiosity).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/family.h"
#include "core/image.h"
#include "core/radiosity.h"
#include "core/scene.h"
#include "optimized/embree_scene.h"

namespace lockstep::opt::simd {

// What the rays method did: segments cast, patch pairs the shaft test
// spared, and the seconds its Embree BVH of the scene took to build.
struct RayCounts {
  uint64_t rays = 0, culled_pairs = 0;
  double build_seconds = 0;
};
FormFactors radiosity_form_factors_rays(const Scene& scene, const PatchMesh& mesh, int k, int threads,
                                                const embree::Device& device,
                                                const std::function<void(double)>& progress = {},
                                                RayCounts* counts = nullptr,
                                                FormFactorMethod method = FormFactorMethod::rays);
FormFactors radiosity_form_factors_hemicube(const PatchMesh& mesh, int res, int threads,
                                                    const std::function<void(double)>& progress = {});

Image radiosity(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
// The same on a device the caller keeps (a session's, registry/radiosity_row.cpp).
Image radiosity_with(const Scene& scene, const FrameOptions& opts, FrameStats* stats, const embree::Device& device);

}  // namespace lockstep::opt::simd
