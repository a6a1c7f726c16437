// lockstep core: shadow volumes for point lights -- the steps every
// shadow-volume implementation shares (issue #22): the occluders and their
// silhouettes, the volume's triangles, the volume as the z-buffer's pipeline
// sees it, and the depth and the stencil rule at one sample. What counts the
// stencils is each implementation's (reference/shadow_volume.h: the textbook
// loop, and there the method, its sources and what is exact;
// optimized/zbuffer/zbuffer_shadow_volume.cpp: tiles on threads). Both call these
// functions, so that their counts agree bit for bit.
//
// Occluders: every scene triangle and every sphere, tessellated as the z-buffer
// draws it. occluder_mesh() splits them into edge-connected components and
// checks that every edge is shared by exactly two triangles of the component,
// traversed in opposite directions (vertices matched by exact position); a
// closed one turned inside out is turned outward. A component that fails
// gets a volume per triangle (exact for any soup, only more fill), counted for
// the stats line (occluder_note).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/raster.h"
#include "core/scene.h"

namespace lockstep {

// The occluders, as a triangle soup with their components' verdicts.
struct OccluderMesh {
  std::vector<std::array<Vec3, 3>> tri;  // world positions, in the order the z-buffer draws them
  std::vector<uint32_t> component;       // per triangle
  // Per triangle and edge k (v[k] -> v[k+1]): the one other triangle sharing
  // that edge (by position), or kNone when the edge has not exactly two.
  std::vector<std::array<uint32_t, 3>> adj;
  static constexpr uint32_t kNone = 0xffffffffu;
  std::vector<uint8_t> closed;  // per component: closed and consistently oriented
  uint64_t open_tris = 0;       // triangles of components that are not
  uint32_t open_components = 0;
  uint32_t inverted_components = 0;  // closed but inside out: turned outward (their tri reversed)
};

// Scene triangles (scene order) after the spheres' tessellations (as
// view_spheres makes them for the frame `mesh`, tess_error from s).
OccluderMesh occluder_mesh(const Scene& scene, const ScreenMesh& frame, const RasterSettings& s);
// The same analysis of a given soup (for the tests).
OccluderMesh occluder_mesh(std::vector<std::array<Vec3, 3>> tris);

// The shadow volume of every occluder for a point light, as outward-facing
// triangles (counter-clockwise seen from outside the volume): side quads (two
// triangles each) extruded to distance `far` from the light (further when a
// flat back cap at `far` would come nearer the light than far / 2:
// shadow_volume.cpp), and with caps the front and back caps.
// silhouette_only_for_open: the textbook silhouette rule even for components
// that are not closed (wrong; the tests show why the check matters). is_cap,
// when given, gets 1 per cap triangle and 0 per side.
std::vector<std::array<Vec3, 3>> shadow_volume(const OccluderMesh& occ, const Vec3& light,
                                               double far, bool caps,
                                               bool silhouette_only_for_open = false,
                                               std::vector<uint8_t>* is_cap = nullptr);

// Twice the distance from the light to the farthest corner of the box around
// the scene and the eye.
double shadow_far(const Scene& scene, const Vec3& light);

// The stats-line note for components that took the per-triangle fallback ("" when none).
std::string occluder_note(const OccluderMesh& occ);

// The volume's triangles through the z-buffer's viewing pipeline (the frame's
// camera, hither and far, no culling: view_polygons, one polygon each), and per
// screen triangle whether it faces the eye and whether it is a cap (is_cap as
// shadow_volume gives it, or none).
struct ViewedVolume {
  ScreenMesh mesh;
  std::vector<uint8_t> front;  // per mesh.tris: faces the eye
  std::vector<uint8_t> cap;    // per mesh.tris: a cap
};
ViewedVolume view_volume(const Scene& scene, const ScreenMesh& frame, const RasterSettings& s,
                         const std::vector<std::array<Vec3, 3>>& volume,
                         const std::vector<uint8_t>* is_cap);

// The eye depth of triangle t at a sample with edge functions e0, e1, e2 (the
// z-buffer's formula: screen barycentrics, the plane of 1/z). One function,
// not inlined, for visible samples and volume faces alike, in every
// implementation, so that equal inputs give equal depths bit for bit.
double sample_depth(const ScreenTri& t, int64_t e0, int64_t e1, int64_t e2);

// What a volume face at depth z adds to the stencil count of a sample whose
// visible surface is at depth z_visible (finite): z-pass counts the faces in
// front of it (+1 front-facing, -1 back-facing), z-fail those at or behind it
// (+1 back-facing, -1 front-facing). A face at exactly the visible depth is
// behind, except a cap seen from its back, which is in front
// (reference/shadow_volume.cpp says why).
inline int32_t stencil_step(bool zfail, bool front, bool cap, double z, double z_visible) {
  const bool in_front = z < z_visible || (z == z_visible && cap && !front);
  if (in_front == zfail) return 0;
  return zfail ? (front ? -1 : 1) : (front ? 1 : -1);
}

}  // namespace lockstep
