// The optimized z-buffer's set-up: ref::view_scene's screen mesh, bit for bit,
// in less time (declared in optimized/zbuffer/zbuffer_simd.h). This file is its chunk driver
// (view_scene_chunks: the frame, the vertices, spheres and polygons in parallel
// chunks, the image's sink); one sphere's set-up is zbuffer_spheres.cpp, the
// hidden spheres' occlusion map zbuffer_occlusion.h/.cpp, the parts they share
// zbuffer_setup.h, the vector steps zbuffer_setup_kernels.cpp.
//
// view_scene_chunks runs these steps in order, each a member of Setup (the
// state they share):
//   frame            the scene's bounds, view_frame, the projection, the depth map
//   ring_counts      each sphere's ring count (0: outside the view), in parallel
//   unit_spheres     one unit sphere and its faces per ring count in use
//   occluders        the image: the hidden spheres' occlusion map
//   plan_chunks      spheres and polygons per chunk; the sink's begin
//   spheres          the spheres' chunks in parallel (sphere_chunk), their counts
//   polygon_vertices every polygon vertex projected once; the runs of triangles
//   polygons         the polygons' chunks in parallel (PolygonChunk), their counts
//   cones            view_scene's own step, one chunk after the polygons'
// PolygonChunk takes one chunk of polygons: polygon (the scalar loop), clipped
// (view_polygons on a polygon that may need clipping), simd_run (polygon_run
// on a run of single-triangle polygons), flush (the pending run to the sink).
//
// view_scene (core/viewing.cpp) transforms, tests and projects every
// triangle's three vertices on their own, one triangle after another. Here:
//   * every scene vertex is moved to eye space and snapped once, in parallel,
//     with the very same double operations (so the same bits): a vertex shared
//     by six triangles is projected once, not six times;
//   * polygons are set up in parallel chunks (TBB), each chunk writing its own
//     triangles, which are then concatenated in scene order;
//   * everything else (culling in world or projection space, the flat colour
//     per polygon, the Gouraud colour per vertex, the degenerate and culled
//     counts) is the reference's arithmetic, operation for operation.
// Spheres: one unit sphere per ring count in use (not sines and cosines per
// sphere), then chunks of spheres in parallel, each sphere's vertices projected
// once and its triangles built in place (view_spheres copies three vertices a
// triangle, twice). Only the common case is done here: a sphere or polygon with
// a vertex outside the hither plane or the guard band (a triangle that may need
// clipping) goes through view_scene's own step (lockstep::view_spheres,
// view_polygons) on its own, in its chunk, so the result is always view_scene's.
// The vertex projection, the scene bounds and the spheres' face tests run in
// Highway kernels (zbuffer_setup_kernels.cpp) with the same double operations.
// For the z-buffer's image (ImageOnly) the triangles go to a TriSink instead
// (one at a time, or as positions a sphere or a run of polygons at a time when
// the sink needs no more), without those that have no sample in their box and
// those hidden behind nearer spheres (OcclusionMap: the same image), and flat
// colours are lit per chunk in SIMD (double lanes, within 1e-7 of view_scene's).
// Spheres' clear back faces (world culling) are found from the unit sphere's
// face normals and counted without the world face test; for the image, clear
// front faces take the unit normal too (the world test runs near the silhouette).
// For the image drawn forward (positions only), runs of 16 or more polygons
// that are one triangle each with their own vertices (the SPD meshes) skip the
// scalar loop: polygon_run projects their vertices and takes the loop's steps
// 8 polygons at a time, reading the vertices in order (no gathers), and hands
// the kept triangles over as arrays of vertex fields (TriVertices).
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "core/shading.h"
#include "optimized/zbuffer/zbuffer_simd.h"
#include "optimized/tiling.h"
#include "optimized/zbuffer/zbuffer_setup.h"
#include "optimized/zbuffer/zbuffer_simd_kernels.h"

namespace lockstep::opt::zsimd {

namespace {

// core/viewing.cpp's eye_from_world, operation for operation.
Vec3 eye_from_world(const Camera& c, const Vec3& p) {
  const Vec3 d = p - c.eye;
  return {dot(d, c.right), dot(d, c.up), dot(d, c.forward)};
}

struct Chunk {
  std::vector<ScreenTri> tris;
  uint64_t scene_tris = 0, culled = 0, degenerate = 0, clipped = 0;
  ScreenMesh drops;  // only its dropped counts (view_polygons' reasons)
};

constexpr int kMaxRings = 256;  // sphere_rings' upper end

// Triangles for a positions-only sink, n of them, as arrays of their vertices'
// fields (TriVertices), with a vector's slack past the last.
struct PackedTris {
  std::vector<int32_t> x[3], y[3];
  std::vector<double> w[3], q[3];
  size_t n = 0;
  // Room for m more (and 16 entries of slack past them: the set-up reads
  // whole vectors, polygon_run's compressed stores may write one).
  void room(size_t m) {
    const size_t need = n + m + 16;
    if (need <= x[0].size()) return;
    const size_t cap = std::max(need, 2 * x[0].size());
    for (int k = 0; k < 3; ++k) x[k].resize(cap), y[k].resize(cap), w[k].resize(cap), q[k].resize(cap);
  }
  // The triangle of vertices v[0], v[1], v[2] (in the raster's order).
  void push(const ProjectedVertex* pv, const VertexDepth* vd, const uint32_t v[3]) {
    room(1);
    for (int k = 0; k < 3; ++k) {
      x[k][n] = pv[v[k]].x, y[k][n] = pv[v[k]].y;
      w[k][n] = vd[v[k]].w, q[k][n] = vd[v[k]].q;
    }
    ++n;
  }
  TriVertices view() const {
    TriVertices t;
    for (int k = 0; k < 3; ++k)
      t.x[k] = x[k].data(), t.y[k] = y[k].data(), t.w[k] = w[k].data(), t.q[k] = q[k].data();
    return t;
  }
};

// The end of the run of polygons from p (before last) that are one triangle
// each with their own three vertices in order (add_polygon's layout for a
// triangle), of p's material: polygon_run's input.
uint32_t triangle_run(const Scene& scene, uint32_t p, uint32_t last) {
  const uint32_t material = scene.poly_material[p];
  uint32_t q = p;
  for (; q < last; ++q) {
    const uint32_t f = scene.poly_first[q], t = scene.poly_tri_first[q];
    if (scene.poly_first[q + 1] != f + 3 || scene.poly_tri_first[q + 1] != t + 1 ||
        scene.poly_material[q] != material)
      break;
    const auto& v = scene.tri_vertex[t];
    if (v[0] != f || v[1] != f + 1 || v[2] != f + 2) break;
  }
  return q;
}

}  // namespace

SampleGrid::SampleGrid(const std::vector<std::array<int32_t, 2>>& offsets, int w, int h)
    : ox0(kSubpixel), ox1(0), oy0(kSubpixel), oy1(0), width(w), height(h) {
  for (const auto& o : offsets) {
    ox0 = std::min(ox0, o[0]), ox1 = std::max(ox1, o[0]);
    oy0 = std::min(oy0, o[1]), oy1 = std::max(oy1, o[1]);
  }
}


namespace {

// Hands tris[first..] with a sample of the image's grid in their box to its
// sink (chunk c), and removes them all from tris.
void to_sink(const ImageOnly& image, size_t c, std::vector<ScreenTri>& tris, size_t first) {
  for (size_t i = first; i < tris.size(); ++i) {
    const ScreenTri& t = tris[i];
    const int32_t x[3] = {t.v[0].x, t.v[1].x, t.v[2].x}, y[3] = {t.v[0].y, t.v[1].y, t.v[2].y};
    if (image.grid.any(x, y)) image.sink->add(c, t, nullptr);
  }
  tris.resize(first);
}

// view_scene_chunks' state, shared by its steps: one member function a step,
// run in the order declared (the file's header lists them).
struct Setup {
  Setup(const Scene& scene, int width, int height, const RasterSettings& s, int threads,
        ScreenMesh& mesh, std::vector<std::vector<ScreenTri>>& out_chunks, const ImageOnly* image)
      : scene(scene),
        width(width),
        height(height),
        s(s),
        image(image),
        mesh(mesh),
        out_chunks(out_chunks),
        arena(resolve_threads(threads)) {}

  void frame();             // the frame, near and far; the projection, the stored depth
  void ring_counts();       // each sphere's ring count (0: outside the view), eye centre
  void unit_spheres();      // one unit sphere per ring count in use
  void occluders();         // the image: the hidden spheres' occlusion map
  void plan_chunks();       // how many spheres and polygons a chunk; the sink's begin
  void spheres();           // the spheres' chunks in parallel, then their counts
  void polygon_vertices();  // every polygon vertex projected once (and the runs)
  void polygons();          // the polygons' chunks in parallel (PolygonChunk)
  void cones();             // view_scene's own step, in one chunk after the polygons'

  void sphere_chunk(size_t c);
  // The vertices of polygons [p0, p1).
  void project(uint32_t p0, uint32_t p1) {
    const uint32_t v0 = scene.poly_first[p0], v1 = scene.poly_first[p1];
    if (v1 > v0)
      project_vertices(proj, scene.vertex.data() + v0, v1 - v0, pv.data() + v0,
                       image ? &depth_map : nullptr, image ? pvd.data() + v0 : nullptr);
  }

  // The call's.
  const Scene& scene;
  const int width, height;
  const RasterSettings& s;
  const ImageOnly* const image;
  ScreenMesh& mesh;
  std::vector<std::vector<ScreenTri>>& out_chunks;
  tbb::task_arena arena;
  // frame()
  const Camera& cam = mesh.camera;  // (set by frame())
  double near_z = 0, g = 0;
  DepthMap depth_map;  // the image's stored depth (its sink's: the same operations, the same bits)
  Projection proj;     // of the vertices (spheres' and polygons')
  // The frame alone (no triangles, no counts), for view_polygons on one polygon.
  ScreenMesh frame_only;
  // ring_counts(), unit_spheres(), occluders()
  uint32_t spheres_n = 0;
  std::vector<int> rings;
  std::vector<Vec3> centre;  // eye space
  std::vector<UnitSphere> units;
  std::vector<UnitFaces> faces;  // per ring count
  std::optional<OcclusionMap> occlusion;
  // plan_chunks()
  uint32_t spheres_per_chunk = 1;
  std::vector<ScreenMesh> sphere_chunks;
  uint32_t polys = 0, per_chunk = 1, nchunks = 0;
  bool with_cones = false;
  // polygon_vertices()
  std::vector<ProjectedVertex, NoInitAllocator<ProjectedVertex>> pv;
  std::vector<VertexDepth, NoInitAllocator<VertexDepth>> pvd;  // the image's, per vertex
  bool positions = false;                                      // a positions-only sink
  std::vector<std::vector<std::array<uint32_t, 2>>> runs;      // per chunk: [begin, end)
};

// One chunk of polygons, c (Setup::polygons): its triangles to out (or to the
// image's sink), polygon by polygon (polygon), a polygon that may need
// clipping through view_polygons (clipped), the runs of single-triangle
// polygons a vector at a time (simd_run).
class PolygonChunk {
 public:
  PolygonChunk(Setup& up, uint32_t c, Chunk& out)
      : up(up),
        scene(up.scene),
        s(up.s),
        image(up.image),
        out(out),
        c(c),
        sink_chunk(up.sphere_chunks.size() + c),
        first(c * up.per_chunk),
        last(std::min(up.polys, first + up.per_chunk)),
        surface(scene.materials.empty() ? Material{} : scene.materials[0]) {}

  void all();

 private:
  void flush();
  void polygon(uint32_t p);
  void clipped(uint32_t p);
  void simd_run(uint32_t& p, uint32_t run_end);

  Setup& up;
  const Scene& scene;
  const RasterSettings& s;
  const ImageOnly* const image;
  Chunk& out;
  const uint32_t c;
  const size_t sink_chunk;
  const uint32_t first, last;
  FlatBatch batch;
  ScreenTri local;
  // A positions-only sink gets the triangles a run at a time (flushed before a
  // polygon that goes through view_polygons, so that the order stays).
  // (The pending triangles' vertices in the raster's order.)
  PackedTris pending;
  // The lighting's inputs of the last material seen (meshes share one).
  uint32_t surface_of = UINT32_MAX;
  FlatBatch::Surface surface;
};

void PolygonChunk::flush() {
  const size_t n = pending.n;
  if (n == 0) return;
  const size_t at = image->sink->add_positions(sink_chunk, pending.view(), n);
  batch.offset_last(n, at);
  pending.n = 0;
}

// A vertex outside the hither plane or the guard band: a triangle may need
// clipping, so view_scene's own polygon step, on this polygon. So does a
// polygon without a normal (rare): view_polygons says whether it was dropped
// for range or had no area.
void PolygonChunk::clipped(uint32_t p) {
  if (up.positions) flush();
  ScreenMesh part = up.frame_only;
  lockstep::view_polygons(scene, s, p, p + 1, part);
  if (image)
    to_sink(*image, sink_chunk, part.tris, 0);
  else
    out.tris.insert(out.tris.end(), part.tris.begin(), part.tris.end());
  out.scene_tris += part.scene_tris;
  out.culled += part.culled;
  out.degenerate += part.degenerate;
  out.clipped += part.clipped;
  out.drops.add_dropped(part);
}

void PolygonChunk::polygon(uint32_t p) {
  const Camera& cam = up.cam;
  const auto& pv = up.pv;
  const Material& m = scene.materials[scene.poly_material[p]];
  if (scene.poly_material[p] != surface_of)
    surface = FlatBatch::Surface(m), surface_of = scene.poly_material[p];
  const Vec3 face = scene.poly_plane[p].n;
  const uint32_t t_first = scene.poly_tri_first[p], t_last = scene.poly_tri_first[p + 1];
  bool inside = dot(face, face) != 0;  // length(face) == 0, without the square root
  for (uint32_t t = t_first; t < t_last; ++t)
    for (const uint32_t vi : scene.tri_vertex[t]) inside = inside && pv[vi].inside;
  if (!inside) {
    clipped(p);
    return;
  }
  // The flat colour, lit when the first triangle is kept (the same bits as
  // view_polygons' up-front evaluation); for the image, each kept triangle
  // asks for the polygon's colour, lit in SIMD.
  Vec3 flat, centroid;
  bool flat_lit = s.shading != Shading::kFlat;
  auto light_flat = [&] {
    for (const Vec3& x : scene.polygon_vertices(p)) centroid += x;
    centroid = centroid / double(scene.polygon_vertices(p).size());
    if (!image) flat = lit(scene, m, cam.eye, centroid, face);
    flat_lit = true;
  };
  const bool patch = scene.poly_is_patch[p] != 0;
  const bool two_sided = m.two_sided();
  for (uint32_t t = t_first; t < t_last; ++t) {
    ++out.scene_tris;
    const auto& tv = scene.tri_vertex[t];
    // World-space culling (view_scene's Emitter::triangle).
    const Vec3& w0 = scene.vertex[tv[0]];
    const bool front = dot(face, cam.eye - w0) > 0;
    if (!front && !two_sided && s.cull == CullMode::kWorld) {
      ++out.culled;
      continue;
    }
    // The snapped area: degenerate, projection-space culling (a front face is
    // counter-clockwise as seen, negative area with y down), the order.
    const ProjectedVertex &q0 = pv[tv[0]], &q1 = pv[tv[1]], &q2 = pv[tv[2]];
    const int64_t area =
        int64_t(q1.x - q0.x) * (q2.y - q0.y) - int64_t(q1.y - q0.y) * (q2.x - q0.x);
    if (area == 0) {
      ++out.degenerate;
      continue;
    }
    if (area > 0 && !two_sided && s.cull == CullMode::kProjection) {
      ++out.culled;
      continue;
    }
    if (image) {
      const int32_t x[3] = {q0.x, q1.x, q2.x}, y[3] = {q0.y, q1.y, q2.y};
      if (!image->grid.any(x, y)) continue;
    }
    if (!flat_lit) light_flat();
    // Positive area: a front face's v[1] and v[2] swapped.
    const uint32_t order[3] = {tv[0], area < 0 ? tv[2] : tv[1], area < 0 ? tv[1] : tv[2]};
    if (up.positions) {  // (flat shading: one lighting request each)
      pending.push(pv.data(), up.pvd.data(), order);
      batch.add(pending.n - 1, centroid, face, surface);
      continue;
    }
    // Built in place (a ScreenTri is 300 bytes), or for the image in `local`
    // (every field it reads is written for each triangle).
    ScreenTri& st = image ? local : out.tris.emplace_back();
    for (int i = 0; i < 3; ++i) {
      const uint32_t vi = order[i];
      ScreenVertex& v = st.v[size_t(i)];
      v.x = pv[vi].x;
      v.y = pv[vi].y;
      v.z = pv[vi].z;
      v.world = scene.vertex[vi];
      v.normal = patch ? scene.vertex_normal[vi] : face;
      if (s.shading == Shading::kGouraud) v.color = lit(scene, m, cam.eye, v.world, v.normal);
    }
    st.prim = scene.sphere_count() + p;
    st.source_tri = t;
    st.flat_color = flat;
    st.face_normal = front ? face : -face;
    if (image) {
      const VertexDepth d[3] = {up.pvd[order[0]], up.pvd[order[1]], up.pvd[order[2]]};
      const size_t at = image->sink->add(sink_chunk, st, d);
      if (s.shading == Shading::kFlat) batch.add(at, centroid, face, surface);
    }
  }
}

// A run of single-triangle polygons [p, run_end) (positions only):
// polygon_run, a vector of polygons at a time, then polygon by polygon past
// what it did (the run's tail, or the vector holding a polygon that may need
// clipping), their vertices projected first. p ends at run_end.
void PolygonChunk::simd_run(uint32_t& p, uint32_t run_end) {
  const uint32_t material = scene.poly_material[p];
  if (material != surface_of)
    surface = FlatBatch::Surface(scene.materials[material]), surface_of = material;
  const bool two_sided = scene.materials[material].two_sided();
  while (p < run_end) {
    static_assert(sizeof(Plane) == 4 * sizeof(double) && offsetof(Plane, n) == 0);
    PolygonRun run;
    run.plane = &scene.poly_plane[p].n.x;
    run.world = scene.vertex.data() + scene.poly_first[p];
    run.proj = &up.proj;
    run.depth = &up.depth_map;
    run.n = run_end - p;
    run.cull_world = !two_sided && s.cull == CullMode::kWorld;
    run.cull_projection = !two_sided && s.cull == CullMode::kProjection;
    pending.room(run.n);
    batch.room(run.n);
    PolygonRunOut got;
    for (int k = 0; k < 3; ++k) {
      got.x[k] = pending.x[k].data() + pending.n, got.y[k] = pending.y[k].data() + pending.n;
      got.w[k] = pending.w[k].data() + pending.n, got.q[k] = pending.q[k].data() + pending.n;
      got.centroid[k] = batch.plane(k), got.face[k] = batch.plane(3 + k);
    }
    const size_t done = polygon_run(run, image->grid, got);
    batch.added(got.kept, pending.n, surface);
    pending.n += got.kept;
    out.scene_tris += got.scene_tris;
    out.culled += got.culled;
    out.degenerate += got.degenerate;
    p += uint32_t(done);
    const uint32_t stop = std::min(run_end, p + 16);
    up.project(p, stop);
    while (p < stop) polygon(p++);
  }
}

// The chunk, in polygon order: its runs (Setup::polygon_vertices found them)
// through simd_run, the other polygons through polygon.
void PolygonChunk::all() {
  const size_t expect = size_t(scene.poly_tri_first[last] - scene.poly_tri_first[first]);
  if (image) {
    image->sink->reserve(sink_chunk, expect);
    if (s.shading == Shading::kFlat) batch.reserve(expect);
  } else {
    out.tris.reserve(expect);
  }
  const auto& chunk_runs = up.runs[c];
  size_t next_run = 0;
  for (uint32_t p = first; p < last;) {
    if (next_run == chunk_runs.size() || p != chunk_runs[next_run][0]) {
      polygon(p++);
      continue;
    }
    simd_run(p, chunk_runs[next_run++][1]);
  }
  if (up.positions) flush();
  if (image) batch.light(image->light, *image->sink, sink_chunk);
}

void Setup::frame() {
  // The frame, near and far: view_scene's own step.
  // (scene_bounds' answer, exact in any order: the spheres as it grows by them,
  // the vertices a vector at a time.)
  Vec3 lo{kInfinity, kInfinity, kInfinity}, hi = -lo;
  for (uint32_t i = 0; i < scene.sphere_count(); ++i) {
    const Vec3& p = scene.sphere_center[i];
    const double r = std::abs(scene.sphere_radius[i]);
    for (int k = 0; k < 3; ++k)
      lo[k] = std::min(lo[k], p[k] - r), hi[k] = std::max(hi[k], p[k] + r);
  }
  grow_bounds(scene.vertex.data(), scene.vertex.size(), lo, hi);
  for (uint32_t i = 0; i < scene.cone_count(); ++i)  // as scene_bounds grows by them
    for (const auto& [p, r] :
         {std::pair{scene.cone_base[i], scene.cone_r0[i]}, {scene.cone_apex[i], scene.cone_r1[i]}})
      for (int k = 0; k < 3; ++k)
        lo[k] = std::min(lo[k], p[k] - r), hi[k] = std::max(hi[k], p[k] + r);
  mesh = lockstep::view_frame(scene, width, height, lo, hi);

  near_z = mesh.near_z, g = kGuardBand * cam.pitch;
  depth_map = DepthMap(s.depth, mesh.near_z, mesh.far_z);
  for (int c = 0; c < 3; ++c) {
    proj.eye[c] = cam.eye[c], proj.right[c] = cam.right[c], proj.up[c] = cam.up[c];
    proj.forward[c] = cam.forward[c];
  }
  proj.near_z = near_z, proj.g = g, proj.pitch = cam.pitch;
  proj.half_w = 0.5 * cam.width, proj.half_h = 0.5 * cam.height;
  frame_only.camera = cam;
  frame_only.width = width;
  frame_only.height = height;
  frame_only.near_z = mesh.near_z;
  frame_only.far_z = mesh.far_z;
}

// Spheres, as view_spheres: each sphere's ring count first (0: outside the
// view), then one unit sphere per ring count in use (the sines and cosines
// once per frame, not once per sphere), then chunks of spheres in parallel,
// each into its own mesh; the chunks' triangles then follow one another in
// sphere order, as in view_scene.
void Setup::ring_counts() {
  spheres_n = scene.sphere_count();
  rings.assign(spheres_n, 0);
  centre.resize(spheres_n);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, spheres_n, 1024),
                      [&](const tbb::blocked_range<uint32_t>& r) {
                        for (uint32_t k = r.begin(); k < r.end(); ++k) {
                          const double radius = std::abs(scene.sphere_radius[k]);
                          const Vec3 ce = eye_from_world(cam, scene.sphere_center[k]);
                          centre[k] = ce;
                          if (!sphere_outside(cam, ce, radius, near_z))
                            rings[k] = sphere_rings(radius, ce.z, cam, near_z, s.tess_error);
                        }
                      });
  });
}

void Setup::unit_spheres() {
  units.resize(kMaxRings + 1);
  faces.resize(kMaxRings + 1);
  std::vector<char> used(kMaxRings + 1, 0);
  for (const int n : rings) used[size_t(n)] = 1;
  std::vector<int> counts;
  for (int n = 1; n <= kMaxRings; ++n)
    if (used[size_t(n)]) counts.push_back(n);
  arena.execute([&] {
    tbb::parallel_for(size_t(0), counts.size(), [&](size_t i) {
      const size_t n = size_t(counts[i]);
      units[n] = unit_sphere(counts[i]);
      faces[n] = unit_faces(units[n]);
    });
  });
}

// The image: the hidden spheres' occluders (every sphere's inner ball), before
// any sphere is tessellated.
void Setup::occluders() {
  if (!(image && s.skip_hidden &&
        std::any_of(rings.begin(), rings.end(), [](int n) { return n != 0; })))
    return;
  occlusion.emplace(cam, width, height, near_z, mesh.far_z);
  for (uint32_t k = 0; k < spheres_n; ++k)
    if (rings[k] != 0)
      occlusion->add(centre[k], std::abs(scene.sphere_radius[k]), !(scene.sphere_radius[k] > 0),
                     faces[size_t(rings[k])].inner);
  occlusion->finish();
}

void Setup::plan_chunks() {
  // At most 16 spheres a chunk (a few big spheres are as much work as many
  // small ones), at most 64 chunks (each chunk gets its own bins per tile).
  spheres_per_chunk =
      std::max({1u, std::min<uint32_t>(16, (spheres_n + 7) / 8), (spheres_n + 63) / 64});
  sphere_chunks.resize((spheres_n + spheres_per_chunk - 1) / spheres_per_chunk);
  // Polygons: 16 chunks or more (after the spheres' chunks, for the sink), of
  // 512 to 4096 polygons (each chunk has its own buffers and its own bins per
  // tile: 2048 rather than 512 for sombrero-3's 32k, 5% faster frames).
  polys = scene.polygon_count();
  per_chunk = std::clamp<uint32_t>((polys + 15) / 16, 512, 4096);
  nchunks = (polys + per_chunk - 1) / per_chunk;
  // Cones (few: 7 to 54 in the SPD scenes): view_scene's own step, in one
  // chunk after the polygons' (the scene's primitive order).
  with_cones = scene.cone_count() > 0;
  if (image) image->sink->begin(mesh, sphere_chunks.size() + nchunks + (with_cones ? 1 : 0));
}

void Setup::sphere_chunk(size_t c) {
  ScreenMesh& part = sphere_chunks[c];
  part.camera = cam;
  part.width = width;
  part.height = height;
  part.near_z = mesh.near_z;
  part.far_z = mesh.far_z;
  const uint32_t first = uint32_t(c) * spheres_per_chunk;
  const uint32_t last = std::min(spheres_n, first + spheres_per_chunk);
  SphereScratch scratch;
  FlatBatch batch;
  // About half of each sphere's triangles face the eye.
  size_t expect = 0;
  for (uint32_t k = first; k < last; ++k)
    if (rings[k] != 0) expect += units[size_t(rings[k])].tri.size() / 2 + 1;
  if (image) {
    image->sink->reserve(c, expect);
    if (s.shading == Shading::kFlat) batch.reserve(expect);
  } else
    part.tris.reserve(expect);
  for (uint32_t k = first; k < last; ++k) {
    if (rings[k] == 0) continue;
    // A sphere hidden whole: counted as tessellated, not tessellated.
    if (occlusion) {
      int i0, i1, j0, j1;
      const double r = std::abs(scene.sphere_radius[k]);
      if (occlusion->sphere_box(centre[k], r, i0, i1, j0, j1) &&
          occlusion->hidden(i0, i1, j0, j1, centre[k].z - r)) {
        const uint64_t n = units[size_t(rings[k])].tri.size();
        part.sphere_tris += n;
        part.hidden += n;
        continue;
      }
    }
    // A sphere crossing the hither plane or the guard band: view_spheres itself.
    if (!view_sphere(scene, s, cam, proj, k, units[size_t(rings[k])], faces[size_t(rings[k])],
                     image, depth_map, occlusion ? &*occlusion : nullptr, c, batch, scratch,
                     part)) {
      const size_t before = part.tris.size();
      lockstep::view_spheres(scene, s, k, k + 1, part);
      if (image) to_sink(*image, c, part.tris, before);
    }
  }
  if (image) batch.light(image->light, *image->sink, c);
}

void Setup::spheres() {
  arena.execute([&] {
    tbb::parallel_for(size_t(0), sphere_chunks.size(), [&](size_t c) { sphere_chunk(c); });
  });
  for (ScreenMesh& part : sphere_chunks) {
    mesh.sphere_tris += part.sphere_tris;
    mesh.culled += part.culled;
    mesh.clipped += part.clipped;
    mesh.degenerate += part.degenerate;
    mesh.hidden += part.hidden;
    mesh.add_dropped(part);
    if (!part.tris.empty()) out_chunks.push_back(std::move(part.tris));
  }
}

// Every polygon vertex once: eye space, the clip test, the snapped screen
// position (and for the image w and the stored depth), a chunk of polygons
// at a time; for a positions-only sink, not those of the chunk's runs of 16
// or more single-triangle polygons (triangle_run): polygon_run projects them
// itself, from the world coordinates it reads anyway (the same operations).
// (A polygon's vertices are its own: vertex[poly_first[p] .. poly_first[p + 1]).)
void Setup::polygon_vertices() {
  pv.resize(scene.vertex.size());
  pvd.resize(image ? scene.vertex.size() : 0);
  positions = image && image->sink->positions_only();
  runs.resize(nchunks);
  arena.execute([&] {
    tbb::parallel_for(uint32_t(0), nchunks, [&](uint32_t c) {
      const uint32_t first = c * per_chunk, last = std::min(polys, first + per_chunk);
      uint32_t projected = first;  // (up to)
      for (uint32_t p = first; positions && p < last;) {
        const uint32_t end = triangle_run(scene, p, last);
        if (end - p < 16) {
          p = std::max(end, p + 1);
          continue;
        }
        project(projected, p);
        runs[c].push_back({p, end});
        projected = p = end;
      }
      project(projected, last);
    });
  });
}

void Setup::polygons() {
  std::vector<Chunk> chunks(nchunks);
  arena.execute([&] {
    tbb::parallel_for(uint32_t(0), nchunks,
                      [&](uint32_t c) { PolygonChunk(*this, c, chunks[c]).all(); });
  });
  for (Chunk& c : chunks) {
    mesh.scene_tris += c.scene_tris;
    mesh.culled += c.culled;
    mesh.degenerate += c.degenerate;
    mesh.clipped += c.clipped;
    mesh.add_dropped(c.drops);
    out_chunks.push_back(std::move(c.tris));
  }
}

void Setup::cones() {
  if (!with_cones) return;
  ScreenMesh part = frame_only;
  lockstep::view_cones(scene, s, 0, scene.cone_count(), part);
  mesh.cone_tris += part.cone_tris;
  mesh.culled += part.culled;
  mesh.degenerate += part.degenerate;
  mesh.clipped += part.clipped;
  if (image) {
    const size_t sink_chunk = sphere_chunks.size() + nchunks;
    image->sink->reserve(sink_chunk, part.tris.size());
    to_sink(*image, sink_chunk, part.tris, 0);
  } else {
    out_chunks.push_back(std::move(part.tris));
  }
}

}  // namespace

void view_scene_chunks(const Scene& scene, int width, int height, const RasterSettings& s,
                       int threads, ScreenMesh& mesh,
                       std::vector<std::vector<ScreenTri>>& out_chunks, const ImageOnly* image) {
  out_chunks.clear();
  Setup setup(scene, width, height, s, threads, mesh, out_chunks, image);
  setup.frame();
  setup.ring_counts();
  setup.unit_spheres();
  setup.occluders();
  setup.plan_chunks();
  setup.spheres();
  setup.polygon_vertices();
  setup.polygons();
  setup.cones();
}

}  // namespace lockstep::opt::zsimd

namespace lockstep::opt::simd {

ScreenMesh view_scene(const Scene& scene, int width, int height, const RasterSettings& s,
                      int threads) {
  ScreenMesh mesh;
  std::vector<std::vector<ScreenTri>> chunks;
  zsimd::view_scene_chunks(scene, width, height, s, threads, mesh, chunks);
  size_t total = mesh.tris.size();
  for (const auto& c : chunks) total += c.size();
  mesh.tris.reserve(total);
  for (const auto& c : chunks) mesh.tris.insert(mesh.tris.end(), c.begin(), c.end());
  return mesh;
}

}  // namespace lockstep::opt::simd
