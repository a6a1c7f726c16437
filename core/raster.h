// lockstep core: rasterization -- the contract every raster implementation
// shares (the textbook ones: reference/raster.h, namespace ref; the fast ones:
// optimized/zbuffer/zbuffer_simd.h, optimized/zbuffer/zbuffer_llvmpipe.h), and the shared steps they all call: the settings
// (core/raster_settings.cpp), the viewing pipeline, samples and depth
// (core/viewing.cpp) and the shading of a fragment (core/raster_shading.cpp).
//
// The raster families (zbuffer, scanline, painter; registry/raster_rows.cpp) draw the
// same NFF scenes as ray casting, with the same camera (core/camera.h: pixel
// centres, `angle` between the centres of the edge pixels), so that a z-buffer
// image with per-pixel Phong shading equals the ray-cast image.
//
// The pipeline (Foley, van Dam, Feiner, Hughes, "Computer Graphics: Principles
// and Practice", 2nd ed., ch. 6, 15 and 16; Akenine-Moller et al., "Real-Time
// Rendering", ch. 2 and 23):
//
//   view_scene()       world -> eye space (the camera's right, up, forward)
//                      -> back-face culling (world space or projection space)
//                      -> clipping at the hither plane z = hither (and at a
//                         guard band far outside the image, so that snapped
//                         coordinates stay small enough for exact integers)
//                      -> perspective divide -> screen (pixels)
//                      -> snapping to 1/256 pixel (kSubpixelBits).
//                      Spheres and cones become triangles here, adaptively:
//                      just enough that the silhouette is within tess_error
//                      pixels.
//   rasterisation      per triangle, per covered sample: edge functions,
//                      evaluated exactly in integers on the snapped vertices,
//                      with the top-left fill rule, so that an edge shared by
//                      two triangles gives each of its samples to exactly one.
//   shade_fragment()   flat, Gouraud, Phong, Blinn-Phong, toon; silhouettes.
//
// Screen space: x right, y down, in pixels; pixel (i, j) is the square
// [i, i+1) x [j, j+1) and its centre is (i + 1/2, j + 1/2). Supersampling puts
// n x n samples in each square (sample_offsets()).
//
// Fill rule (Direct3D's top-left rule, Pineda 1988 edge functions): triangles are
// stored with positive area A = E01(v2), where for the edge a -> b
//     E_ab(P) = (b.x - a.x)(P.y - a.y) - (b.y - a.y)(P.x - a.x).
// A sample P is inside when E12(P), E20(P), E01(P) are all >= 0, and an edge
// with E = 0 at P owns P only if it is a top edge (dy = 0, dx > 0) or a left
// edge (dy < 0). With y down, positive area is clockwise as the viewer sees
// it: NFF's front faces (counter-clockwise seen from the front) come out of the
// projection with negative area, and view_scene stores them reordered.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/family.h"
#include "core/image.h"
#include "core/scene.h"

namespace lockstep {

// ---------------------------------------------------------------- settings

enum class Shading : uint8_t {
  kFlat,     // one lighting evaluation per polygon (at its centroid, with its face normal)
  kGouraud,  // lighting per vertex, the colour interpolated (Gouraud 1971)
  kPhong,    // the normal interpolated and renormalised per sample, Phong specular (Phong 1975)
  kBlinn,    // as kPhong with Blinn-Phong's halfway-vector specular (Blinn 1977)
  kToon,     // as kPhong's normal, N.L quantised into bands, no specular
};
enum class CullMode : uint8_t {
  kWorld,       // face normal against the vector to the eye, in world space
  kProjection,  // sign of the projected (snapped) area on screen
  kNone,        // draw back faces too (their normal flipped towards the eye)
};
enum class SampleGrid : uint8_t {
  kRegular,  // n x n: ((a + 1/2)/n, (b + 1/2)/n)
  kRotated,  // the regular grid sheared by 1/n (x' = x - y/n, y' = y + x/n about the
             // centre): every sample has its own row and column (n-rooks; n = 2 is RGSS)
};
// What the z-buffer stores and compares (the value written is always derived
// from the eye depth z; n = hither, f = the scene's far bound).
// The order the simd z-buffer's tiles draw their triangles in (the same
// buffers every way): kAuto, front to back where the mesh comes back to front.
enum class DrawOrder : uint8_t { kAuto, kMesh, kReverse };

enum class DepthFormat : uint8_t {
  kFloat,     // window depth d = (1/n - 1/z) / (1/n - 1/f) in [0, 1], as a float; nearer = smaller
  kReversed,  // reversed-Z: d = n / z as a float (infinite far plane); nearer = larger
  kFixed24,   // the window depth d rounded to 24-bit fixed point, as most hardware
  kDouble,    // the window depth d in double: the reference's exact-ish answer
};

// How the raster families shadow point lights: not at all (every light reaches
// every surface, as ray casting lights it), with shadow maps (Williams 1978:
// core/shadow_map.h) or with shadow volumes (Crow 1977: reference/shadow_volume.h,
// stencil counting).
enum class ShadowMode : uint8_t { kNone, kMap, kVolume };

struct RasterSettings {
  Shading shading = Shading::kPhong;
  CullMode cull = CullMode::kWorld;
  bool silhouette = false;     // draw black where |N.V| < silhouette_eps
  double silhouette_eps = 0.2;
  int toon_bands = 4;
  int spp = 1;                 // samples per pixel: a square n * n, 1..256
  SampleGrid grid = SampleGrid::kRegular;
  bool split = false;          // painter: split polygons along the planes of cycles and interpenetrations
  double tess_error = 0.25;    // sphere and cone tessellation: silhouette error bound, pixels
  DepthFormat depth = DepthFormat::kFloat;
  bool perspective = true;     // perspective-correct interpolation (false: affine, for the tests)
  bool skip_hidden = true;     // opt::simd::zbuffer: leave out what nearer spheres hide (same image)
  DrawOrder order = DrawOrder::kAuto;  // opt::simd's tiles: their triangles' order (same buffers)
  // Shadows of point lights (issue #22; core/shadow_map.h for the map's units):
  ShadowMode shadows = ShadowMode::kNone;
  double bias = 0;          // shadows=map: constant depth bias, world units (distance from the light)
  double slope_bias = 1;    // shadows=map: slope-scaled bias, in texels (core/shadow_map.h)
  int map_size = 1024;      // shadows=map: each cube face is map_size x map_size texels
  int pcf = 1;              // shadows=map: percentage-closer filter, pcf x pcf texels (0 and 1: off)
  bool zfail = false;       // shadows=volume: z-fail with capped volumes (Carmack; Everitt-Kilgard) instead of z-pass
};

// Reads a family's Params (shading, cull, silhouette, spp, grid, split,
// tess_error, depth, interp, hidden, order, shadows, bias, slope_bias, map_size,
// pcf). Throws InputError(source, 0, ...) naming the
// setting and what it may be.
RasterSettings raster_settings(const Params& params, const std::string& source);
// The settings of one frame (raster_settings of opts.params), after the one
// limit every raster implementation shares: width x height x spp at most 2^25
// samples (the reference's sample buffers take 30 bytes a sample: 1024 x 1024
// at spp 25, 2048 x 2048 at 4), so that all refuse the same frames (InputError
// naming the scene).
RasterSettings frame_settings(const Scene& scene, const FrameOptions& opts);
// The settings the raster families understand, for --help and checking.
std::vector<ParamSpec> raster_params();

// ---------------------------------------------------------------- the screen-space mesh

inline constexpr int kSubpixelBits = 8;
inline constexpr int kSubpixel = 1 << kSubpixelBits;  // snapped units per pixel

// Floor of a / b for b > 0 (C++ division truncates toward zero): the first
// sample at or right of a snapped coordinate, in every rasterizer.
inline int64_t floor_div(int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
// The edge function E_ab(P) of the fill rule, exact in int64 for snapped
// coordinates within the guard band (|E| < 2^51).
inline int64_t edge_function(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t px, int64_t py) {
  return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}
// Clipping keeps every snapped vertex within kGuardBand pixels of the image
// centre: coordinates below 2^25 units, edge-function products below 2^51, so
// edge functions are exact in int64 and in double.
inline constexpr int kGuardBand = 1 << 16;

struct ScreenVertex {
  int32_t x = 0, y = 0;  // snapped screen position, 1/256 pixel
  double z = 0;          // eye-space depth along the view axis (>= hither)
  Vec3 world;            // world position
  Vec3 normal;           // unit shading normal of the drawn side (vertex normal of patches and spheres)
  Vec3 color;            // Gouraud: the lit colour at the vertex (only set for Shading::kGouraud)
};

struct ScreenTri {
  std::array<ScreenVertex, 3> v;  // positive area (see the fill rule above): a front face's v[1], v[2] swapped
  uint32_t prim = 0;              // scene primitive: spheres first, then polygons (Scene::prim_count)
  uint32_t source_tri = 0;        // polygons: index into Scene::tri_vertex; spheres: the tessellation's triangle
  Vec3 face_normal;               // unit world normal of the drawn side
  Vec3 flat_color;                // Shading::kFlat: the polygon's one lighting evaluation
};

struct ScreenMesh {
  Camera camera;
  int width = 0, height = 0;
  double near_z = 0, far_z = 0;  // hither, and the farthest eye depth of the scene's bounds
  std::vector<ScreenTri> tris;   // in scene order: the z-buffer keeps the first of equal depths
  // What view_scene did, for the stats line and the tests.
  uint64_t scene_tris = 0;       // polygon triangles in the scene
  uint64_t sphere_tris = 0;      // triangles the spheres were tessellated into
  uint64_t cone_tris = 0;        // triangles the cones were tessellated into (not in the stats' items)
  uint64_t culled = 0;           // dropped as back faces
  uint64_t clipped = 0;          // triangles that crossed the hither plane or the guard band
  uint64_t degenerate = 0;       // zero area after snapping (edge-on), dropped
  uint64_t hidden = 0;           // left out as behind nearer spheres (opt::simd::zbuffer's image only)
  // Primitives the pipeline could not draw, by reason (FrameStats::dropped):
  // never silently. Every raster implementation copies them into its stats.
  std::map<std::string, uint64_t> dropped;
  void drop(const std::string& reason, uint64_t n = 1) {
    if (n != 0) dropped[reason] += n;
  }
  void add_dropped(const ScreenMesh& other) {
    for (const auto& [reason, n] : other.dropped) drop(reason, n);
  }
};

// The viewing pipeline above, in double precision, for a width x height frame.
ScreenMesh view_scene(const Scene& scene, int width, int height, const RasterSettings& s);

// Its steps, for implementations that run them in pieces (opt::simd::view_scene):
// the frame (camera, near and far; no triangles), then the triangles of spheres
// [first, last), then those of polygons [first, last), each appended to
// mesh.tris with the counts, as view_scene emits them.
ScreenMesh view_frame(const Scene& scene, int width, int height);
// The same from the scene's bounds (scene_bounds' lo and hi), found another way.
ScreenMesh view_frame(const Scene& scene, int width, int height, const Vec3& lo, const Vec3& hi);
void view_spheres(const Scene& scene, const RasterSettings& s, uint32_t first, uint32_t last, ScreenMesh& mesh);
void view_polygons(const Scene& scene, const RasterSettings& s, uint32_t first, uint32_t last, ScreenMesh& mesh);
// The triangles of cones [first, last), after the polygons (prim order).
void view_cones(const Scene& scene, const RasterSettings& s, uint32_t first, uint32_t last, ScreenMesh& mesh);

// The sphere step's pieces. A sphere of centre c and signed radius R becomes the
// unit sphere of sphere_rings(|R|, ...) rings, positions c + |R| unit, normals
// unit (-unit and the winding reversed for R < 0), unless sphere_outside.
struct UnitSphere {
  int rings = 0;
  std::vector<Vec3> unit;                    // the poles (0, 0, 1), (0, 0, -1), then ring by ring
  std::vector<std::array<uint32_t, 3>> tri;  // counter-clockwise seen from outside
};
UnitSphere unit_sphere(int rings);
int sphere_rings(double radius, double centre_z, const Camera& cam, double near_z, double tess_error);
bool sphere_outside(const Camera& cam, const Vec3& eye_centre, double radius, double near_z);

// The cone step's pieces (core/viewing.cpp). A cone becomes one band of
// cone_segments(...) facets around its axis between its end circles (open
// ends, no caps), vertices on the surface, smooth normals of the side (the
// visible side's: inwards for NFF's negative radii, winding to match).
struct ConeMesh {
  std::vector<Vec3> position, normal;
  std::vector<std::array<uint32_t, 3>> tri;  // counter-clockwise seen from the visible side
};
int cone_segments(double r0, double r1, double base_z, double apex_z, const Camera& cam, double near_z,
                  double tess_error);
ConeMesh tessellate_cone(const Vec3& base, double r0, const Vec3& apex, double r1, bool inside, int segments);

// The n*n sample positions of a pixel, in 1/256 pixel from its top-left corner
// (spp = 1: the centre, (128, 128)). Rounded to the snapping grid.
std::vector<std::array<int32_t, 2>> sample_offsets(const RasterSettings& s);

// The value the z-buffer stores for eye depth z, and whether a is nearer than b.
double stored_depth(DepthFormat f, double z, double near_z, double far_z);
inline bool nearer(DepthFormat f, double a, double b) { return f == DepthFormat::kReversed ? a > b : a < b; }
// What an empty sample holds (the far end of the format).
double empty_depth(DepthFormat f);

// A visible sample of triangle tri: perspective-correct barycentrics b (sum 1)
// and eye depth z, at sample position (sx, sy) in pixels.
struct Fragment {
  uint32_t tri = 0;
  double b[3] = {1, 0, 0};
  double z = 0;
  double sx = 0, sy = 0;
};

// The colour of a fragment under s.shading (and s.silhouette). For kPhong
// without silhouettes on a scene without spheres this is exactly what ray
// casting computes at the same point (core/shading.h).
Vec3 shade_fragment(const Scene& scene, const ScreenMesh& mesh, const RasterSettings& s, const Fragment& f);
// The same under shadows, for kPhong and kBlinn: light k's diffuse + specular
// term is scaled by lit(k, p, face_normal) in [0, 1] (the share of the light
// that reaches p, where the sample's ray meets the triangle's unsnapped world
// plane; face_normal: the triangle's unit world normal of the drawn side),
// asked only where that term is not 0 (the light in front of the surface), as
// the ray tracer casts a shadow ray only there.
using LightReach = std::function<double(uint32_t light, const Vec3& p, const Vec3& face_normal)>;
Vec3 shade_fragment(const Scene& scene, const ScreenMesh& mesh, const RasterSettings& s, const Fragment& f,
                    const LightReach& lit);

// ---------------------------------------------------------------- visibility (kernel level)

// What a z-buffer rasteriser leaves per sample, before shading. Sample s of
// pixel (i, j) is index (j * width + i) * spp + s.
struct Visibility {
  static constexpr uint32_t kNone = 0xffffffffu;
  int width = 0, height = 0, spp = 1;
  std::vector<uint32_t> tri;     // the visible triangle (index into ScreenMesh::tris), or kNone
  std::vector<double> depth;     // its stored depth (stored_depth), or empty_depth
  std::vector<uint16_t> count;   // how many triangles cover the sample, depth test or not (watertightness)
};

}  // namespace lockstep
