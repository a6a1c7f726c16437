// lockstep optimized: the z-buffer with Highway edge functions over tiles on
// TBB threads (optimized/zbuffer/zbuffer_simd.cpp and its kernels), the contract of
// core/raster.h; its shadow maps and shadow volumes too.
#pragma once

#include "core/raster.h"
#include "core/shadow_map.h"

namespace lockstep {

namespace opt::simd {
// Same contract as ref::zbuffer_visibility; threads = 0: all cores.
void zbuffer_visibility(const ScreenMesh& mesh, const RasterSettings& s, int threads, Visibility& vis);
Image zbuffer(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
// The same frame drawn into img, which a caller keeps from frame to frame (a
// session's frame buffer, registry/raster_rows.cpp): reused when it has the frame's
// size and a depth plane (every pixel and depth rewritten), made afresh
// otherwise. A fresh 1024^2 frame is 20 MiB of first-touch page faults, 7-10 ms
// on the 2-core VM against a 2.4 ms warm frame (issue #21, "One-shot cost").
void zbuffer_into(const Scene& scene, const FrameOptions& opts, FrameStats* stats, Image& img);
// img made width x height with a depth plane, unless it is already (contents
// left as they are: every renderer here writes every pixel).
void fit_frame(Image& img, int width, int height);
// A frame buffer for zbuffer_into and scanline_into, every page touched now.
Image new_frame(int width, int height);
// lockstep::view_scene's mesh, bit for bit, in parallel and with every vertex
// projected once (optimized/zbuffer/zbuffer_setup.cpp); spheres go through view_scene's
// own sphere step in parallel chunks, polygons that need clipping through its
// polygon step, one polygon at a time.
ScreenMesh view_scene(const Scene& scene, int width, int height, const RasterSettings& s, int threads);
// The z-buffer's SIMD shading (float, structure of arrays, every Shading mode,
// box filter) of a visibility found by another method: visible holds, per
// sample ((y width + x) spp + k, as Visibility::tri), the index into mesh.tris
// of the triangle seen there, or Visibility::kNone (mesh.width * mesh.height *
// spp entries). The image and its depth plane (the nearest sample's eye
// depth), as opt::simd::zbuffer draws them.
Image shade_visibility(const Scene& scene, const ScreenMesh& mesh, const RasterSettings& s,
                       const uint32_t* visible, const FrameOptions& opts);
void shade_visibility_into(const Scene& scene, const ScreenMesh& mesh, const RasterSettings& s,
                           const uint32_t* visible, const FrameOptions& opts, Image& img);
// shadows=map (optimized/zbuffer/zbuffer_shadow.cpp): every light's cube map drawn by
// zbuffer_visibility (pass 1), and the frame zbuffer draws when s.shadows is
// map: the fast rasterizer's visibility, each sample shaded in double with the
// map's test (shade_fragment, as the reference).
ShadowMaps shadow_maps(const Scene& scene, const RasterSettings& s, int threads);
// Pass 1's face (core/shadow_map.h FaceDistances): the texels' distances
// written tile by tile from the raster's buffers (depth.spp must be 1).
void zbuffer_distances(const ScreenMesh& face_frame, const RasterSettings& depth, int threads, float* dist);
Image zbuffer_shadowed(const Scene& scene, const FrameOptions& opts, const RasterSettings& s, FrameStats* stats);
// shadows=volume (optimized/zbuffer/zbuffer_shadow_volume.cpp): per visible sample
// and light (index sample * lights + k) 1 where the light reaches it (stencil
// count 0), counted on tiles on threads; equal to the reference's
// ref::shadow_masks for the same mesh and visibility.
struct ShadowVolumeMasks {
  uint32_t lights = 0;
  std::vector<uint8_t> lit;
  uint64_t volume_tris = 0;  // volume triangles over all lights, before viewing
  std::string note;          // occluder_note: "" when every occluder is closed
};
ShadowVolumeMasks shadow_volume_masks(const Scene& scene, const ScreenMesh& mesh, const RasterSettings& s,
                                      const Visibility& vis, int threads);
// The SIMD shading lights in float lanes, relative to the eye: a point farther
// than 2^60 from it overflows |L|^2 and |V|^2, one nearer than 2^-60
// underflows them (measured: a triangle 1e20 away came out ambient only).
// (A vertex's distance counts as at most (1 + guard band) times its depth:
// clipping brings a huge polygon's visible part that close.)
// Such primitives are drawn but not lit right: counted into stats->dropped
// with that reason (issue #22), as are those of a scene whose lights are out
// of that range.
void count_float_lighting_limits(const Scene& scene, const Camera& cam, FrameStats* stats);
}  // namespace opt::simd

namespace opt {
// The Highway target the z-buffer kernels dispatch to (for the tests).
const char* zsimd_target_name();
}  // namespace opt

}  // namespace lockstep
