// lockstep optimized: the simd z-buffer set-up's parts, shared by its files:
//   zbuffer_setup.cpp      the chunk driver (view_scene_chunks, opt::simd::view_scene);
//   zbuffer_spheres.cpp    one sphere, set up from its ring count's unit sphere;
//   zbuffer_occlusion.cpp  the hidden spheres' occlusion map (zbuffer_occlusion.h).
// (Internal to those files; the kernels they call are zbuffer_simd_kernels.h's.)
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/raster.h"
#include "core/shading.h"
#include "optimized/zbuffer/zbuffer_occlusion.h"
#include "optimized/zbuffer/zbuffer_simd_kernels.h"

namespace lockstep::opt::zsimd {

// core/viewing.cpp's lit, operation for operation.
inline Vec3 lit(const Scene& scene, const Material& m, const Vec3& eye, const Vec3& p, Vec3 n) {
  const Vec3 v = normalize(eye - p);
  if (dot(n, v) < 0) n = -n;
  return phong(scene, m, p, n, v);
}

// The flat colours of a chunk's triangles, lit together (flat_colors; ImageOnly):
// one request per triangle kept, lit by flat_colors at the chunk's end and
// handed to the sink.
class FlatBatch {
 public:
  // A material's inputs to the lighting (kd colour, ks, shine), worked out once
  // per sphere or run of polygons of one material, not once per triangle, and
  // kept once per run of requests (a table the kernel reads), not per request.
  struct Surface : FlatSurface {
    explicit Surface(const Material& m)
        : FlatSurface{{m.kd * m.color.x, m.kd * m.color.y, m.kd * m.color.z, m.ks, m.shine}} {}
  };
  void reserve(size_t n) { grow(n + 16); }
  // Triangle `at` of the chunk: a face of surface s with unit normal n, lit at p.
  // (Kept as planes, the kernel's layout: no transposition later.)
  [[gnu::always_inline]] void add(size_t at, const Vec3& p, const Vec3& n, const Surface& s) {
    if (n_ == cap_) [[unlikely]]
      grow(2 * cap_ + 64);
    at_[n_] = at;
    id_[n_] = surface_id(s);
    double* x = in_.get() + n_;
    const size_t c = cap_;
    x[0] = p.x, x[c] = p.y, x[2 * c] = p.z;
    x[3 * c] = n.x, x[4 * c] = n.y, x[5 * c] = n.z;
    ++n_;
  }
  // Room for m more requests, written through plane(k) (polygon_run's
  // compressed stores, which may write a vector past the last).
  void room(size_t m) {
    if (n_ + m + 16 > cap_) grow(std::max(2 * cap_, n_ + m + 16));
  }
  // Input k's plane from the next free request on.
  double* plane(int k) { return in_.get() + size_t(k) * cap_ + n_; }
  // The next n requests, their positions and normals written through plane():
  // triangles first, first + 1, ... of surface s.
  void added(size_t n, size_t first, const Surface& s) {
    const uint32_t id = surface_id(s);
    for (size_t i = 0; i < n; ++i) at_[n_ + i] = first + i, id_[n_ + i] = id;
    n_ += n;
  }
  // The last n requests' triangles were numbered from 0: they start at first.
  void offset_last(size_t n, size_t first) {
    for (size_t i = n_ - n; i < n_; ++i) at_[i] += first;
  }
  void light(const ShadeParams& p, TriSink& sink, size_t chunk) {
    const size_t n = n_, padded = (n + 15) / 16 * 16;
    if (n == 0) return;
    if (padded > cap_) grow(padded);
    const double* in[kFlatInputs];
    for (int k = 0; k < kFlatInputs; ++k) {
      double* plane = in_.get() + size_t(k) * cap_;
      // Positions relative to the eye, where the kernels light (ShadeParams::origin).
      if (k < 3 && p.origin[k] != 0)
        for (size_t i = 0; i < n; ++i) plane[i] -= p.origin[k];
      std::fill(plane + n, plane + padded, 0.0);  // (the kernel reads whole vectors)
      in[k] = plane;
    }
    std::fill(id_.get() + n, id_.get() + padded, id_[n - 1]);
    rgb_.resize(3 * padded);
    float* out[3] = {rgb_.data(), rgb_.data() + padded, rgb_.data() + 2 * padded};
    flat_colors(p, n, in, id_.get(), surfaces_.data(), out);
    sink.set_flats(chunk, at_.get(), n, out);
    n_ = 0;
    surfaces_.clear();
  }

 private:
  static_assert(kFlatInputs == 6);  // position, normal
  // s's index in the table: the last one's when the same, else a new one.
  uint32_t surface_id(const Surface& s) {
    if (surfaces_.empty() || !std::equal(s.k, s.k + 5, surfaces_.back().k))
      surfaces_.push_back(s);
    return uint32_t(surfaces_.size() - 1);
  }
  // (Not value-initialised: only the n_ entries in use are read; a chunk's
  // worth of zeroed planes was ~7% of a frame of many spheres.)
  [[gnu::noinline]] void grow(size_t cap) {
    if (cap <= cap_) return;
    std::unique_ptr<double[]> in(new double[size_t(kFlatInputs) * cap]);
    for (size_t k = 0; k < size_t(kFlatInputs); ++k)
      std::copy_n(in_.get() + k * cap_, n_, in.get() + k * cap);
    std::unique_ptr<size_t[]> at(new size_t[cap]);
    std::copy_n(at_.get(), n_, at.get());
    std::unique_ptr<uint32_t[]> id(new uint32_t[cap]);
    std::copy_n(id_.get(), n_, id.get());
    in_ = std::move(in);
    at_ = std::move(at);
    id_ = std::move(id);
    cap_ = cap;
  }
  std::unique_ptr<size_t[]> at_;    // cap_ long, n_ in use
  std::unique_ptr<uint32_t[]> id_;  // each request's surface (surfaces_), cap_ long
  std::unique_ptr<double[]> in_;    // one plane per input, cap_ apart, n_ in use
  size_t n_ = 0, cap_ = 0;
  std::vector<FlatSurface> surfaces_;
  std::vector<float> rgb_;
};

// A unit sphere's faces: unit outward normals n and plane distances h =
// n . (vertex a), planes (for a vector loop), and the smallest h (the inner
// ball, OcclusionMap).
struct UnitFaces {
  std::vector<double, NoInitAllocator<double>> nx, ny, nz, h;  // (every entry written)
  std::vector<uint32_t, NoInitAllocator<uint32_t>> vertex[3];  // unit.tri's, as arrays
  double inner = 1;
};
UnitFaces unit_faces(const UnitSphere& u);

// A sphere's vertices and faces, projected and tested (view_sphere's scratch).
// (Not value-initialised: every entry read is written first, and the arrays
// shrink and grow from one sphere to the next: zeroing the regrown part was
// about 2% of balls-3's frame.)
template <class T>
using Scratch = std::vector<T, NoInitAllocator<T>>;
struct SphereScratch {
  Scratch<Vec3> world, color;
  Scratch<ProjectedVertex> proj;
  Scratch<double> face;  // 3 per triangle
  Scratch<uint8_t> flags;
  Scratch<VertexDepth> depth;  // the image's, per vertex
  // The triangles that get the face test (kSureFace set: a front face by a margin).
  Scratch<uint32_t> cand;
  Scratch<std::array<uint32_t, 3>> cand_tri;  // the world face test's triangles
  Scratch<uint32_t> amb;                      // the candidates the world test decides
  Scratch<double> amb_face;
  Scratch<uint8_t> amb_flags;
  // The positions path's triangle step (triangle_step): vertices and
  // candidate per triangle past world culling, the kept ones then moved to the front.
  Scratch<uint32_t> va, vb, vc, vcand;
  Scratch<double> kept_face[3];  // (shaded: the kept triangles' face normals)
};

// Sphere k as view_spheres emits it (unit: its unit sphere), appended to out
// with the counts, when every vertex of its tessellation lies inside the hither
// plane and the guard band (then no triangle is clipped). Otherwise false, and
// nothing is emitted. Operation for operation view_spheres' and Emitter::triangle's
// arithmetic, so the same bits (the vertices and the face tests a vector at a
// time); only the per-triangle copies and the per-sphere sines are gone.
bool view_sphere(const Scene& scene, const RasterSettings& s, const Camera& cam,
                 const Projection& projection, uint32_t k, const UnitSphere& unit,
                 const UnitFaces& unit_face,
                 const ImageOnly* image, const DepthMap& depth_map, const OcclusionMap* occlusion,
                 size_t chunk, FlatBatch& batch, SphereScratch& sc, ScreenMesh& out);

}  // namespace lockstep::opt::zsimd
