// lockstep optimized: the Highway z-buffer kernels, declared here, defined in
//   zbuffer_raster_kernels.cpp  raster_tile, target_name;
//   zbuffer_shade_kernels.cpp   shade_tile, flat_colors;
//   zbuffer_setup_kernels.cpp   the set-up's vector steps (project_vertices,
//                               triangle_step, set_up_*, polygon_run, ...);
// with the helpers two of them share in zbuffer_simd_kernels-inl.h. The
// set-up driver (zbuffer_setup.cpp, zbuffer_spheres.cpp, zbuffer_occlusion.cpp)
// declares view_scene_chunks here too.
//
// The contract functions (optimized/zbuffer/zbuffer_simd.cpp) prepare one TriSetup per
// screen triangle and bin them into screen tiles; these kernels then run one
// tile at a time, on one thread, over tile-local buffers:
//   raster_tile()  every binned triangle's samples: edge functions 16 samples
//                  at a time, depth test, coverage count;
//   shade_tile()   the visible samples' colours (every Shading mode), SoA.
// Entry points dispatch at run time to the best target the CPU has
// (HWY_DYNAMIC_DISPATCH), as in ray_cast_simd_kernels.h.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "core/raster.h"

namespace lockstep::opt::zsimd {

// One triangle, ready for tiles. Snapped coordinates (1/256 pixel) as in the
// ScreenMesh; edge k is the edge opposite vertex k (a -> b = v1 -> v2, v2 -> v0,
// v0 -> v1), E_k(P) = ex[k] (P.x - ax[k]) + ey[k] (P.y - ay[k]) exactly in
// int64, with ex = -(b.y - a.y), ey = b.x - a.x (|coordinates| < 2^25, so
// they fit int32; the products do not). A sample is inside when
// E_k(P) - bias[k] >= 0 for all k: bias 0 for top and left edges, 1 for the
// others (E integer, so E - 1 >= 0 is E > 0: the top-left rule).
// Kept small (128 bytes, two cache lines in the binner's page-aligned arrays):
// a big mesh's set-ups are written to memory and read back, tile by tile, by
// the raster.
struct TriSetup {
  int32_t ax[3], ay[3];
  int32_t ex[3], ey[3];
  // Pixels that may hold a covered sample (inclusive; i0 > i1 or j0 > j1: none),
  // clamped to [-1, size] (set_box).
  int16_t i0, i1, j0, j1;
  uint8_t bias[3];
  // Depth plane q(P) = q0 + qx (P.x - x0()) + qy (P.y - y0()), P in 1/256 px:
  // the stored depth (kFixed24: the window depth before rounding).
  double q0, qx, qy;
  // What only one raster reads: the float one with flat shading drawn forward
  // (RasterParams::flat), or the double one (kDouble, kFixed24).
  struct Forward {
    double w0, wx, wy;  // the plane of w = 1/z, as q's
    float flat[3];      // the triangle's flat colour
  };
  struct Corners {
    // The depth at the three vertices and twice the area A: the double raster
    // takes depth from barycentrics, sum E_k q_k / A, whose rounding stays
    // within a few ulps of the largest q_k however thin the triangle (the
    // plane's gradients lose digits to cancellation there).
    double qv[3], area;
  };
  union {
    Forward fwd;
    Corners dbl;
  };
  // Vertex 0, the planes' origin (edge 2 starts there).
  int32_t x0() const { return ax[2]; }
  int32_t y0() const { return ay[2]; }
  // The box from SampleGrid::pixels' (i0 in [0, inf), i1 in (-inf, width - 1]:
  // clamped, still empty where it was).
  void set_box(int32_t a0, int32_t a1, int32_t b0, int32_t b1) {
    i0 = int16_t(std::min(a0, 1 << 14)), i1 = int16_t(std::max(a1, -1));
    j0 = int16_t(std::min(b0, 1 << 14)), j1 = int16_t(std::max(b1, -1));
  }
  // (No initialisers: the set-up writes every field; arrays of them are not zeroed first.)
};
static_assert(sizeof(TriSetup) == 128);

// What shading needs of one triangle. Its attribute planes (kept apart, in
// double, as many rows as the shading needs) are a(P) = a0 + ax (P.x - x0) +
// ay (P.y - y0) (P in 1/256 px, (x0, y0) = TriSetup's vertex 0): row 0 is
// w = 1/z; rows 1.. hold attribute / z under perspective (the attribute is
// row / w) and the attributes themselves under affine interpolation.
// Rows 1-3: shading normal; 4-6: Gouraud's lit colour.
// (16 bytes: the set-up writes one per triangle and the shading reads it back;
// the material, the same for a whole sphere or polygon, is an index into
// ShadeParams::materials rather than a copy.)
struct ShadeTri {
  static constexpr int kRows = 7;
  float face[3];      // the face normal of the drawn side (where the interpolated one is 0)
  uint32_t material;  // ShadeParams::materials[material]
};

// A material as the lighting reads it (Scene::materials[i] in float).
struct ShadeMaterial {
  float k[3], ks, shine;  // kd * colour, ks, shine
};

// A triangle as one tile shades it: its planes moved to the tile (base at the
// tile's top-left pixel corner, gradients per pixel, in float), rows 0-3 (w
// and the normal: what Phong, Blinn-Phong and toon read), and its ShadeTri.
// One cache line: the set-up writes one per triangle, ready for the tile of a
// triangle that meets one tile only (most of a fine mesh's), and the shading
// reads it there.
struct alignas(64) TilePlanes {
  ShadeTri tri;
  float p[4][3];
};
static_assert(sizeof(TilePlanes) == 64);

// All of a triangle's rows, for a tile (shade_one_tile's, from the double
// planes): TilePlanes first (a pointer to base is one to the LocalPlanes),
// then Gouraud's colour rows 4-6 and kFlat's colour.
struct LocalPlanes {
  TilePlanes base;
  float more[ShadeTri::kRows - 4][3];
  float flat[3];  // kFlat: the polygon's colour
};
static_assert(std::is_standard_layout_v<LocalPlanes> && offsetof(LocalPlanes, base) == 0);

struct ShadeParams {
  Shading shading = Shading::kPhong;
  bool perspective = true;
  bool silhouette = false;
  float silhouette_eps = 0.2f;
  int toon_bands = 4;
  int nlights = 0;
  // Per light, kLightFloats floats: position x y z, intensity r g b,
  // attenuation c1 c2 c3, spot (0 or 1), spot direction x y z, cos(cut-off), exponent.
  static constexpr int kLightFloats = 15;
  const float* light = nullptr;
  // The scene's materials (ShadeTri::material indexes them; at least one entry).
  const ShadeMaterial* materials = nullptr;
  float eye[3] = {0, 0, 0};
  // The world point the kernels' positions, lights and eye are relative to (the
  // camera's eye; light_params): lighting depends on differences only, and in
  // float lanes absolute world positions 1e20 from the origin overflow |L|^2
  // and those 1e12 away lose every digit (issue #22). FlatBatch subtracts it.
  double origin[3] = {0, 0, 0};
  // The eye in double: flat_colors turns each face towards it as view_scene's
  // lit() does, in double (a face seen edge-on is turned the same way).
  double flat_eye[3] = {0, 0, 0};
  // The view direction (forward component 1) through the tile's top-left
  // pixel corner, and its change per pixel right and down: the sample at eye
  // depth z is eye + z dir (as the reference's fragments).
  float dir0[3] = {0, 0, 1}, dir_u[3] = {1, 0, 0}, dir_v[3] = {0, 1, 0};
  float background[3] = {0, 0, 0};
  const std::array<int32_t, 2>* offsets = nullptr;
  int spp = 1;
  int buf_w = 64, buf_h = 64;
  // Flat shading without silhouettes, drawn forward by raster_tile: w and the
  // colours per sample come from these buffers, and whether a sample was drawn
  // from its depth there (finite: the float raster's far end is infinite);
  // tri, planes and slots are unused.
  const float* forward_w = nullptr;
  const float* forward_rgb[3] = {nullptr, nullptr, nullptr};
  const float* forward_depth = nullptr;
};

// Shades the visible samples of a tile (tri: raster_tile's buffer) and
// box-filters them into the image: pixel (col, r) of the tile is written at
// image + r * image_stride + 4 col (RGBA, alpha 1; empty samples show the
// background), its eye depth -- the nearest sample's, +inf for none -- at
// depth + r * depth_stride + col. rgb (3 planes) and z (1 plane) of buf_w x
// buf_h floats, aligned, hold the sums while spp > 1. where[id]: triangle
// id's planes for this tile (the base of a LocalPlanes where the shading reads
// rows past 3 or the flat colour: Gouraud, flat). cols x rows: the tile's size.
void shade_tile(const ShadeParams& p, const int32_t* tri, const TilePlanes* const* where,
                int cols, int rows, float* rgb, float* z, float* image, size_t image_stride,
                float* depth, size_t depth_stride);

// Flat colours with shade_tile's lighting (Phong specular, as view_scene's
// flat colour), in float lanes (double ones for a high shine): for i < n, the
// colour at point (in[0..2])[i] of a face with unit normal (in[3..5])[i],
// turned towards the eye here (ShadeParams::flat_eye; decided in double, as
// view_scene's lit() decides it, on the same bits), of surface surface[id[i]]
// (kd * colour, ks, shine: FlatSurface); out[0..2]: red, green, blue. Every array has room for n
// rounded up to 16; id does not decrease (a surface's requests are one run).
inline constexpr int kFlatInputs = 6;
struct FlatSurface {
  double k[5];  // kd * colour (3), ks, shine
};
void flat_colors(const ShadeParams& p, size_t n, const double* const* in, const uint32_t* id,
                 const FlatSurface* surface, float* const* out);

// Flat shading drawn forward: per sample, alongside the triangle, its w = 1/z
// and flat colour (tile buffers laid out as raster_tile's), so that shading
// needs no per-triangle work (shade_tile with ShadeParams::forward).
struct ForwardFlat {
  float* w = nullptr;
  float* rgb[3] = {nullptr, nullptr, nullptr};
};

struct RasterParams {
  const ForwardFlat* flat = nullptr;                // float depth formats only
  const std::array<int32_t, 2>* offsets = nullptr;  // sample_offsets()
  int spp = 1;
  DepthFormat depth = DepthFormat::kFloat;
  int buf_w = 64, buf_h = 64;  // tile buffers: spp planes of buf_h rows of buf_w (a multiple of 16)
  DrawOrder order = DrawOrder::kAuto;  // TileJob::reverse per tile (the contract side decides)
};

// Triangles binned into one tile, a chunk of the mesh at a time: triangle
// ids[i] of a chunk is tris[ids[i]], its id in the mesh first + ids[i].
struct TileList {
  const std::vector<uint32_t>* ids = nullptr;
  const TriSetup* tris = nullptr;
  int32_t first = 0;
};
// A tile's work: lists[0..nlists) in order, each in mesh order; or, with
// reverse, all of it backwards, a tie in depth then winning (the earliest of
// equal depths is still the one kept): the same buffers either way, but a mesh
// drawn back to front is then drawn front to back, and the hidden triangles'
// samples fail the test and write nothing.
struct TileJob {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // pixels, half-open
  const TileList* lists = nullptr;
  int nlists = 0;
  bool reverse = false;
};

// Tile-local buffers, plane s (sample s), row r, column c at [(s buf_h + r) buf_w + c].
// Before raster_tile: depth = the format's far end, tri = -1, count = 0
// (count may be null: coverage is then not counted). Drawn forward
// (RasterParams::flat), tri is neither read nor written.
// float depth for every format but kDouble; that one rasters in double.
void raster_tile(const RasterParams& p, const TileJob& t, float* depth, int32_t* tri,
                 int32_t* count);
void raster_tile(const RasterParams& p, const TileJob& t, double* depth, int32_t* tri,
                 int32_t* count);

const char* target_name();

// The stored depth at a vertex of w = 1/z (see zbuffer_setup_kernels.cpp):
// affine in w, so in screen space; stored_depth before its rounding, with
// stored_depth's own operations (the constant denominator computed once, the
// same bits): the depth plane's error stays that of the reference's formula.
struct DepthMap {
  bool reversed = false;
  double near_z = 1, inv_near = 1, range = 1;
  DepthMap() = default;
  DepthMap(DepthFormat f, double n, double far)
      : reversed(f == DepthFormat::kReversed), near_z(n), inv_near(1 / n), range(1 / n - 1 / far) {}
  double operator()(double z, double w) const {
    return reversed ? near_z / z : (inv_near - w) / range;
  }
};
// A vertex's w = 1 / z and stored depth (DepthMap), worked out once per vertex
// by a set-up that shares vertices between triangles.
// (No initialisers, as ProjectedVertex's.)
struct VertexDepth {
  double w, q;
};

// The set-up's vertex step (zbuffer_setup.cpp): world -> eye space, the clip
// test and the snapped screen position, as view_scene's eye_from_world,
// inside_all and to_screen compute them, operation for operation in double (so
// the same bits), several vertices a vector.
// (No initialisers: project_vertices writes every field, and a frame's arrays
// of them, a vertex of the scene each, are not zeroed first.)
struct ProjectedVertex {
  double z;          // eye depth
  int32_t x, y;      // snapped (0 where not inside)
  uint8_t inside;    // within the hither plane and the guard band
};
struct Projection {
  double eye[3], right[3], up[3], forward[3];
  double near_z, g;              // hither, guard band slope
  double half_w, half_h, pitch;  // 0.5 width, 0.5 height, the camera's pitch
};
// With depth: also each vertex's VertexDepth in depth_out (the same operations
// as DepthMap's, so the same bits; where not inside, whatever).
void project_vertices(const Projection& p, const Vec3* world, size_t n, ProjectedVertex* out,
                      const DepthMap* depth = nullptr, VertexDepth* depth_out = nullptr);
// view_spheres' face test for the n triangles tri[i] = (a, b, c) of world
// (b and c swapped when flip): the unit normal normalize(cross(w_b - w_a,
// w_c - w_a)) in face[3 i .. 3 i + 2], and flags[i] = kNoFace when the cross
// product has length 0, else kFront when dot(normal, eye - w_a) > 0 (0: a back
// face). The same double operations, so the same bits.
inline constexpr uint8_t kNoFace = 1, kFront = 2;
void sphere_faces(const Vec3* world, const std::array<uint32_t, 3>* tri, size_t n, bool flip,
                  const Vec3& eye, double* face, uint8_t* flags);
// view_sphere's world culling by a unit sphere's faces (unit normals nx, ny,
// nz, plane distances h; the sphere's radius r, the eye e relative to its
// centre, sign -1 inside out): per face t < n, sd = sign ((nx e.x + ny e.y +
// nz e.z) - r h) (that operation order, in double), a back face by the margin
// when sd < -margin, a front face by it when sd > margin. Writes the faces
// that are not back faces by the margin to cand, in order, with kSureFace set
// on the front faces by the margin when mark_sure; returns their count. cand
// needs room for n + 16. A vector of faces at a time. With verts, each
// written face's three vertex indices too (verts.in[k][t] to verts.out[k], in
// the same order; room for n + 16 each), and in verts.unsure how many of the
// written faces are not front faces by the margin.
inline constexpr uint32_t kSureFace = 1u << 31;
struct FaceVertices {
  const uint32_t* in[3] = {};
  uint32_t* out[3] = {};
  size_t unsure = 0;
};
size_t sphere_face_codes(const double* nx, const double* ny, const double* nz, const double* h,
                         size_t n, const double e[3], double r, double sign, double margin,
                         bool mark_sure, uint32_t* cand, FaceVertices* verts = nullptr);
// Grows [lo, hi] by the n points, as scene_bounds does (std::min and std::max:
// a NaN coordinate is passed over), a vector of points at a time.
void grow_bounds(const Vec3* points, size_t n, Vec3& lo, Vec3& hi);
// The hidden spheres' occluders (zbuffer_occlusion.cpp's OcclusionMap::add): along a
// row of n rays (eye-space directions ((a0 + i) cell - half_w) pitch, dy, 1),
// where each enters the ball of centre ce (eye space) and radius^2 rho2, in eye
// depth: out[i] = z_occ for an inside-out ball, +inf for a ray that misses it
// (or meets it behind the eye). A vector of rays at a time.
void ball_entries(const double ce[3], double rho2, bool inverted, double z_occ, double pitch,
                  double half_w, double dy, int cell, int a0, int n, double* out);

// Where a frame's samples are: the sample offsets' extent (1/256 pixel from
// the pixel's corner) and the frame's size in pixels.
struct SampleGrid {
  int32_t ox0 = 128, ox1 = 128, oy0 = 128, oy1 = 128;
  int width = 0, height = 0;
  SampleGrid() = default;
  SampleGrid(const std::vector<std::array<int32_t, 2>>& offsets, int w, int h);
  // The pixels [i0, i1] x [j0, j1] (inclusive; i0 > i1 or j0 > j1: none) that may
  // have a sample in the snapped box [xmin, xmax] x [ymin, ymax].
  // (Pixels i with a sample 256 i + ox inside [xmin, xmax] for some offset ox:
  // floor and ceiling of a division by 256 are arithmetic shifts.)
  void pixels(int64_t xmin, int64_t xmax, int64_t ymin, int64_t ymax, int32_t& i0, int32_t& i1,
              int32_t& j0, int32_t& j1) const {
    static_assert(kSubpixel == 256);
    i0 = int32_t(std::max<int64_t>(0, (xmin - ox1 + 255) >> 8));
    i1 = int32_t(std::min<int64_t>(width - 1, (xmax - ox0) >> 8));
    j0 = int32_t(std::max<int64_t>(0, (ymin - oy1 + 255) >> 8));
    j1 = int32_t(std::min<int64_t>(height - 1, (ymax - oy0) >> 8));
  }
  // Whether the triangle of snapped vertices (x[k], y[k]) has one in its box.
  bool any(const int32_t x[3], const int32_t y[3]) const {
    int32_t i0, i1, j0, j1;
    pixels(std::min({x[0], x[1], x[2]}), std::max({x[0], x[1], x[2]}), std::min({y[0], y[1], y[2]}),
           std::max({y[0], y[1], y[2]}), i0, i1, j0, j1);
    return i0 <= i1 && j0 <= j1;
  }
};


// Triangles as a sink that needs only positions and depths takes them
// (TriSink::add_positions): triangle i has vertices a[i], b[i], c[i] (in the
// raster's order) of pv (snapped x and y) and vd (w and stored depth). a, b
// and c are readable to n rounded up to 16, valid vertex indices there too.
struct IndexedTris {
  const ProjectedVertex* pv = nullptr;
  const VertexDepth* vd = nullptr;
  const uint32_t *a = nullptr, *b = nullptr, *c = nullptr;
};
// Or as arrays of their vertices' fields: vertex k (in the raster's order) of
// triangle i at x[k][i], y[k][i] (snapped), w[k][i], q[k][i] (its VertexDepth);
// readable to n rounded up to 16 (whatever is there past n).
struct TriVertices {
  const int32_t *x[3] = {}, *y[3] = {};
  const double *w[3] = {}, *q[3] = {};
};
// The image's triangle step (view_scene's Emitter::triangle after world
// culling) for n triangles of vertices a[i], b[i], c[i] of pv, as the mesh
// lists them: dropped as degenerate (zero snapped area, counted), culled
// (positive area under projection culling, counted), without a sample of grid
// in its box or, one sample per pixel, small and covering none of its samples
// (CoversNothing; not counted), or hidden (with occ: every cell its box spans
// lies nearer than its nearest vertex, counted); the others are kept: moved to
// the front of a, b, c, with b and c swapped where the area is negative
// (view_scene's order), and tag[i] (the caller's) along with them, in order.
// Returns how many were kept. The arrays hold n rounded up to 16 (a, b, c:
// valid indices there too); a vector of triangles at a time.
struct TriangleCounts {
  uint64_t degenerate = 0, culled = 0, hidden = 0;
};
// The hidden spheres' map as triangle_step reads it (zbuffer_setup's
// OcclusionMap): per cell of kOcclusionCell^2 pixels, rows of nx cells, the
// eye depth beyond which everything with its samples in the cell is hidden;
// then from beyond[coarse] the same for cells twice as wide and high (rows of
// coarse_nx; each the largest of its four cells').
inline constexpr int kOcclusionCell = 4;
struct OcclusionCells {
  const double* beyond;
  int nx;
  int coarse;
  int coarse_nx;
};
size_t triangle_step(const ProjectedVertex* pv, uint32_t* a, uint32_t* b, uint32_t* c,
                     uint32_t* tag, size_t n, const SampleGrid& grid, bool cull_projection,
                     const OcclusionCells* occ, TriangleCounts& counts);
// The binner's set-up of n such triangles for the float raster drawn forward
// (opt::simd's set_up: box, edges, fill-rule biases, the depth and w planes;
// the flat colour 0, for set_flats), a vector of triangles at a time: the same
// double operations (no contraction), so the same bits. One sample per pixel,
// a small triangle that covers no sample gets an empty box (never binned)
// unless tested: they were all sorted out before (triangle_step).
// (The triangles' vertices gathered from their arrays: no copy of them first.)
void set_up_forward(const IndexedTris& tris, size_t n, const SampleGrid& grid, TriSetup* out,
                    bool tested = false);
void set_up_forward(const TriVertices& tris, size_t n, const SampleGrid& grid, TriSetup* out,
                    bool tested = false);
// The same set-ups (tested), and for shading from vertex normals (Phong and
// the like) each triangle's four attribute planes (ShadeTri's rows 0-3: a0,
// ax, ay each): w, then vertex v's normal normal[v] (negated where negate)
// times w under perspective, else as it is, with opt::simd's set_up_shading's
// double operations (so the same bits). Where they go: a triangle whose box
// lies in one tile (tiles of 2^tw_log2 x 2^th_log2 pixels) gets them moved to
// that tile, local[i].p, as shade_one_tile moves them (the same bits); any
// other gets them in double, 12 a triangle at planes + 12 i, for each of its
// tiles to move; ready[i] says which (1: in local). (local[i].tri is left to
// the caller.)
struct ShadedPlanes {
  TilePlanes* local = nullptr;
  uint8_t* ready = nullptr;
  double* planes = nullptr;
  int tw_log2 = 6, th_log2 = 6;
};
void set_up_shaded(const IndexedTris& tris, size_t n, const SampleGrid& grid, TriSetup* out,
                   const Vec3* normal, bool negate, bool perspective, const ShadedPlanes& to);

// The image's polygon step (view_scene_chunks, positions only: flat shading
// drawn forward) for a run of polygons that are one triangle each, with their
// own three vertices (add_polygon's layout): polygon i's plane at plane[i], its
// triangle's vertices (in the mesh's order) 3i, 3i + 1, 3i + 2 of world,
// projected here (project_vertices' operations, with depth: no ProjectedVertex
// or VertexDepth is written). Per polygon, as view_scene_chunks' scalar loop: a zero face normal is
// passed over uncounted; then a triangle is counted, culled in world space
// (cull_world) or, by the sign of its snapped area, in projection space
// (cull_projection) or left out as degenerate (zero area) or without a sample
// of grid in its box; the others are kept: appended to out (at out.kept) in
// the raster's order with their flat colour's inputs (the centroid, the face
// normal). Whole vectors of polygons only, and none with a vertex outside the
// hither plane or the guard band (those need clipping: view_polygons): returns
// how many polygons were done, a multiple of the lanes, stopping before the
// first vector that has such a polygon. out's arrays need room for
// out.kept + n + 16 entries. The same double operations as the scalar loop,
// so the same bits; the vertices read in order (loads, not gathers).
struct PolygonRun {
  const double* plane = nullptr;  // (n, d): 4 doubles a polygon, Plane's layout
  const Vec3* world = nullptr;
  const Projection* proj = nullptr;
  const DepthMap* depth = nullptr;
  size_t n = 0;
  bool cull_world = false, cull_projection = false;  // (false for two-sided faces)
};
struct PolygonRunOut {
  int32_t *x[3] = {}, *y[3] = {};
  double *w[3] = {}, *q[3] = {};
  double *centroid[3] = {}, *face[3] = {};
  size_t kept = 0;
  uint64_t scene_tris = 0, culled = 0, degenerate = 0;
};
size_t polygon_run(const PolygonRun& run, const SampleGrid& grid, PolygonRunOut& out);

// What add_shaded needs besides the positions: vertex v's shading normal is
// normal[v] (negated where negate: an inside-out sphere), triangle i's face
// normal (of its drawn side) face[0..2][i]; every triangle has the material
// (an index into Scene::materials and ShadeParams::materials) material.
struct ShadedTris {
  const Vec3* normal = nullptr;
  bool negate = false;
  const double* face[3] = {};
  uint32_t material = 0;
};

// Where the image path's set-up puts its triangles one at a time, instead of
// keeping them in ScreenTri chunks (opt::simd::zbuffer's binner). Triangles
// come chunk by chunk (each chunk's in mesh order, the chunks in mesh order),
// a chunk from one thread at a time, different chunks from several at once.
class TriSink {
 public:
  virtual ~TriSink() = default;
  // First: the frame (camera, size, near and far; no triangles) and the number of chunks.
  virtual void begin(const ScreenMesh& frame, size_t chunks) = 0;
  // Room for about n triangles in chunk c (a hint).
  virtual void reserve(size_t c, size_t n) = 0;
  // Chunk c's next triangle (t is only read during the call); its index in the
  // chunk. d: its vertices' VertexDepth (DepthMap(settings' depth, frame's near
  // and far)), or null for the sink to work them out.
  virtual size_t add(size_t c, const ScreenTri& t, const VertexDepth* d) = 0;
  // Whether the sink reads nothing of a triangle but its positions and depths
  // (flat shading drawn forward): then the set-up may hand them over n at a
  // time, add_positions (chunk c's next n triangles; the index of the first;
  // tested: none is a small triangle that covers no sample, triangle_step).
  virtual bool positions_only() const { return false; }
  virtual size_t add_positions(size_t c, const IndexedTris& t, size_t n, bool tested = false) = 0;
  virtual size_t add_positions(size_t c, const TriVertices& t, size_t n, bool tested = false) = 0;
  // Whether the sink shades from vertex normals alone (Phong, Blinn-Phong,
  // toon; the float raster): then a sphere's triangles may come n at a time,
  // add_shaded (as add_positions, tested: chunk c's next n triangles; the
  // index of the first), with what shading needs besides their positions.
  virtual bool shaded_bulk() const { return false; }
  virtual size_t add_shaded(size_t c, const IndexedTris& t, size_t n, const ShadedTris& s) = 0;
  // The flat colours of chunk c's triangles at[0], ..., at[n - 1], lit after
  // add: triangle at[i]'s is (rgb[0][i], rgb[1][i], rgb[2][i]).
  virtual void set_flats(size_t c, const size_t* at, size_t n, const float* const rgb[3]) = 0;
};

// What the z-buffer's image needs of the set-up, and no more: the triangles
// with a sample of grid in their bounding box (the others would cover
// nothing), handed to sink, their flat colours lit together in SIMD (flat_colors with
// light), as the image is shaded.
struct ImageOnly {
  SampleGrid grid;
  ShadeParams light;  // the lights and the eye
  TriSink* sink = nullptr;
};

// opt::simd::view_scene's mesh, left in the set-up's chunks: mesh holds the
// frame, near, far and counts (no triangles); chunks the triangles, in mesh
// order (spheres' chunks, then polygons'), every one of view_scene's, bit for
// bit. With image: only what it needs, to image->sink (chunks is left empty;
// the counts are still view_scene's).
void view_scene_chunks(const Scene& scene, int width, int height, const RasterSettings& s,
                       int threads, ScreenMesh& mesh, std::vector<std::vector<ScreenTri>>& chunks,
                       const ImageOnly* image = nullptr);

}  // namespace lockstep::opt::zsimd
