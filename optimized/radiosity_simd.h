// lockstep optimized: radiosity (issue #33) on TBB threads, Embree's rays and
// the simd z-buffer's hemicubes; the contract of core/radiosity.h, the
// reference's steps (reference/radiosity.h) done fast:
//   rays      Lambert's factors from patch i's centre to 8 patches a vector
//             (optimized/radiosity_simd_kernels.h, double; patches reaching
//             behind the tangent plane by the reference's clipping code);
//             visibility by shadow polygons (Atherton, Weiler and Greenberg
//             1978): from c, every blocker that may reach into the shaft
//             over a receiving polygon (Haines and Wallace's shaft culling:
//             boxes and the pyramid from c) is clipped to the heights a
//             segment crosses and projected onto the receiver's plane; a
//             target whose projection no shade covers arrives, one deep in
//             a shade's core is hidden, the rest are decided by the
//             reference's own predicate (Moller-Trumbore in double) against
//             that blocker alone: the reference's answers without testing
//             every triangle. The receiver's targets are kept in bins; a
//             shade classifies the runs of bins under it a vector at a
//             time (radiosity_simd_kernels.h classify_points). Segments
//             the shades cannot take (c within 1e-6 of the scene of the
//             receiver's plane, scenes of more than 256 polygons) go to
//             Embree in one stream (rtcOccluded1M, float); rows on TBB
//             threads;
//   hemicube  each face through opt::simd's view_scene and z-buffer (one
//             thread each; the depth format the reference's, float, whose
//             ties the two z-buffers break alike), patches on TBB threads;
//   display   the patches through opt::simd's z-buffer, the shared display
//             step (core/radiosity.h radiosity_image).
//   solve     Jacobi and Gauss-Seidel over the radiosities as structure of
//             arrays, each row's gathers in one Highway pass over its form
//             factors (the residual of the last sweep and the new B_i
//             together: the reference reads F twice a sweep); Jacobi's rows
//             on TBB threads (Gauss-Seidel's in order: a second thread
//             taking the rows' suffixes ahead of the sweep gained 7%, the
//             sweep being bound by memory: 9 GB/s); progressive refinement
//             the shared solver.
#pragma once

#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

#include "core/family.h"
#include "core/image.h"
#include "core/radiosity.h"
#include "core/scene.h"
#include "optimized/embree_scene.h"

namespace lockstep::opt::simd {

// The form factors by rays (or exact) and by the hemicube, written into
// storage (its memory reused when it holds n^2 values, else made).
// What the rays method did: segments cast through Embree, targets tested
// against shades (a target and a shade over it), patch pairs no shade hid
// (every segment arrives), and the seconds its Embree BVH of the scene took
// to build.
struct RayCounts {
  uint64_t rays = 0, culled_pairs = 0, shaded = 0;
  double build_seconds = 0;
};
FormFactors radiosity_form_factors_rays(const Scene& scene, const PatchMesh& mesh, int k, int threads,
                                                const embree::Device& device,
                                                const std::function<void(double)>& progress = {},
                                                RayCounts* counts = nullptr,
                                                FormFactorMethod method = FormFactorMethod::rays,
                                                FormFactors storage = {});
FormFactors radiosity_form_factors_hemicube(const PatchMesh& mesh, int res, int threads,
                                                    const std::function<void(double)>& progress = {},
                                                    FormFactors storage = {});

// solve_radiosity's contract (core/radiosity.h), on `threads` threads (0:
// all cores; Jacobi's rows), the sweeps over a float copy of f (in
// `single` when given: a session's storage, kept between frames).
SolveResult solve_radiosity(const std::vector<Patch>& patches, const FormFactors& f, RadiositySolver solver,
                            double tolerance, int max_iterations, int threads, UninitVector<float>* single = nullptr);

Image radiosity(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
// What a session keeps from frame to frame (registry/radiosity_row.cpp): the
// form-factor matrix's storage and the solve's float copy of it, touched
// once (the matrix's first touch, 136 MB at 4,119 patches, is a tenth of a
// fresh frame). One frame at a time uses it;
// a frame that finds it busy makes its own.
struct RadiosityScratch {
  std::mutex busy;
  FormFactors f;
  UninitVector<float> single;  // the solve's float copy of f
};
// The same on a device the caller keeps (a session's, registry/radiosity_row.cpp),
// and the scratch it keeps (may be null).
Image radiosity_with(const Scene& scene, const FrameOptions& opts, FrameStats* stats, const embree::Device& device,
                     RadiosityScratch* scratch = nullptr);

}  // namespace lockstep::opt::simd
