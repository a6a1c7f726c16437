// lockstep reference: shadow volumes for point lights, the z-buffer family's
// shadows=volume (issue #22), textbook style.
//
// Sources: F. Crow, "Shadow algorithms for computer graphics", SIGGRAPH 1977
// (the volume: the occluder's silhouette edges as seen from the light, swept
// away from it; a point is in shadow when it lies inside); T. Heidmann, "Real
// shadows, real time", IRIS Universe 18, 1991 (z-pass: count the volume faces
// in front of the visible surface, +1 front-facing, -1 back-facing, in the
// stencil buffer); J. Carmack (2000) and C. Everitt, M. Kilgard, "Practical and
// robust stenciled shadow volumes for hardware-accelerated rendering", 2002
// (z-fail: count the faces behind it instead, +1 back-facing, -1 front-facing,
// with the volumes closed by a front cap (the light-facing occluder triangles)
// and a back cap (the same, pushed away from the light), so that the count
// does not depend on where the eye is). In both, the count is the in/out parity
// (winding number) of the visible point: a light contributes where it is 0.
//
// Z-pass counts from the eye, so it is wrong when the eye itself is inside a
// volume (the volume faces it is inside of were clipped at the hither plane;
// precisely: wherever the hither plane's point on the view ray is in shadow);
// z-fail counts from beyond the scene, where every volume is closed, and is not.
// Heidmann's z-pass draws no caps, relying on the occluder itself to be drawn
// where a view ray enters a volume through it; here z-pass draws the caps too,
// since an occluder may be culled from the eye (a one-sided back face still
// casts a shadow; corpus/scenes/clip-tris.nff has one) and with smooth normals
// a visible triangle may face away from the light yet be lit.
//
// Exactness: the volume faces go through the z-buffer's own pipeline
// (view_polygons: the same camera, hither clipping, snapping to 1/256 pixel,
// edge functions with the top-left rule, depth from the plane of 1/z), and are
// compared against the visible sample's eye depth z in double. A front cap is
// the very scene triangle the z-buffer drew (same vertices, same order), so its
// depth at a sample equals the visible depth exactly; it counts as behind the
// surface when it faces the eye and in front of it otherwise, so that the
// count is the one on the surface's light side, where shadow rays start (a
// smooth-shaded triangle that faces away from the light is not shadowed by its
// own volume, as the ray tracer's offset shadow ray is not). What remains is
// rounding where a volume face passes within a snapping step of a sample: shadow
// edges, where shadow rays (the oracle) and the volume may decide differently.
//
// Occluders: every scene triangle and every sphere, tessellated as the z-buffer
// draws it (sphere_rings with the frame's camera). The silhouette method needs
// closed, consistently oriented meshes: occluder_mesh() splits the triangles
// into edge-connected components and checks that every edge is shared by
// exactly two triangles of the component, traversed in opposite directions
// (vertices matched by exact position); a closed one turned inside out is
// turned outward (its triangles reversed). A component that fails (open, e.g. a
// floor or a single polygon, or inconsistently oriented, or with T-junctions)
// is not refused: each of its triangles gets a volume of its own (its three
// edges extruded, turned to face the light, capped), which is exact for any
// triangle soup, only more faces to fill. How many triangles took that
// fallback is counted and printed (FrameStats::notes). Volumes are extruded
// "far enough": to a distance from the light twice the farthest corner of the
// box around the scene and the eye, or further where a back cap would
// otherwise cut a volume short inside that box (a triangle seen from the light
// over a wide angle: core/shadow_volume.cpp), so that inside that box they
// equal the infinite volumes. A light inside a closed occluder (everything
// outside in its shadow; its winding number about the light is not 0) has no
// silhouette: that component takes the per-triangle volumes for that light.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/raster.h"
#include "core/scene.h"
#include "core/shadow_volume.h"

namespace lockstep::ref {

// The shared steps (core/shadow_volume.h), under the names the tests use.
using lockstep::occluder_mesh;
using lockstep::occluder_note;
using lockstep::OccluderMesh;
using lockstep::shadow_far;
using lockstep::shadow_volume;

// The eye depth z of each visible sample (Visibility's triangle at the
// sample), +inf where nothing is drawn: computed by the very function that
// gives the volume faces' depths, so that a front cap equals its triangle.
std::vector<double> visible_z(const ScreenMesh& mesh, const RasterSettings& s,
                              const Visibility& vis);

// The stencil count of every sample (index (j * width + i) * spp + k, as
// Visibility) for one light's volume: z-pass (faces nearer than the visible
// eye depth z_visible, +1 front-facing, -1 back-facing) or z-fail (faces at or
// behind it, +1 back-facing, -1 front-facing; s.zfail). A face at exactly
// the visible depth counts as behind, except a cap (is_cap) seen from its
// back, which counts as in front (see shadow_volume.cpp). Samples with
// z_visible = +inf (nothing drawn) stay 0.
void stencil_counts(const Scene& scene, const ScreenMesh& frame, const RasterSettings& s,
                    const std::vector<std::array<Vec3, 3>>& volume,
                    const std::vector<double>& z_visible, std::vector<int32_t>& count,
                    const std::vector<uint8_t>* is_cap = nullptr);

// Per sample and light (index sample * lights + k): 1 where the light
// reaches the visible point (count 0), for the frame's visible samples;
// volumes extruded to shadow_far, capped for both rules.
struct ShadowMasks {
  uint32_t lights = 0;
  std::vector<uint8_t> lit;
  uint64_t volume_tris = 0;  // volume triangles over all lights, before viewing
};
ShadowMasks shadow_masks(const Scene& scene, const ScreenMesh& frame, const RasterSettings& s,
                         const OccluderMesh& occ, const Visibility& vis);

// shade_fragment's Phong (or Blinn-Phong) with only the lights whose lit[k] is
// set: the ray tracer's local term at depth 1 with shadow rays.
Vec3 shade_fragment_lit(const Scene& scene, const ScreenMesh& mesh, const RasterSettings& s,
                        const Fragment& f, const uint8_t* lit);

}  // namespace lockstep::ref
