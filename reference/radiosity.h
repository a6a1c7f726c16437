// lockstep reference: radiosity (issue #33), the textbook way.
//
// Contract (core/radiosity.h): radiosity(scene, opts, stats) cuts the
// scene's polygons into patches (opts.params: patch_area), computes the form
// factors (form_factors=rays|hemicube), solves B = E + rho F B (solver=),
// and displays the solution through the reference z-buffer, Gouraud
// interpolating the vertex radiosities. stats->items counts the form factors
// (patch pairs); its counts give the patches, rays or hemicube pixels, and
// the solver's sweeps or shots.
//
// The steps are exported for the properties (props/radiosity/) and the
// benchmarks.
#pragma once

#include <vector>

#include "core/family.h"
#include "core/image.h"
#include "core/radiosity.h"
#include "core/scene.h"

namespace lockstep::ref {

// The n x n form factor matrix (row-major, F_ij at i * n + j) by rays from
// each patch's centre to k x k points of every other patch, every segment
// tested against every triangle of the scene (brute force, double). The
// unoccluded factor is the centre's (method rays) or the area-to-area one
// (method exact): core/radiosity.h.
FormFactors form_factors_rays(const Scene& scene, const PatchMesh& mesh, int k,
                                      FormFactorMethod method = FormFactorMethod::rays);

// The same by hemicubes of res pixels a side, each face drawn through the
// reference z-buffer (reference/raster.h) as an item buffer of patches.
FormFactors form_factors_hemicube(const PatchMesh& mesh, int res);

// Whether the segment from a (on scene polygon from) to b (on polygon to),
// shortened by kSegmentMargin of its length at each end, meets no triangle
// of the scene (either side) but those of its own two polygons (planar: a
// segment leaving one's plane, or arriving at the other's, cannot meet it).
bool segment_clear(const Scene& scene, const Vec3& a, const Vec3& b, int from, int to);

Image radiosity(const Scene& scene, const FrameOptions& opts, FrameStats* stats);

}  // namespace lockstep::ref
