// lockstep core: shadow maps for point lights -- the cube-map geometry, the
// map and the test every shadow-map implementation shares (the passes that
// fill the map are each implementation's: reference/shadow_map.h).
//
// Williams, "Casting curved shadows on curved surfaces", SIGGRAPH 1978: two
// passes of the z-buffer. Pass 1 renders the scene's depth as the light sees
// it; pass 2 draws the scene from the eye and, for each visible point p,
// compares p's depth from the light with the depth stored where p falls in the
// light's map: farther than the stored surface (by more than a bias) means
// something lies between p and the light.
//
// Point lights shine everywhere, so each light gets a cube map: six square
// faces of map_size x map_size texels, each a 90 degree frustum looking along
// one axis from the light (Akenine-Moller et al., "Real-Time Rendering", 4th
// ed., 7.4). Direction d from the light falls in face cube_face(d), that of
// its major axis |d_x|, |d_y| or |d_z| (ties go to x before y before z, and
// to + before -: the faces tile the sphere of directions without gaps or
// overlaps). Each face is drawn by the rasterizer's own pipeline
// (core/viewing.cpp) with the face's camera (cube_face_camera: pitch 2/n, so
// that the face's n texels span exactly tan 45 = 1 either side of its axis,
// and texel (i, j)'s sample is its centre, as a pixel's), no back-face
// culling (a shadow ray is blocked by either side of any surface,
// core/ray_trace.h), one sample per texel.
//
// What a texel stores: the distance from the light to the nearest surface
// along the ray through the texel's centre, as a float (+inf where the ray
// meets nothing). A distance, not the face's depth, so that texels of
// different faces compare with each other (percentage-closer filtering across
// a cube edge; Gerasimov, "Omnidirectional shadow mapping", GPU Gems ch. 12).
//
// The test (lit_fraction): p at distance r from the light is shadowed by a
// texel storing t when r - bias_total > t, with
//     bias_total = bias + slope_bias * (2 r / n) * min(tan theta, 10),
// bias in world units (the textbook constant offset), slope_bias in texels:
// 2 r / n is a texel's width at distance r at the face's centre (its widest)
// and theta the angle between the surface's normal and the direction to the
// light, so slope_bias * (2r/n) tan(theta) is how much a plane's distance
// from the light changes across slope_bias texel widths (Real-Time Rendering,
// 7.4.2: slope-scaled bias). The sample point p and the texel's centre ray
// are at most half a texel's diagonal apart, so on a plane slope_bias >=
// sqrt(2)/2 ~ 0.71 covers the whole discretisation error (no acne), and more
// pushes the shadow off its occluder where they touch (peter-panning).
// tan is capped at 10 (84 degrees): a surface that grazes the light would
// otherwise push its bias to infinity. A third term, kShadowRounding * r,
// always there, covers the rounding of the two distances compared (the
// texel's through the rasterizer's interpolated 1/z and a float, 2^-24
// relative; p's through the eye's pass): without it a point exactly on a
// texel's centre ray, facing the light, would shadow itself by a rounding.
//
// Percentage-closer filtering (Reeves, Salesin and Cook, "Rendering
// antialiased shadows with depth maps", SIGGRAPH 1987): with pcf = k > 1 the
// test is made against the k x k texels around p's (offsets -(k-1)/2 ..
// (k-1)/2 texels on p's face; an offset past the face's edge is followed onto
// the neighbouring face through its direction) and the light is scaled by the
// fraction that pass: a soft edge k texels wide where the hard one was. Each
// sample (a, b) texels from p adds sqrt(a^2 + b^2) texels to the slope term
// (the plane's distance changes across the offset as across p's own texel).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/raster.h"
#include "core/scene.h"

namespace lockstep {

inline constexpr int kCubeFaces = 6;
// Face k looks along +x, -x, +y, -y, +z, -z (k = 0..5).
inline constexpr std::array<const char*, kCubeFaces> kCubeFaceNames = {"+x", "-x", "+y",
                                                                       "-y", "+z", "-z"};

// The face direction d (not 0) falls in: its major axis, ties to x, y, z in
// that order and to + over -.
int cube_face(const Vec3& d);
// The camera of face `face` of a cube map of n x n faces around light: eye at
// the light, forward along the face's axis, pitch 2/n (image plane at distance 1
// from -1 to 1 on both axes), hither 0 (the frame sets its own near).
Camera cube_face_camera(const Vec3& light, int face, int n);

struct CubeTexel {
  int face = 0;
  int i = 0, j = 0;  // column from the left, row from the top (the face camera's pixel)
};
// The texel of direction d: its face, and the texel whose square holds d's
// point on that face's image plane (clamped to the face: a direction exactly on
// a face's edge belongs to the edge texel).
CubeTexel cube_texel(const Vec3& d, int n);
// The world direction through screen position (x, y) (in texels, y down) of
// face `face`; x, y may lie outside [0, n] (the face's plane extended).
Vec3 cube_direction(int face, double x, double y, int n);

// One light's cube map.
struct ShadowCube {
  Vec3 light;
  int n = 0;
  // n * n texels per face, row by row: the distance from the light to the
  // nearest surface along the texel centre's ray, +inf where there is none.
  std::array<std::vector<float>, kCubeFaces> dist;
  float at(const CubeTexel& t) const {
    return dist[size_t(t.face)][size_t(t.j) * size_t(n) + size_t(t.i)];
  }
};

// Every light's cube, in the scene's light order.
struct ShadowMaps {
  std::vector<ShadowCube> cubes;
};

// Pass 1's pieces, for the implementations that fill a map:
// the frame of one face (the face's camera, n x n, near and far from the
// scene's bounds as seen along the face's axis; no triangles yet) ...
ScreenMesh cube_face_frame(const Scene& scene, const Vec3& light, int face, int n);
// ... the settings the depth pass draws with (the frame's tess_error, in
// texels; no culling, one sample per texel at its centre, double depth,
// perspective-correct) ...
RasterSettings depth_pass_settings(const RasterSettings& s);
// ... and the distance a texel stores, from the window depth the z-buffer kept
// (stored_depth of kDouble) at texel (i, j) of the face's frame.
double texel_distance(const ScreenMesh& face_frame, double window_depth, int i, int j);

// Pass 1 whole: every light's cube, each face's triangles drawn by `visibility`
// (an implementation's z-buffer without shading: the reference's or the fast
// one) into one Visibility buffer reused across faces (its arrays keep their
// pages: a fresh 14 bytes a texel per face cost as much as drawing the face).
using DepthPass =
    std::function<void(const ScreenMesh& face_frame, const RasterSettings& depth, Visibility& vis)>;
ShadowMaps build_shadow_maps(const Scene& scene, const RasterSettings& s,
                             const DepthPass& visibility);
// The same with pass 1's last step an implementation's too: `distances` draws
// the face and writes each of its n x n texels' distance (texel_distance of
// the window depth its z-buffer kept, +inf where nothing is drawn) into dist,
// in whatever order and on whatever threads it likes (the simd z-buffer: tile
// by tile, while the tile's depths are in cache, instead of a Visibility
// copied out and then walked again here).
using FaceDistances =
    std::function<void(const ScreenMesh& face_frame, const RasterSettings& depth, float* dist)>;
ShadowMaps build_shadow_maps_direct(const Scene& scene, const RasterSettings& s,
                                    const FaceDistances& distances);

// The relative rounding allowance of the test (a few float ulps of r).
inline constexpr double kShadowRounding = 1.0 / (1 << 20);
// The bias of the test above at distance r with cos_theta = |N.L|.
double shadow_bias(const RasterSettings& s, int n, double r, double cos_theta);
// Pass 2: the fraction of cube's light that reaches point p with unit
// geometric normal face_normal (0 or 1 without PCF).
double lit_fraction(const ShadowCube& cube, const RasterSettings& s, const Vec3& p,
                    const Vec3& face_normal);

// Whether s can be drawn with shadows (throws InputError(source, 0, ...) if
// not): both kinds need per-sample lighting (shading phong or blinn;
// shading_name: the shading as the user named it). Which rows draw which
// shadows is the registry's (registry/raster_rows.cpp refuse_shadows).
void check_shadow_settings(const RasterSettings& s, const std::string& source,
                           const std::string& shading_name);

}  // namespace lockstep
