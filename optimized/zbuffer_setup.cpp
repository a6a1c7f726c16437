// The optimized z-buffer's set-up: ref::view_scene's screen mesh, bit for bit,
// in less time (declared in optimized/raster.h).
//
// view_scene (reference/viewing.cpp) transforms, tests and projects every
// triangle's three vertices on their own, one triangle after another. Here:
//   * every scene vertex is moved to eye space and snapped once, in parallel,
//     with the very same double operations (so the same bits): a vertex shared
//     by six triangles is projected once, not six times;
//   * polygons are set up in parallel chunks (TBB), each chunk writing its own
//     triangles, which are then concatenated in scene order;
//   * everything else (culling in world or projection space, the flat colour
//     per polygon, the Gouraud colour per vertex, the degenerate and culled
//     counts) is the reference's arithmetic, operation for operation.
// Spheres run view_scene's own sphere step (ref::view_spheres) on chunks of
// spheres in parallel. Polygons: only the common case is done here, no
// polygon with a triangle that needs clipping (at the hither plane or the guard
// band) goes through view_scene's own polygon step (ref::view_polygons) on its
// own, in its chunk, so the result is always view_scene's.
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>

#include "core/shading.h"
#include "optimized/raster.h"
#include "optimized/tiling.h"
#include "optimized/zbuffer_simd_kernels.h"

namespace lockstep::opt::zsimd {

namespace {

// reference/viewing.cpp's eye_from_world, to_screen and lit, operation for operation.
Vec3 eye_from_world(const Camera& c, const Vec3& p) {
  const Vec3 d = p - c.eye;
  return {dot(d, c.right), dot(d, c.up), dot(d, c.forward)};
}

Vec3 lit(const Scene& scene, const Material& m, const Vec3& eye, const Vec3& p, Vec3 n) {
  const Vec3 v = normalize(eye - p);
  if (dot(n, v) < 0) n = -n;
  return phong(scene, m, p, n, v);
}

// std::llround (half away from zero), inline: x - trunc(x) is exact, so this is
// llround's answer for every finite x (the callers' are below 2^40).
inline int64_t round_half_away(double x) {
  const double t = std::trunc(x);
  const double f = x - t;
  return int64_t(t + (f >= 0.5 ? 1.0 : 0.0) - (f <= -0.5 ? 1.0 : 0.0));
}

struct Projected {
  Vec3 eye;
  int32_t x = 0, y = 0;
  bool inside = false;  // within the hither plane and the guard band
};

struct Chunk {
  std::vector<ScreenTri> tris;
  uint64_t scene_tris = 0, culled = 0, degenerate = 0, clipped = 0;
};

}  // namespace

void view_scene_chunks(const Scene& scene, int width, int height, const RasterSettings& s,
                       int threads, ScreenMesh& mesh,
                       std::vector<std::vector<ScreenTri>>& out_chunks) {
  out_chunks.clear();
  // The frame, near and far: view_scene's own step.
  mesh = lockstep::view_frame(scene, width, height);
  const Camera& cam = mesh.camera;
  tbb::task_arena arena(resolve_threads(threads));

  // Spheres: view_scene's own sphere step (tessellation, clipping, culling),
  // run on chunks of spheres in parallel, each chunk into its own mesh; the
  // chunks' triangles then follow one another in sphere order, as in view_scene.
  const uint32_t spheres = scene.sphere_count();
  // At most 16 spheres a chunk (a few big spheres are as much work as many
  // small ones), at most 64 chunks (each chunk gets its own bins per tile).
  const uint32_t spheres_per_chunk =
      std::max({1u, std::min<uint32_t>(16, (spheres + 7) / 8), (spheres + 63) / 64});
  std::vector<ScreenMesh> sphere_chunks((spheres + spheres_per_chunk - 1) / spheres_per_chunk);
  arena.execute([&] {
    tbb::parallel_for(size_t(0), sphere_chunks.size(), [&](size_t c) {
      ScreenMesh& part = sphere_chunks[c];
      part.camera = cam;
      part.width = width;
      part.height = height;
      part.near_z = mesh.near_z;
      part.far_z = mesh.far_z;
      const uint32_t first = uint32_t(c) * spheres_per_chunk;
      lockstep::view_spheres(scene, s, first, std::min(spheres, first + spheres_per_chunk), part);
    });
  });
  for (ScreenMesh& part : sphere_chunks) {
    mesh.sphere_tris += part.sphere_tris;
    mesh.culled += part.culled;
    mesh.clipped += part.clipped;
    mesh.degenerate += part.degenerate;
    if (!part.tris.empty()) out_chunks.push_back(std::move(part.tris));
  }

  const double near_z = mesh.near_z, g = kGuardBand * cam.pitch;

  // Every vertex once: eye space, the clip test, the snapped screen position.
  std::vector<Projected> pv(scene.vertex.size());
  arena.execute([&] {
    tbb::parallel_for(
        tbb::blocked_range<size_t>(0, pv.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
          for (size_t i = r.begin(); i < r.end(); ++i) {
            Projected& p = pv[i];
            const Vec3 e = eye_from_world(cam, scene.vertex[i]);
            p.eye = e;
            // Branch-free (& not &&), so that the compiler can vectorise the loop.
            const bool inside = (e.z - near_z >= 0) & (g * e.z - e.x >= 0) & (g * e.z + e.x >= 0) &
                                (g * e.z - e.y >= 0) & (g * e.z + e.y >= 0);
            p.inside = inside;
            const double xs = 0.5 * cam.width + e.x / (e.z * cam.pitch);
            const double ys = 0.5 * cam.height - e.y / (e.z * cam.pitch);
            p.x = int32_t(round_half_away(inside ? xs * kSubpixel : 0.0));
            p.y = int32_t(round_half_away(inside ? ys * kSubpixel : 0.0));
          }
        });
  });

  const uint32_t polys = scene.polygon_count();
  const uint32_t per_chunk = 512;
  const uint32_t nchunks = (polys + per_chunk - 1) / per_chunk;
  std::vector<Chunk> chunks(nchunks);
  // The frame alone (no triangles, no counts), for view_polygons on one polygon.
  ScreenMesh frame;
  frame.camera = cam;
  frame.width = width;
  frame.height = height;
  frame.near_z = mesh.near_z;
  frame.far_z = mesh.far_z;
  auto run_chunk = [&](uint32_t c) {
    Chunk& out = chunks[c];
    const uint32_t first = c * per_chunk, last = std::min(polys, first + per_chunk);
    out.tris.reserve(size_t(scene.poly_tri_first[last] - scene.poly_tri_first[first]));
    for (uint32_t p = first; p < last; ++p) {
      const Material& m = scene.materials[scene.poly_material[p]];
      const Vec3 face = scene.poly_plane[p].n;
      if (length(face) == 0) continue;
      Vec3 flat;
      if (s.shading == Shading::kFlat) {
        Vec3 centroid;
        for (const Vec3& x : scene.polygon_vertices(p)) centroid += x;
        flat = lit(scene, m, cam.eye, centroid / double(scene.polygon_vertices(p).size()), face);
      }
      const bool patch = scene.poly_is_patch[p] != 0;
      const bool two_sided = m.two_sided();
      const size_t tris_before = out.tris.size();
      const uint64_t scene_before = out.scene_tris, culled_before = out.culled,
                     degenerate_before = out.degenerate;
      bool needs_clipping = false;
      for (uint32_t t = scene.poly_tri_first[p]; t < scene.poly_tri_first[p + 1]; ++t) {
        ++out.scene_tris;
        const auto& tv = scene.tri_vertex[t];
        // World-space culling (view_scene's Emitter::triangle).
        const Vec3& w0 = scene.vertex[tv[0]];
        const bool front = dot(face, cam.eye - w0) > 0;
        if (!front && !two_sided && s.cull == CullMode::kWorld) {
          ++out.culled;
          continue;
        }
        if (!pv[tv[0]].inside || !pv[tv[1]].inside || !pv[tv[2]].inside) {
          needs_clipping = true;
          break;
        }
        ScreenTri& st = out.tris.emplace_back();  // built in place (a ScreenTri is 300 bytes)
        for (int i = 0; i < 3; ++i) {
          const uint32_t vi = tv[size_t(i)];
          ScreenVertex& v = st.v[size_t(i)];
          v.x = pv[vi].x;
          v.y = pv[vi].y;
          v.z = pv[vi].eye.z;
          v.world = scene.vertex[vi];
          v.normal = patch ? scene.vertex_normal[vi] : face;
          if (s.shading == Shading::kGouraud) v.color = lit(scene, m, cam.eye, v.world, v.normal);
        }
        st.prim = scene.sphere_count() + p;
        st.source_tri = t;
        st.flat_color = flat;
        const int64_t area = int64_t(st.v[1].x - st.v[0].x) * (st.v[2].y - st.v[0].y) -
                             int64_t(st.v[1].y - st.v[0].y) * (st.v[2].x - st.v[0].x);
        if (area == 0) {
          ++out.degenerate;
          out.tris.pop_back();
          continue;
        }
        // Projection space: a front face is counter-clockwise as seen, negative area with y down.
        if (area > 0 && !two_sided && s.cull == CullMode::kProjection) {
          ++out.culled;
          out.tris.pop_back();
          continue;
        }
        if (area < 0) std::swap(st.v[1], st.v[2]);
        st.face_normal = front ? face : -face;
      }
      if (needs_clipping) {
        // A triangle of this polygon crosses the hither plane or the guard
        // band: undo the polygon and run view_scene's own polygon step on it.
        out.tris.erase(out.tris.begin() + std::ptrdiff_t(tris_before), out.tris.end());
        out.scene_tris = scene_before;
        out.culled = culled_before;
        out.degenerate = degenerate_before;
        ScreenMesh part = frame;
        lockstep::view_polygons(scene, s, p, p + 1, part);
        out.tris.insert(out.tris.end(), part.tris.begin(), part.tris.end());
        out.scene_tris += part.scene_tris;
        out.culled += part.culled;
        out.degenerate += part.degenerate;
        out.clipped += part.clipped;
      }
    }
  };
  arena.execute([&] { tbb::parallel_for(uint32_t(0), nchunks, run_chunk); });
  for (Chunk& c : chunks) {
    mesh.scene_tris += c.scene_tris;
    mesh.culled += c.culled;
    mesh.degenerate += c.degenerate;
    mesh.clipped += c.clipped;
    out_chunks.push_back(std::move(c.tris));
  }
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
