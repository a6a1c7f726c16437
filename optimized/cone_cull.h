// lockstep optimized: per-tile cone culling for the SIMD renderer.
//
// All primary rays start at the eye (the frame's origin), so a screen tile's
// rays lie inside a cone around the tile's central direction. A primitive whose
// bounding sphere (seen from the eye under half-angle beta) is further than
// alpha + beta from the cone's axis cannot be hit by any of them: the packets
// of that tile skip it. This is what keeps brute-force packets (every packet
// against every primitive) affordable on scenes of a few thousand primitives;
// beyond that a BVH wins (opt::embree, BENCHMARKS.md). Conservative by a margin
// well above float's direction error, so culling never changes an image.
#pragma once

#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/math.h"
#include "optimized/simd_scene.h"

namespace lockstep::opt::simd {

// Every primitive's bounding sphere as seen from the eye (spheres first, then
// triangles, as in SimdScene's bounds arrays).
struct ConeBounds {
  std::vector<Vec3> dir;              // unit direction from the eye to the bounding centre
  std::vector<double> beta;           // angular radius of the bounding sphere
  std::vector<uint8_t> contains_eye;  // the eye is inside: always a candidate
};

// Once per frame; s's frame must have the camera's eye as its origin.
ConeBounds cone_bounds(const SimdScene& s);

// The candidates of the tile of pixels [i0, i1) x [j0, j1) (out is cleared
// first; its capacity is reused).
void cull_tile(const SimdScene& s, const ConeBounds& cb, const Camera& cam, int i0, int i1, int j0, int j1,
               Candidates& out);

}  // namespace lockstep::opt::simd
