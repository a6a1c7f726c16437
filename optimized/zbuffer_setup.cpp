// The optimized z-buffer's set-up: ref::view_scene's screen mesh, bit for bit,
// in less time (declared in optimized/raster.h).
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
// Highway kernels (zbuffer_simd_kernels.cpp) with the same double operations.
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
#include "optimized/raster.h"
#include "optimized/tiling.h"
#include "optimized/zbuffer_simd_kernels.h"

namespace lockstep::opt::zsimd {

namespace {

// core/viewing.cpp's eye_from_world, to_screen and lit, operation for operation.
Vec3 eye_from_world(const Camera& c, const Vec3& p) {
  const Vec3 d = p - c.eye;
  return {dot(d, c.right), dot(d, c.up), dot(d, c.forward)};
}

Vec3 lit(const Scene& scene, const Material& m, const Vec3& eye, const Vec3& p, Vec3 n) {
  const Vec3 v = normalize(eye - p);
  if (dot(n, v) < 0) n = -n;
  return phong(scene, m, p, n, v);
}

struct Chunk {
  std::vector<ScreenTri> tris;
  uint64_t scene_tris = 0, culled = 0, degenerate = 0, clipped = 0;
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

// ---------------------------------------------------------------- hidden spheres
// (The z-buffer's image only.) A sphere whose every sample is already covered
// by a nearer sphere's mesh can never pass the depth test, whatever the order:
// it is not tessellated at all, and of the other spheres, no triangle whose
// samples are all so covered is kept. The image is the same: only triangles
// that would lose every depth test are left out.
//
// The occluders. A sphere's tessellation (unit_sphere) is a convex polyhedron
// inscribed in it, so it contains the ball of radius r h (h: the smallest
// distance from the unit sphere's centre to a face plane). A sample whose ray
// meets that ball crosses the mesh: the mesh is closed and the fill rule
// watertight, so a kept triangle covers it: the front face where the ray
// enters, before it reaches the ball, or the inside-out sphere's far face, at
// eye depth at most z + r (every point of the mesh is in the sphere). The ball
// is shrunk by 2 px of its farthest depth first, for the snapping (the drawn
// surface is the mesh with its vertices moved by 1/512 px) and for the slivers
// seen edge-on at the silhouette, and only spheres wholly past the hither plane
// count (no clipping). Per cell of 4 x 4 pixels the map keeps the nearest bound
// of the spheres whose shrunk ball covers the whole cell (its four corners'
// rays: the ball's image is convex): the largest of the four corner rays' entry
// depths into the ball (the entry depth is quasi-convex over the screen: the
// points whose ray enters by depth Z are the image of ball and half-space
// z <= Z, a convex set, so its maximum over a cell is at a corner), z + r for
// an inside-out sphere.
//
// The test. Something at eye depth >= z_min with all its samples in a box of
// cells is hidden when every cell's bound z_occ is nearer by a margin that
// outlasts the depth formats' rounding: window depth (1/n - 1/z) / (1/n - 1/f)
// 1e-5 apart (float and 24-bit codes: ~170 steps near 1) and z 1e-5 apart
// relatively (reversed n / z in float). The map keeps, per cell, the depth
// beyond which that holds, so the test is a maximum and one comparison. A
// triangle's depth is at least its nearest vertex's (up to the plane's few
// ulps); a sphere's at least z - r. Boxes over many cells read coarse cells of
// 8 x 8 pixels instead, each the largest bound of its four (fewer to read, the
// test no less safe). (8 x 8 cells alone hid 68k of balls-3's triangles at
// 1024^2, 4 x 4 ones hide 76k; the corner rays a vector at a time, ball_entries,
// keep the finer map's cost below what it saves.)
class OcclusionMap {
 public:
  static constexpr int kCell = kOcclusionCell;

  OcclusionMap(const Camera& cam, int width, int height, double near_z, double far_z)
      : cam_(cam),
        width_(width),
        height_(height),
        nx_((width + kCell - 1) / kCell),
        ny_((height + kCell - 1) / kCell),
        cnx_((nx_ + 1) / 2),
        cny_((ny_ + 1) / 2),
        near_(near_z),
        inv_near_(1 / near_z),
        range_(1 / near_z - 1 / far_z),
        // (One more: triangle_step reads cells in pairs, the last one's
        // neighbour too, and ignores it.)
        z_(size_t(nx_) * size_t(ny_) + size_t(cnx_) * size_t(cny_) + 1, kInfinity) {}

  // The pixels [i0, i1] x [j0, j1] (clipped to the frame) that may hold a
  // sample of a mesh inscribed in the ball (eye-space centre ce, radius r):
  // the ball's image, found from its tangent planes through the eye, and a
  // pixel more. False when the ball is not wholly past the hither plane.
  bool sphere_box(const Vec3& ce, double r, int& i0, int& i1, int& j0, int& j1) const {
    if (!(ce.z - r > near_)) return false;
    double x_lo, x_hi, y_lo, y_hi;  // tangents x / z and y / z
    tangents(ce.x, ce.z, r, x_lo, x_hi);
    tangents(ce.y, ce.z, r, y_lo, y_hi);
    const double sx0 = 0.5 * width_ + x_lo / cam_.pitch, sx1 = 0.5 * width_ + x_hi / cam_.pitch;
    const double sy0 = 0.5 * height_ - y_hi / cam_.pitch, sy1 = 0.5 * height_ - y_lo / cam_.pitch;
    i0 = clamp_to(std::floor(sx0) - 1, width_);
    i1 = clamp_to(std::floor(sx1) + 1, width_);
    j0 = clamp_to(std::floor(sy0) - 1, height_);
    j1 = clamp_to(std::floor(sy1) + 1, height_);
    return std::isfinite(sx0 + sx1 + sy0 + sy1);
  }

  // The sphere (eye-space centre ce, radius r, inside out when inverted,
  // mesh's inner distance h per unit radius) as an occluder.
  void add(const Vec3& ce, double r, bool inverted, double h) {
    int i0, i1, j0, j1;
    if (!sphere_box(ce, r, i0, i1, j0, j1)) return;
    const double rho = r * h * (1 - 1e-9) - 2 * cam_.pitch * (ce.z + r);
    if (!(rho > 0)) return;
    const double z_occ = ce.z + r;
    // Cells wholly inside [i0, i1 + 1) x [j0, j1 + 1); their corners on the grid of cells.
    const int a0 = (i0 + kCell - 1) / kCell, a1 = (i1 + 1) / kCell;  // cells [a0, a1)
    const int b0 = (j0 + kCell - 1) / kCell, b1 = (j1 + 1) / kCell;
    if (a0 >= a1 || b0 >= b1) return;
    const int na = a1 - a0 + 1;
    entry_.resize(size_t(na) * size_t(b1 - b0 + 1));
    // The rays through the corners (a, b) of cells, a row at a time.
    const double centre[3] = {ce.x, ce.y, ce.z};
    for (int b = b0; b <= b1; ++b)
      ball_entries(centre, rho * rho, inverted, z_occ, cam_.pitch, 0.5 * width_,
                   (0.5 * height_ - b * kCell) * cam_.pitch, kCell, a0, na,
                   entry_.data() + size_t(b - b0) * size_t(na));
    for (int b = b0; b < b1; ++b)
      for (int a = a0; a < a1; ++a) {
        const size_t k = size_t(b - b0) * size_t(na) + size_t(a - a0);
        // (+inf where a corner is outside: the cell is not covered.)
        const double bound = std::max({entry_[k], entry_[k + 1], entry_[k + size_t(na)],
                                       entry_[k + size_t(na) + 1]});
        if (bound < kInfinity) {
          double& z = z_[size_t(b) * size_t(nx_) + size_t(a)];
          z = std::min(z, std::min(bound, z_occ));
        }
      }
  }

  // Whether everything at eye depth >= z_min with its samples in pixels
  // [i0, i1] x [j0, j1] loses to the occluders.
  // (The coarse cells: fewer to look at, each at least its cells' bounds.)
  bool hidden(int i0, int i1, int j0, int j1, double z_min) const {
    if (i0 > i1 || j0 > j1) return false;
    double beyond = -kInfinity;
    const double* coarse = z_.data() + coarse_at();
    for (int b = j0 / (2 * kCell); b <= j1 / (2 * kCell); ++b)
      for (int a = i0 / (2 * kCell); a <= i1 / (2 * kCell); ++a)
        beyond = std::max(beyond, coarse[size_t(b) * size_t(cnx_) + size_t(a)]);
    return z_min > beyond;
  }

  // The map for triangle_step.
  OcclusionCells cells() const { return {z_.data(), nx_, int(coarse_at()), cnx_}; }

  // After the last add: each cell's bound becomes the depth beyond which its
  // occluders hide (hidden_beyond, monotonic: the largest over cells decides),
  // and each coarse cell's the largest of its cells'.
  void finish() {
    double* coarse = z_.data() + coarse_at();
    for (size_t k = 0; k < coarse_at(); ++k) z_[k] = hidden_beyond(z_[k]);
    for (int b = 0; b < cny_; ++b)
      for (int a = 0; a < cnx_; ++a) {
        double m = -kInfinity;
        for (int y = 2 * b; y < std::min(2 * b + 2, ny_); ++y)
          for (int x = 2 * a; x < std::min(2 * a + 2, nx_); ++x)
            m = std::max(m, z_[size_t(y) * size_t(nx_) + size_t(x)]);
        coarse[size_t(b) * size_t(cnx_) + size_t(a)] = m;
      }
  }

 private:
  // x / z of the two planes through the eye (and the other axis) tangent to the
  // ball: (x - t z)^2 = r^2 (1 + t^2).
  static void tangents(double x, double z, double r, double& lo, double& hi) {
    const double a = z * z - r * r, root = r * std::sqrt(std::max(0.0, x * x + a));
    lo = (x * z - root) / a, hi = (x * z + root) / a;
  }
  static int clamp_to(double v, int n) { return int(std::clamp(v, 0.0, double(n - 1))); }
  size_t coarse_at() const { return size_t(nx_) * size_t(ny_); }
  // The eye depth beyond which something is hidden by an occluder at z_occ:
  // 1e-5 further relatively, and 1e-5 further in window depth
  // (1/n - 1/z) / (1/n - 1/f), i.e. 1/z < 1/z_occ - 1e-5 (1/n - 1/f); +inf for
  // no occluder.
  double hidden_beyond(double z_occ) const {
    if (!(z_occ < kInfinity)) return kInfinity;
    const double inv = 1 / z_occ - 1e-5 * range_;
    return inv > 0 ? std::max(z_occ * (1 + 1e-5), 1 / inv) : kInfinity;
  }

  const Camera& cam_;
  int width_, height_, nx_, ny_, cnx_, cny_;  // cells of kCell px a row and column; coarse ones
  double near_, inv_near_, range_;
  // Per cell: the nearest bound of a sphere covering it whole, +inf for none;
  // after finish, hidden_beyond of it.
  std::vector<double> z_;
  std::vector<double> entry_;  // add's corners' entry depths
};

// A unit sphere's faces: unit outward normals n and plane distances h =
// n . (vertex a), planes (for a vector loop), and the smallest h (the inner
// ball, OcclusionMap).
struct UnitFaces {
  std::vector<double, NoInitAllocator<double>> nx, ny, nz, h;  // (every entry written)
  std::vector<uint32_t, NoInitAllocator<uint32_t>> vertex[3];  // unit.tri's, as arrays
  double inner = 1;
};
UnitFaces unit_faces(const UnitSphere& u) {
  // The UV sphere turns into itself about z by 2 pi / meridians: per band of
  // latitude, meridian 0's faces (one at the poles, two elsewhere, in
  // unit_sphere's order) are worked out, every other meridian's turned from them.
  UnitFaces f;
  const size_t nt = u.tri.size();
  f.nx.resize(nt), f.ny.resize(nt), f.nz.resize(nt), f.h.resize(nt);
  for (int k = 0; k < 3; ++k) {
    f.vertex[k].resize(nt);
    for (size_t t = 0; t < nt; ++t) f.vertex[k][t] = u.tri[t][size_t(k)];
  }
  const int rings = u.rings, meridians = 2 * rings;
  std::vector<double> cos_phi(static_cast<size_t>(meridians)), sin_phi(static_cast<size_t>(meridians));
  for (int l = 0; l < meridians; ++l) {
    cos_phi[size_t(l)] = std::cos(2 * M_PI * l / meridians);
    sin_phi[size_t(l)] = std::sin(2 * M_PI * l / meridians);
  }
  size_t t = 0;
  for (int k = 0; k < rings; ++k) {
    const int per = (k == 0 || k == rings - 1) ? 1 : 2;
    Vec3 n0[2];
    double h0[2] = {0, 0};
    for (int j = 0; j < per; ++j) {
      const auto& [a, b, c] = u.tri[t + size_t(j)];
      const Vec3 n = cross(u.unit[b] - u.unit[a], u.unit[c] - u.unit[a]);
      const double len = length(n);
      n0[j] = len > 0 ? n / len : n;
      h0[j] = dot(n0[j], u.unit[a]);
      if (len > 0) f.inner = std::min(f.inner, std::abs(h0[j]));
    }
    for (int l = 0; l < meridians; ++l) {
      const double cl = cos_phi[size_t(l)], sl = sin_phi[size_t(l)];
      for (int j = 0; j < per; ++j, ++t) {
        f.nx[t] = n0[j].x * cl - n0[j].y * sl;
        f.ny[t] = n0[j].x * sl + n0[j].y * cl;
        f.nz[t] = n0[j].z;
        f.h[t] = h0[j];
      }
    }
  }
  return f;
}

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
                 size_t chunk, FlatBatch& batch, SphereScratch& sc, ScreenMesh& out) {
  const Vec3 c = scene.sphere_center[k];
  const double signed_radius = scene.sphere_radius[k];
  const double r = std::abs(signed_radius);
  const Material& m = scene.materials[scene.sphere_material[k]];
  const FlatBatch::Surface surface(m);
  const bool gouraud = s.shading == Shading::kGouraud, flat_shading = s.shading == Shading::kFlat;
  const size_t nv = unit.unit.size(), nt = unit.tri.size();
  sc.world.resize(nv);
  sc.proj.resize(nv);
  for (size_t i = 0; i < nv; ++i) sc.world[i] = c + r * unit.unit[i];
  // For the image, w and the stored depth too, once per vertex (not per triangle).
  if (image) sc.depth.resize(nv);
  project_vertices(projection, sc.world.data(), nv, sc.proj.data(), image ? &depth_map : nullptr,
                   image ? sc.depth.data() : nullptr);
  for (size_t i = 0; i < nv; ++i)
    if (!sc.proj[i].inside) return false;
  auto normal = [&](uint32_t i) { return signed_radius > 0 ? unit.unit[i] : -unit.unit[i]; };
  if (gouraud) {
    sc.color.resize(nv);
    for (uint32_t i = 0; i < nv; ++i) sc.color[i] = lit(scene, m, cam.eye, sc.world[i], normal(i));
  }
  // Counter-clockwise seen from the visible side: reversed inside out.
  const bool flip = !(signed_radius > 0);
  // Culling in world space: the faces that are back faces by a clear margin,
  // found from the unit sphere's normals (N . (eye - w_a) = n . (eye - c) - r h,
  // n and h the unit face's), are counted and passed over without the world
  // face test; the others get it (sphere_faces, the reference's operations).
  // The margin dwarfs the rounding of c + r u and of the cross product (the
  // unit faces' edges are >= ~1e-4 long, 256 rings), and the sphere must not be
  // so small beside its distance from the origin that its vertices round together.
  // The image's triangles in bulk: positions only (flat shading drawn
  // forward), or with vertex normals for shading (Phong, Blinn-Phong, toon).
  const bool positions = image && image->sink->positions_only();
  const bool shaded = image && !positions && image->sink->shaded_bulk();
  const bool bulk = positions || shaded;
  // The candidates (sc.cand's first nc), and whether they are all front faces
  // by the margin with their vertices in sc.va, vb, vc already (in bulk, when
  // nothing is left to the world face test).
  size_t nc = 0;
  bool all_sure = false;
  const Vec3 e_rel = cam.eye - c;
  const double spread = (length(c) + r) / r;
  // Unit-space normals turned to the drawn side (inside out: reversed).
  const double sign = flip ? -1.0 : 1.0;
  if (s.cull == CullMode::kWorld && spread < 1e6) {
    const double margin = 1e-9 * (length(e_rel) + r) * std::max(1.0, spread);
    // 0: a back face by the margin, 1: either, 2: a front face by the margin;
    // the faces past 0 are the candidates, in order (a vector of faces at a
    // time: sphere_face_codes), those at 2 marked sure for the image: a face
    // that is a front face by the same margin needs no world test either: its
    // unit normal stands in for the world one (the same direction to ~1e-16,
    // far below the image's float shading).
    sc.cand.resize(nt + 16);
    const double e[3] = {e_rel.x, e_rel.y, e_rel.z};
    // In bulk: the candidates' vertices (in the raster's winding) written by
    // the kernel too, for triangle_step.
    FaceVertices verts;
    if (bulk) {
      for (auto* v : {&sc.va, &sc.vb, &sc.vc}) v->resize(nt + 16);
      const auto& vx = unit_face.vertex;
      verts.in[0] = vx[0].data(), verts.in[1] = vx[flip ? 2 : 1].data();
      verts.in[2] = vx[flip ? 1 : 2].data();
      verts.out[0] = sc.va.data(), verts.out[1] = sc.vb.data(), verts.out[2] = sc.vc.data();
    }
    nc = sphere_face_codes(unit_face.nx.data(), unit_face.ny.data(), unit_face.nz.data(),
                           unit_face.h.data(), nt, e, r, sign, margin, image != nullptr,
                           sc.cand.data(), bulk ? &verts : nullptr);
    all_sure = bulk && verts.unsure == 0;
    const uint64_t clear = nt - nc;
    out.sphere_tris += clear;
    out.culled += clear;
  } else {
    sc.cand.resize(nt + 16);
    for (uint32_t t = 0; t < nt; ++t) sc.cand[t] = t;
    nc = nt;
  }
  // (In bulk the sure faces' normals are read from the unit faces and the
  // others' from sphere_faces' results directly, below.)
  if (!bulk) sc.face.resize(3 * nc), sc.flags.resize(nc);
  // The world face test (the reference's operations) on the others.
  sc.cand_tri.resize(nc);
  if (!bulk) sc.amb.resize(nc);  // (bulk: sphere_faces' results are read in order)
  size_t na = 0;
  for (size_t i = 0; i < nc && !all_sure; ++i) {
    const uint32_t t = sc.cand[i] & ~kSureFace;
    if (bulk) {
      if (!(sc.cand[i] & kSureFace)) sc.cand_tri[na++] = unit.tri[t];
    } else if (sc.cand[i] & kSureFace) {
      sc.face[3 * i] = sign * unit_face.nx[t];
      sc.face[3 * i + 1] = sign * unit_face.ny[t];
      sc.face[3 * i + 2] = sign * unit_face.nz[t];
      sc.flags[i] = kFront;
    } else {
      sc.amb[na] = uint32_t(i);
      sc.cand_tri[na++] = unit.tri[t];
    }
  }
  sc.amb_face.resize(3 * na);
  sc.amb_flags.resize(na);
  sphere_faces(sc.world.data(), sc.cand_tri.data(), na, flip, cam.eye, sc.amb_face.data(),
               sc.amb_flags.data());
  for (size_t j = 0; j < na && !bulk; ++j) {
    const size_t i = sc.amb[j];
    for (int k = 0; k < 3; ++k) sc.face[3 * i + size_t(k)] = sc.amb_face[3 * j + size_t(k)];
    sc.flags[i] = sc.amb_flags[j];
  }
  ScreenTri local;
  if (bulk) {
    // The same steps, the area's and the box's in SIMD (triangle_step): the
    // triangles past world culling first, then the kernel, which moves the
    // kept ones to the front and counts the others.
    const size_t room = (nc + 15) / 16 * 16;
    for (auto* v : {&sc.va, &sc.vb, &sc.vc, &sc.vcand}) v->resize(room);
    // Per triangle kept here, where its face normal is (tag): its unit
    // face's index with kSureFace, else its place in sphere_faces' results.
    // (All sure: the candidates themselves, their vertices in place already.)
    size_t n = all_sure ? nc : 0, j = 0;
    uint32_t* const tag = all_sure ? sc.cand.data() : sc.vcand.data();
    if (all_sure) out.sphere_tris += nc;
    for (uint32_t i = 0; i < nc && !all_sure; ++i) {
      const uint32_t ci = sc.cand[i];
      const bool sure = (ci & kSureFace) != 0;
      const uint8_t flags = sure ? kFront : sc.amb_flags[j];
      const uint32_t face_at = sure ? ci : uint32_t(j);
      j += !sure;
      if (flags & kNoFace) continue;
      ++out.sphere_tris;
      if (!(flags & kFront) && s.cull == CullMode::kWorld) {
        ++out.culled;
        continue;
      }
      const auto& [a, b0, c0] = unit.tri[ci & ~kSureFace];
      sc.va[n] = a, sc.vb[n] = flip ? c0 : b0, sc.vc[n] = flip ? b0 : c0;
      sc.vcand[n++] = face_at;
    }
    const size_t padded = (n + 15) / 16 * 16;
    if (n == 0) return true;
    for (auto* v : {&sc.va, &sc.vb, &sc.vc}) std::fill(v->begin() + n, v->begin() + padded, sc.va[0]);
    const OcclusionCells cells = occlusion ? occlusion->cells() : OcclusionCells{};
    TriangleCounts counts;
    const size_t kept = triangle_step(sc.proj.data(), sc.va.data(), sc.vb.data(), sc.vc.data(),
                                      tag, n, image->grid,
                                      s.cull == CullMode::kProjection,
                                      occlusion ? &cells : nullptr, counts);
    out.degenerate += counts.degenerate, out.culled += counts.culled, out.hidden += counts.hidden;
    // Their flat colours' inputs, written straight into the batch's planes
    // (indices in the sphere for now: its chunk's once handed over).
    if (flat_shading && kept > 0) {
      batch.room(kept);
      double* const in[6] = {batch.plane(0), batch.plane(1), batch.plane(2),
                             batch.plane(3), batch.plane(4), batch.plane(5)};
      for (size_t j = 0; j < kept; ++j) {
        // (v1 and v2 may be swapped: the sum may differ from view_spheres'
        // in its last bit, far below the SIMD lighting's float precision.)
        const Vec3 p = (sc.world[sc.va[j]] + sc.world[sc.vb[j]] + sc.world[sc.vc[j]]) / 3.0;
        in[0][j] = p.x, in[1][j] = p.y, in[2][j] = p.z;
        const uint32_t at = tag[j];
        if (at & kSureFace) {
          const uint32_t t = at & ~kSureFace;
          in[3][j] = sign * unit_face.nx[t], in[4][j] = sign * unit_face.ny[t],
          in[5][j] = sign * unit_face.nz[t];
        } else {
          const double* face = sc.amb_face.data() + 3 * size_t(at);
          in[3][j] = face[0], in[4][j] = face[1], in[5][j] = face[2];
        }
      }
      batch.added(kept, 0, surface);
    }
    if (kept > 0 && positions) {  // (triangle_step's samples test: done already)
      // (va, vb, vc hold valid vertex indices up to n rounded up to 16.)
      const size_t first = image->sink->add_positions(
          chunk, {sc.proj.data(), sc.depth.data(), sc.va.data(), sc.vb.data(), sc.vc.data()},
          kept, true);
      if (flat_shading) batch.offset_last(kept, first);
    }
    if (kept > 0 && shaded) {
      // Their face normals, of the side drawn (a kept face is a front face,
      // unless culling is not in world space: then sphere_faces says).
      for (auto& f : sc.kept_face) f.resize(kept);
      for (size_t j = 0; j < kept; ++j) {
        const uint32_t at = tag[j];
        Vec3 f;
        bool front = true;
        if (at & kSureFace) {
          const uint32_t t = at & ~kSureFace;
          f = {sign * unit_face.nx[t], sign * unit_face.ny[t], sign * unit_face.nz[t]};
        } else {
          const double* face = sc.amb_face.data() + 3 * size_t(at);
          f = {face[0], face[1], face[2]};
          front = (sc.amb_flags[at] & kFront) != 0;
        }
        if (!front) f = -f;
        sc.kept_face[0][j] = f.x, sc.kept_face[1][j] = f.y, sc.kept_face[2][j] = f.z;
      }
      ShadedTris sh;
      sh.normal = unit.unit.data();
      sh.negate = !(signed_radius > 0);
      for (int k = 0; k < 3; ++k) sh.face[k] = sc.kept_face[k].data();
      sh.material = scene.sphere_material[k];
      image->sink->add_shaded(
          chunk, {sc.proj.data(), sc.depth.data(), sc.va.data(), sc.vb.data(), sc.vc.data()},
          kept, sh);
    }
    return true;
  }
  for (uint32_t i = 0; i < nc; ++i) {
    if (sc.flags[i] & kNoFace) continue;
    const uint32_t t = sc.cand[i] & ~kSureFace;
    const auto& [a, b0, c0] = unit.tri[t];
    const uint32_t idx[3] = {a, flip ? c0 : b0, flip ? b0 : c0};
    const Vec3& w0 = sc.world[idx[0]];
    const Vec3& w1 = sc.world[idx[1]];
    const Vec3& w2 = sc.world[idx[2]];
    const Vec3 face{sc.face[3 * i], sc.face[3 * i + 1], sc.face[3 * i + 2]};
    const bool front = (sc.flags[i] & kFront) != 0;
    ++out.sphere_tris;
    // Emitter::triangle: world-space culling (spheres are one-sided) ...
    if (!front && s.cull == CullMode::kWorld) {
      ++out.culled;
      continue;
    }
    // ... then the snapped area: degenerate, projection-space culling, the
    // order (positive area: a front face's v[1] and v[2] swapped).
    const ProjectedVertex &p0 = sc.proj[idx[0]], &p1 = sc.proj[idx[1]], &p2 = sc.proj[idx[2]];
    const int64_t area =
        int64_t(p1.x - p0.x) * (p2.y - p0.y) - int64_t(p1.y - p0.y) * (p2.x - p0.x);
    if (area == 0) {
      ++out.degenerate;
      continue;
    }
    if (area > 0 && s.cull == CullMode::kProjection) {
      ++out.culled;
      continue;
    }
    if (image) {
      int32_t i0, i1, j0, j1;
      image->grid.pixels(std::min({p0.x, p1.x, p2.x}), std::max({p0.x, p1.x, p2.x}),
                         std::min({p0.y, p1.y, p2.y}), std::max({p0.y, p1.y, p2.y}), i0, i1, j0,
                         j1);
      if (i0 > i1 || j0 > j1) continue;  // no sample in its box
      if (occlusion && occlusion->hidden(i0, i1, j0, j1, std::min({p0.z, p1.z, p2.z}))) {
        ++out.hidden;
        continue;
      }
    }
    const uint32_t order[3] = {idx[0], area < 0 ? idx[2] : idx[1], area < 0 ? idx[1] : idx[2]};
    // Built in place (a ScreenTri is 300 bytes), or for the image in `local`
    // (every field it reads is written for each triangle).
    ScreenTri& st = image ? local : out.tris.emplace_back();
    for (int i = 0; i < 3; ++i) {
      const uint32_t vi = order[i];
      ScreenVertex& v = st.v[size_t(i)];
      v.x = sc.proj[vi].x;
      v.y = sc.proj[vi].y;
      v.z = sc.proj[vi].z;
      v.world = sc.world[vi];
      v.normal = normal(vi);
      if (gouraud) v.color = sc.color[vi];
    }
    st.prim = k;
    st.source_tri = t;
    st.face_normal = front ? face : -face;
    // The flat colour: view_spheres lights every face not culled in world space,
    // the same bits whenever it is done; for the image, in SIMD, later.
    if (image) {
      const VertexDepth d[3] = {sc.depth[order[0]], sc.depth[order[1]], sc.depth[order[2]]};
      const size_t at = image->sink->add(chunk, st, d);
      if (flat_shading) batch.add(at, (w0 + w1 + w2) / 3.0, face, surface);
    } else if (flat_shading) {
      st.flat_color = lit(scene, m, cam.eye, (w0 + w1 + w2) / 3.0, face);
    }
  }
  return true;
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

}  // namespace

void view_scene_chunks(const Scene& scene, int width, int height, const RasterSettings& s,
                       int threads, ScreenMesh& mesh,
                       std::vector<std::vector<ScreenTri>>& out_chunks, const ImageOnly* image) {
  out_chunks.clear();
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
  mesh = lockstep::view_frame(scene, width, height, lo, hi);
  const Camera& cam = mesh.camera;
  tbb::task_arena arena(resolve_threads(threads));

  const double near_z = mesh.near_z, g = kGuardBand * cam.pitch;
  // The image's stored depth (its sink's DepthMap: the same operations, so the same bits).
  const DepthMap depth_map(s.depth, mesh.near_z, mesh.far_z);

  // The projection of the vertices (spheres' and polygons').
  Projection proj;
  for (int c = 0; c < 3; ++c) {
    proj.eye[c] = cam.eye[c], proj.right[c] = cam.right[c], proj.up[c] = cam.up[c];
    proj.forward[c] = cam.forward[c];
  }
  proj.near_z = near_z, proj.g = g, proj.pitch = cam.pitch;
  proj.half_w = 0.5 * cam.width, proj.half_h = 0.5 * cam.height;
  // Spheres, as view_spheres: each sphere's ring count first (0: outside the
  // view), then one unit sphere per ring count in use (the sines and cosines
  // once per frame, not once per sphere), then chunks of spheres in parallel,
  // each into its own mesh; the chunks' triangles then follow one another in
  // sphere order, as in view_scene.
  const uint32_t spheres = scene.sphere_count();
  std::vector<int> rings(spheres, 0);
  std::vector<Vec3> centre(spheres);  // eye space
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, spheres, 1024),
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
  std::vector<UnitSphere> units(kMaxRings + 1);
  std::vector<UnitFaces> faces(kMaxRings + 1);  // per ring count
  {
    std::vector<char> used(kMaxRings + 1, 0);
    for (const int n : rings) used[size_t(n)] = 1;
    std::vector<int> counts;
    for (int n = 1; n <= kMaxRings; ++n)
      if (used[size_t(n)]) counts.push_back(n);
    arena.execute([&] {
      tbb::parallel_for(size_t(0), counts.size(),
                        [&](size_t i) {
                          const size_t n = size_t(counts[i]);
                          units[n] = unit_sphere(counts[i]);
                          faces[n] = unit_faces(units[n]);
                        });
    });
  }
  // The image: the hidden spheres' occluders (every sphere's inner ball), before
  // any sphere is tessellated.
  std::optional<OcclusionMap> occlusion;
  if (image && s.skip_hidden && std::any_of(rings.begin(), rings.end(), [](int n) { return n != 0; })) {
    occlusion.emplace(cam, width, height, near_z, mesh.far_z);
    for (uint32_t k = 0; k < spheres; ++k)
      if (rings[k] != 0)
        occlusion->add(centre[k], std::abs(scene.sphere_radius[k]), !(scene.sphere_radius[k] > 0),
                       faces[size_t(rings[k])].inner);
    occlusion->finish();
  }
  // At most 16 spheres a chunk (a few big spheres are as much work as many
  // small ones), at most 64 chunks (each chunk gets its own bins per tile).
  const uint32_t spheres_per_chunk =
      std::max({1u, std::min<uint32_t>(16, (spheres + 7) / 8), (spheres + 63) / 64});
  std::vector<ScreenMesh> sphere_chunks((spheres + spheres_per_chunk - 1) / spheres_per_chunk);
  // Polygons: 16 chunks or more (after the spheres' chunks, for the sink), of
  // 512 to 4096 polygons (each chunk has its own buffers and its own bins per
  // tile: 2048 rather than 512 for sombrero-3's 32k, 5% faster frames).
  const uint32_t polys = scene.polygon_count();
  const uint32_t per_chunk = std::clamp<uint32_t>((polys + 15) / 16, 512, 4096);
  const uint32_t nchunks = (polys + per_chunk - 1) / per_chunk;
  if (image) image->sink->begin(mesh, sphere_chunks.size() + nchunks);
  arena.execute([&] {
    tbb::parallel_for(size_t(0), sphere_chunks.size(), [&](size_t c) {
      ScreenMesh& part = sphere_chunks[c];
      part.camera = cam;
      part.width = width;
      part.height = height;
      part.near_z = mesh.near_z;
      part.far_z = mesh.far_z;
      const uint32_t first = uint32_t(c) * spheres_per_chunk;
      const uint32_t last = std::min(spheres, first + spheres_per_chunk);
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
        if (!view_sphere(scene, s, cam, proj, k, units[size_t(rings[k])],
                         faces[size_t(rings[k])], image, depth_map,
                         occlusion ? &*occlusion : nullptr, c, batch, scratch, part)) {
          const size_t before = part.tris.size();
          lockstep::view_spheres(scene, s, k, k + 1, part);
          if (image) to_sink(*image, c, part.tris, before);
        }
      }
      if (image) batch.light(image->light, *image->sink, c);
    });
  });
  for (ScreenMesh& part : sphere_chunks) {
    mesh.sphere_tris += part.sphere_tris;
    mesh.culled += part.culled;
    mesh.clipped += part.clipped;
    mesh.degenerate += part.degenerate;
    mesh.hidden += part.hidden;
    if (!part.tris.empty()) out_chunks.push_back(std::move(part.tris));
  }

  // Every polygon vertex once: eye space, the clip test, the snapped screen
  // position (and for the image w and the stored depth), a chunk of polygons
  // at a time; for a positions-only sink, not those of the chunk's runs of 16
  // or more single-triangle polygons (triangle_run): polygon_run projects them
  // itself, from the world coordinates it reads anyway (the same operations).
  // (A polygon's vertices are its own: vertex[poly_first[p] .. poly_first[p + 1]).)
  std::vector<ProjectedVertex, NoInitAllocator<ProjectedVertex>> pv(scene.vertex.size());
  // The image's, per vertex.
  std::vector<VertexDepth, NoInitAllocator<VertexDepth>> pvd(image ? scene.vertex.size() : 0);
  const bool positions = image && image->sink->positions_only();
  // The vertices of polygons [p0, p1).
  auto project = [&](uint32_t p0, uint32_t p1) {
    const uint32_t v0 = scene.poly_first[p0], v1 = scene.poly_first[p1];
    if (v1 > v0)
      project_vertices(proj, scene.vertex.data() + v0, v1 - v0, pv.data() + v0,
                       image ? &depth_map : nullptr, image ? pvd.data() + v0 : nullptr);
  };
  std::vector<std::vector<std::array<uint32_t, 2>>> runs(nchunks);  // per chunk: [begin, end)
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
    const size_t sink_chunk = sphere_chunks.size() + c;
    const uint32_t first = c * per_chunk, last = std::min(polys, first + per_chunk);
    const size_t expect = size_t(scene.poly_tri_first[last] - scene.poly_tri_first[first]);
    FlatBatch batch;
    if (image) {
      image->sink->reserve(sink_chunk, expect);
      if (s.shading == Shading::kFlat) batch.reserve(expect);
    } else {
      out.tris.reserve(expect);
    }
    ScreenTri local;
    // A positions-only sink gets the triangles a run at a time (flushed before a
    // polygon that goes through view_polygons, so that the order stays).
    // (The pending triangles' vertices in the raster's order.)
    PackedTris pending;
    auto flush = [&] {
      const size_t n = pending.n;
      if (n == 0) return;
      const size_t at = image->sink->add_positions(sink_chunk, pending.view(), n);
      batch.offset_last(n, at);
      pending.n = 0;
    };
    // The lighting's inputs of the last material seen (meshes share one).
    uint32_t surface_of = UINT32_MAX;
    FlatBatch::Surface surface(scene.materials.empty() ? Material{} : scene.materials[0]);
    auto polygon = [&](uint32_t p) {
      const Material& m = scene.materials[scene.poly_material[p]];
      if (scene.poly_material[p] != surface_of)
        surface = FlatBatch::Surface(m), surface_of = scene.poly_material[p];
      const Vec3 face = scene.poly_plane[p].n;
      if (dot(face, face) == 0) return;  // length(face) == 0, without the square root
      const uint32_t t_first = scene.poly_tri_first[p], t_last = scene.poly_tri_first[p + 1];
      // A vertex outside the hither plane or the guard band: a triangle may
      // need clipping, so view_scene's own polygon step, on this polygon.
      bool inside = true;
      for (uint32_t t = t_first; t < t_last; ++t)
        for (const uint32_t vi : scene.tri_vertex[t]) inside = inside && pv[vi].inside;
      if (!inside) {
        if (positions) flush();
        ScreenMesh part = frame;
        lockstep::view_polygons(scene, s, p, p + 1, part);
        if (image)
          to_sink(*image, sink_chunk, part.tris, 0);
        else
          out.tris.insert(out.tris.end(), part.tris.begin(), part.tris.end());
        out.scene_tris += part.scene_tris;
        out.culled += part.culled;
        out.degenerate += part.degenerate;
        out.clipped += part.clipped;
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
        if (positions) {  // (flat shading: one lighting request each)
          pending.push(pv.data(), pvd.data(), order);
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
          const VertexDepth d[3] = {pvd[order[0]], pvd[order[1]], pvd[order[2]]};
          const size_t at = image->sink->add(sink_chunk, st, d);
          if (s.shading == Shading::kFlat) batch.add(at, centroid, face, surface);
        }
      }
    };
    // The chunk's runs of single-triangle polygons (positions only):
    // polygon_run, a vector of polygons at a time, then polygon by polygon past
    // what it did (the run's tail, or the vector holding a polygon that may
    // need clipping), their vertices projected first.
    size_t next_run = 0;
    for (uint32_t p = first; p < last;) {
      if (next_run == runs[c].size() || p != runs[c][next_run][0]) {
        polygon(p++);
        continue;
      }
      const uint32_t run_end = runs[c][next_run++][1];
      const uint32_t material = scene.poly_material[p];
      if (material != surface_of)
        surface = FlatBatch::Surface(scene.materials[material]), surface_of = material;
      const bool two_sided = scene.materials[material].two_sided();
      while (p < run_end) {
        static_assert(sizeof(Plane) == 4 * sizeof(double) && offsetof(Plane, n) == 0);
        PolygonRun run;
        run.plane = &scene.poly_plane[p].n.x;
        run.world = scene.vertex.data() + scene.poly_first[p];
        run.proj = &proj;
        run.depth = &depth_map;
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
        project(p, stop);
        while (p < stop) polygon(p++);
      }
    }
    if (positions) flush();
    if (image) batch.light(image->light, *image->sink, sink_chunk);
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
