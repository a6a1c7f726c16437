// lockstep optimized: radiosity (optimized/radiosity_simd.h).
#include "optimized/radiosity_simd.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include "core/error.h"
#include "core/timer.h"
#include "optimized/radiosity_simd_kernels.h"
#include "optimized/tiling.h"
#include "optimized/zbuffer/zbuffer_simd.h"

namespace lockstep::opt::simd {

namespace {


// The scene's triangles in Embree, moved to be centred on the origin (float
// keeps relative precision near the scene, not near the world origin).
struct Occluders {
  RTCScene scene = nullptr;
  Vec3 centre;
  const uint32_t* tri_poly = nullptr;  // Embree primID -> scene polygon
  ~Occluders() {
    if (scene) rtcReleaseScene(scene);
  }
};

// A query's context: the polygon the rays leave from, and per ray (its id)
// the polygon it arrives at; hits on either are not blockers (as the
// reference's segment_clear).
struct SkipContext {
  RTCIntersectContext base;
  const Occluders* occ = nullptr;
  uint32_t from = 0;
  const uint32_t* to = nullptr;
};

void skip_own_polygons(const RTCFilterFunctionNArguments* args) {
  const auto* ctx = reinterpret_cast<const SkipContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const uint32_t poly = ctx->occ->tri_poly[RTCHitN_primID(args->hit, args->N, i)];
    if (poly == ctx->from || poly == ctx->to[RTCRayN_id(args->ray, args->N, i)]) args->valid[i] = 0;
  }
}

void build(Occluders& o, const Scene& scene, const embree::Device& device) {
  Vec3 lo, hi;
  scene_bounds(scene, lo, hi);
  o.centre = (lo + hi) * 0.5;
  o.scene = rtcNewScene(device.handle);
  RTCGeometry g = rtcNewGeometry(device.handle, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), scene.vertex.size()));
  for (size_t i = 0; i < scene.vertex.size(); ++i) {
    const Vec3 p = scene.vertex[i] - o.centre;
    v[3 * i] = float(p.x), v[3 * i + 1] = float(p.y), v[3 * i + 2] = float(p.z);
  }
  auto* t = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                           3 * sizeof(unsigned), scene.tri_vertex.size()));
  for (size_t i = 0; i < scene.tri_vertex.size(); ++i)
    for (int k = 0; k < 3; ++k) t[3 * i + k] = scene.tri_vertex[i][k];
  o.tri_poly = scene.tri_poly.data();
  rtcSetGeometryOccludedFilterFunction(g, skip_own_polygons);
  rtcCommitGeometry(g);
  rtcAttachGeometry(o.scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(o.scene);
}

// An axis-aligned box; overlaps: their interiors meet (boxes that only touch
// hold no segment of one that crosses the other's polygon).
struct Box {
  Vec3 lo{kInfinity, kInfinity, kInfinity}, hi{-kInfinity, -kInfinity, -kInfinity};
  void add(const Vec3& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  bool overlaps(const Box& b) const {
    return lo.x < b.hi.x && b.lo.x < hi.x && lo.y < b.hi.y && b.lo.y < hi.y && lo.z < b.hi.z && b.lo.z < hi.z;
  }
};

// The pyramid from an apex c over a convex planar polygon (c in front of
// its plane): every segment from c to a point of the polygon lies in it.
// Its faces as planes through a point, normals pointing inwards: the
// polygon's plane and one through c and each edge. Default: no planes
// (excludes nothing).
struct Pyramid {
  Vec3 origin[9], inward[9];  // inward: unit normals
  int planes = 0;
  double slack = 0;
  Pyramid() = default;
  // slack: how far beyond a face a corner must be to count (rounding's
  // reach, 1e-9 of the scene and of its largest coordinate).
  Pyramid(const Vec3& c, std::span<const Vec3> base, double beyond) : slack(beyond) {
    if (base.size() < 3 || base.size() > 8) return;
    Vec3 area{0, 0, 0}, mid{0, 0, 0};
    for (size_t k = 0; k < base.size(); ++k) {
      area = area + cross(base[k] - base[0], base[(k + 1) % base.size()] - base[0]);  // relative: no cancellation far out
      mid = mid + base[k];
    }
    mid = mid / double(base.size());
    // The apex clearly in front of the base's plane (else: no planes).
    const Vec3 r = c - base[0];
    double h = dot(area, r);
    if (!(h * h > 1e-18 * dot(area, area) * dot(r, r))) return;
    add(base[0], h > 0 ? area : -area);
    for (size_t k = 0; k < base.size(); ++k) {
      Vec3 m = cross(base[k] - c, base[(k + 1) % base.size()] - c);
      if (dot(m, mid - c) < 0) m = -m;
      add(c, m);
    }
  }
  void add(const Vec3& o, const Vec3& m) {
    const double len = length(m);
    if (!(len > 0) || !std::isfinite(len)) return;  // no plane: excludes nothing by it
    origin[planes] = o, inward[planes++] = m / len;
  }
  // Whether polygon v lies wholly outside: all its corners more than slack
  // beyond one face (so rounding never culls a blocker).
  bool excludes(std::span<const Vec3> v) const {
    for (int f = 0; f < planes; ++f) {
      bool beyond = true;
      for (const Vec3& q : v)
        if (!(dot(inward[f], q - origin[f]) < -slack)) {
          beyond = false;
          break;
        }
      if (beyond) return true;
    }
    return false;
  }
};

// A 2-D box in a plane frame, closed (boxes that touch overlap).
struct Box2 {
  double lo[2] = {kInfinity, kInfinity}, hi[2] = {-kInfinity, -kInfinity};
  void add(const std::array<double, 2>& p) {
    for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
  }
  bool overlaps(const Box2& b) const {
    return lo[0] <= b.hi[0] && b.lo[0] <= hi[0] && lo[1] <= b.hi[1] && b.lo[1] <= hi[1];
  }
};

// Whether a planar polygon is convex: every corner turns the same way.
bool convex(std::span<const Vec3> v) {
  if (v.size() < 3) return false;
  Vec3 area{0, 0, 0};
  for (size_t k = 0; k < v.size(); ++k) area = area + cross(v[k] - v[0], v[(k + 1) % v.size()] - v[0]);
  for (size_t k = 0; k < v.size(); ++k) {
    const Vec3& a = v[k];
    const Vec3& b = v[(k + 1) % v.size()];
    const Vec3& c = v[(k + 2) % v.size()];
    if (!(dot(cross(b - a, c - b), area) > 0)) return false;
  }
  return true;
}

// A scene polygon as the plane its patches' targets lie on (or near: the
// Cornell box's measured walls are warped by up to 1.6 mm): a point o on
// it, its unit normal n (Newell's), two unit axes u, v in it; thickness:
// how far its corners and targets lie off the plane.
struct Receiver {
  uint32_t polygon = 0;
  Vec3 o, n, u, v;
  Box box;
  double thickness = 0;
  bool pyramid = false;       // convex and flat: the pyramid from a point over it holds every segment to it
  bool flat_targets = false;  // its patches' targets on its plane
  std::span<const Vec3> corners;
  Receiver(uint32_t p, std::span<const Vec3> w, double size) : polygon(p), corners(w) {
    Vec3 area{0, 0, 0};
    for (size_t k = 0; k < w.size(); ++k) area = area + cross(w[k] - w[0], w[(k + 1) % w.size()] - w[0]);
    o = w[0];
    n = normalize(area);
    u = normalize(std::abs(n.x) < 0.5 ? cross(n, Vec3{1, 0, 0}) : cross(n, Vec3{0, 1, 0}));
    v = cross(n, u);
    for (const Vec3& x : w) box.add(x), thickness = std::max(thickness, std::abs(height(x)));
    pyramid = convex(w) && thickness <= 1e-12 * size;
  }
  double height(const Vec3& x) const { return dot(n, x - o); }
  std::array<double, 2> flat(const Vec3& x) const { return {dot(x - o, u), dot(x - o, v)}; }
};

// A flat receiver's patches binned on a kBins x kBins grid over its
// targets' box. Cells: the bins a box covers, clamped to the grid (monotone:
// a box overlapping another shares a bin with it).
constexpr int kBins = 16;
constexpr size_t kCells = size_t(kBins) * kBins;
int cell(const Box2& grid, double v, int axis) {
  const double w = grid.hi[axis] - grid.lo[axis];
  const double k = w > 0 ? std::floor((v - grid.lo[axis]) / w * kBins) : 0;
  return k >= double(kBins - 1) ? kBins - 1 : k > 0 ? int(k) : 0;  // NaN: 0 (never an index outside)
}
struct Cells {
  int x0, x1, y0, y1;
  Cells(const Box2& grid, const Box2& b)
      : x0(cell(grid, b.lo[0], 0)), x1(cell(grid, b.hi[0], 0)), y0(cell(grid, b.lo[1], 1)), y1(cell(grid, b.hi[1], 1)) {}
};

// Shadow polygons (Atherton, Weiler and Greenberg 1978, here as a filter):
// seen from c, a blocker that meets the segment from c to a target y
// covers y's central projection y' onto the receiver's plane, and only
// the part of it between c and y counts. So each candidate blocker (a
// convex flat polygon whole, else each triangle) is clipped to the heights
// a segment passes through (from kSegmentMargin to 1 - kSegmentMargin of
// its length, widened by the receiver's thickness and rounding's reach),
// projected from c (which keeps it convex) and grown by 1e-9 of the scene
// and of its largest coordinate: its shade. A
// target whose y' falls in no shade arrives; one deep in a shade's core
// (the blocker's part clear of both ends) is hidden; the rest are decided
// by the exact predicate (segment_meets_triangle) against that blocker's
// triangles: the reference's answer, found without testing every triangle.

struct Shade {
  Box2 box;
  uint32_t tri_first = 0, tri_end = 0;  // the blocker's triangles (the scene's, in order)
  HalfPlanes outer;  // the shade, grown (Shadow::grow): nothing outside is hidden
  // The core: the shade of the blocker's part clear of either end of the
  // heights (2 Shadow::rise above the plane's end, a thousandth of the
  // height below c; the receiver flat). A point more than Shadow::grow
  // inside it is hidden: its segment crosses the blocker's interior, well
  // within the segment and well inside the blocker's edges.
  HalfPlanes core;
  double deep = 0;
  bool has_core = false;
  // -1: outside; 0: the exact predicate decides; 1: hidden.
  int covers(const std::array<double, 2>& y) const {
    if (!outer.inside(y, 0)) return -1;
    return has_core && core.inside(y, deep) ? 1 : 0;
  }
};

struct Shadow {
  const Receiver* to = nullptr;
  Vec3 c;
  std::array<double, 2> c_flat;
  double h = 0, side = 1, grow = 0, rise = 0, lo = 0, hi = 0;
  bool valid = false;
  // size: the scene's; far: its largest coordinate (rounding's scale).
  Shadow(const Vec3& apex, const Receiver& r, double size, double far) : to(&r), c(apex), c_flat(r.flat(apex)) {
    h = r.height(c);
    if (h < 0) h = -h, side = -1;
    // Rounding's reach: heights (differences of nearby points) to about
    // 1e-15 of the coordinates, so 1e-12 of them; positions on the plane
    // magnified up to 1 / kSegmentMargin by the projection, so 1e-9.
    grow = 1e-9 * (size + far);
    rise = 1e-12 * (size + far);
    const double m = kSegmentMargin;
    lo = m * h - r.thickness - rise;
    hi = (1 - m) * h + m * r.thickness + rise;
    // c clearly off the plane, and the heights clear of c's own.
    valid = h > 1e-6 * size && hi < (1 - 0.5 * m) * h;
  }
  // Where the line from c through x meets the plane: x' in flat
  // coordinates (x_height: x's height as Receiver::height gives it).
  std::array<double, 2> project(const std::array<double, 2>& x_flat, double x_height) const {
    const double t = h / (h - side * x_height);
    return {c_flat[0] + (x_flat[0] - c_flat[0]) * t, c_flat[1] + (x_flat[1] - c_flat[1]) * t};
  }
  // The blocker's part at heights [low, high], projected: its corners into
  // p (room for 10), their count.
  int clip(std::span<const Vec3> poly, double low, double high, std::array<double, 2>* p) const {
    const int corners = int(poly.size());
    int m = 0;
    auto put = [&](const Vec3& x, double hx) { p[m++] = project(to->flat(x), side * hx); };
    for (int k = 0; k < corners; ++k) {
      const Vec3& a = poly[size_t(k)];
      const Vec3& b = poly[size_t((k + 1) % corners)];
      const double ha = side * to->height(a), hb = side * to->height(b);
      if (ha >= low && ha <= high) put(a, ha);
      // Where the edge enters or leaves the heights, in order from a to b.
      double cut[2];
      int cuts = 0;
      for (double level : {low, high})
        if ((ha < level) != (hb < level)) cut[cuts++] = (level - ha) / (hb - ha);
      if (cuts == 2 && cut[0] > cut[1]) std::swap(cut[0], cut[1]);
      for (int q = 0; q < cuts; ++q) put(a + (b - a) * cut[q], ha + (hb - ha) * cut[q]);
    }
    return m;
  }
  // Adds the shade of a convex planar blocker of at most 8 corners (a
  // triangle, or a polygon whose triangles are the scene's [tri_first,
  // tri_end)); nothing when no part of it is in the heights.
  // Returns false when the shade does not come out finite (then the
  // receiver's segments go to Embree).
  bool add(std::span<const Vec3> poly, uint32_t tri_first, uint32_t tri_end, std::vector<Shade>& out) const {
    std::array<double, 2> p[10];
    const int m = clip(poly, lo, hi, p);
    if (m < 3) return true;
    for (int k = 0; k < m; ++k)
      if (!std::isfinite(p[k][0]) || !std::isfinite(p[k][1])) return false;
    Shade s;
    s.tri_first = tri_first, s.tri_end = tri_end;
    s.outer.set(p, m, grow);
    for (int k = 0; k < m; ++k) {
      s.box.add({p[k][0] - grow, p[k][1] - grow});
      s.box.add({p[k][0] + grow, p[k][1] + grow});
    }
    if (to->flat_targets) {
      // Not within a thousandth of the segment from c either: there the
      // projection magnifies more than 1000 times, and 1e-9 of the scene
      // on the plane would be rounding's size on the blocker.
      const int mc = clip(poly, kSegmentMargin * h + 2 * rise, (1 - 1e-3) * h, p);
      if (mc >= 3) {
        s.core.set(p, mc, 0);
        s.deep = grow;
        s.has_core = s.core.edges > 0;
      }
    }
    out.push_back(s);
    return true;
  }
};

// The patches as structure of arrays for lambert_row, padded to 16 lanes.
PatchSoA patch_soa(const PatchMesh& mesh) {
  PatchSoA p;
  p.count = mesh.patches.size();
  p.padded = (p.count + 15) / 16 * 16;
  for (int k = 0; k < 4; ++k) {
    p.x[k].assign(p.padded, 0.0);
    p.y[k].assign(p.padded, 0.0);
    p.z[k].assign(p.padded, 0.0);
  }
  p.nx.assign(p.padded, 0.0);  // padding: a zero normal faces nothing
  p.ny.assign(p.padded, 0.0);
  p.nz.assign(p.padded, 0.0);
  for (size_t j = 0; j < p.count; ++j) {
    const Patch& q = mesh.patches[j];
    for (int k = 0; k < 4; ++k) {
      const Vec3& v = q.v[k < q.count ? k : q.count - 1];
      p.x[k][j] = v.x, p.y[k][j] = v.y, p.z[k][j] = v.z;
    }
    const Vec3 n = q.normal();
    p.nx[j] = n.x, p.ny[j] = n.y, p.nz[j] = n.z;
  }
  return p;
}

}  // namespace

FormFactors radiosity_form_factors_rays(const Scene& scene, const PatchMesh& mesh, int k, int threads,
                                                const embree::Device& device,
                                                const std::function<void(double)>& progress, RayCounts* counts,
                                                FormFactorMethod method, FormFactors storage) {
  const bool exact = method == FormFactorMethod::exact;
  std::atomic<uint64_t> cast{0}, culled{0}, by_shades{0};
  const size_t n = mesh.patches.size();
  FormFactors f = std::move(storage);
  if (f.size() != n * n) f = FormFactors(n * n);  // each row written whole by its task: the first touch spread
  if (n == 0) return f;
  Occluders occ;
  const Stopwatch building;
  build(occ, scene, device);
  embree::Device(device).check("radiosity occluders");
  if (counts) counts->build_seconds = building.seconds();
  // Every patch's centre and targets once.
  std::vector<Vec3> centre(n), normal(n);
  std::vector<std::vector<Vec3>> targets(n);
  for (size_t i = 0; i < n; ++i) {
    centre[i] = mesh.patches[i].centre();
    normal[i] = mesh.patches[i].normal();
    targets[i] = patch_targets(mesh.patches[i], k);
  }
  const PatchSoA soa = patch_soa(mesh);
  // Scenes of more than kShadowPolygons polygons skip the shadows (every
  // pair casts through Embree): they cost polygons^2 a patch.
  constexpr uint32_t kShadowPolygons = 256;
  const uint32_t polys = scene.polygon_count();
  const bool shadows = polys <= kShadowPolygons;
  Vec3 lo, hi;
  scene_bounds(scene, lo, hi);
  const double size = length(hi - lo);
  // Far from the origin coordinates round at their own scale: the shades'
  // margins grow with it (Shadow).
  const double far = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y),
                               std::abs(hi.z)});
  const double slack = 1e-9 * (size + far);  // what the shaft's tests leave for rounding
  std::vector<Box> poly_box(polys);
  std::vector<unsigned char> whole_shade(polys);  // a blocker shaded whole: convex, flat, at most 8 corners
  std::vector<Receiver> receivers;
  for (uint32_t p = 0; p < polys; ++p) {
    for (const Vec3& v : scene.polygon_vertices(p)) poly_box[p].add(v);
    receivers.emplace_back(p, scene.polygon_vertices(p), size);
    whole_shade[p] = receivers.back().pyramid && scene.polygon_vertices(p).size() <= 8;
  }
  // Each target in its polygon's frame, and its height off the plane; the
  // box of each patch's targets; each receiver's box of its targets.
  std::vector<std::vector<std::array<double, 2>>> flat_targets(n);
  std::vector<std::vector<double>> target_height(n);
  std::vector<Box2> target_box(n), receiver_box(polys);
  std::vector<uint32_t> poly_of(n);  // each patch's polygon, packed (the pair loop's stride)
  for (size_t j = 0; j < n; ++j) poly_of[j] = uint32_t(mesh.patches[j].polygon);
  for (size_t j = 0; j < n; ++j) {
    const size_t q = size_t(mesh.patches[j].polygon);
    Receiver& r = receivers[q];
    for (const Vec3& y : targets[j]) {
      flat_targets[j].push_back(r.flat(y));
      target_height[j].push_back(r.height(y));
      target_box[j].add(flat_targets[j].back());
      r.thickness = std::max(r.thickness, std::abs(r.height(y)));
    }
    receiver_box[q].add({target_box[j].lo[0], target_box[j].lo[1]});
    receiver_box[q].add({target_box[j].hi[0], target_box[j].hi[1]});
  }
  // Targets within 1e-12 of the scene of a receiver's plane are taken as on
  // it where c is high enough above it (way 1 below).
  for (Receiver& r : receivers) r.flat_targets = r.thickness <= 1e-12 * size;
  // The targets of flat receivers' patches in bins, each in the bin that
  // holds it, as arrays (classify_points reads a run of bins at once): bin
  // b of receiver q holds [tgt_first[q * kCells + b], tgt_first[q * kCells
  // + b + 1]) of tgt_x, tgt_y (flat), tgt_patch, tgt_index (which of the
  // patch's targets).
  std::vector<uint32_t> tgt_first(size_t(polys) * kCells + 1, 0), tgt_patch;
  std::vector<double> tgt_x, tgt_y;
  std::vector<uint8_t> tgt_index;
  {
    auto bin_of = [&](size_t q, const std::array<double, 2>& y) {
      return q * kCells + size_t(cell(receiver_box[q], y[1], 1) * kBins + cell(receiver_box[q], y[0], 0));
    };
    for (size_t j = 0; j < n; ++j) {
      const size_t q = poly_of[j];
      if (receivers[q].flat_targets)
        for (const auto& y : flat_targets[j]) ++tgt_first[bin_of(q, y) + 1];
    }
    for (size_t b = 1; b < tgt_first.size(); ++b) tgt_first[b] += tgt_first[b - 1];
    const size_t total = tgt_first.back();
    tgt_x.resize(total), tgt_y.resize(total), tgt_patch.resize(total), tgt_index.resize(total);
    std::vector<uint32_t> next(tgt_first.begin(), tgt_first.end() - 1);
    for (size_t j = 0; j < n; ++j) {
      const size_t q = poly_of[j];
      if (!receivers[q].flat_targets) continue;
      for (size_t t = 0; t < flat_targets[j].size(); ++t) {
        const uint32_t g = next[bin_of(q, flat_targets[j][t])]++;
        tgt_x[g] = flat_targets[j][t][0], tgt_y[g] = flat_targets[j][t][1];
        tgt_patch[g] = uint32_t(j), tgt_index[g] = uint8_t(t);
      }
    }
  }
  parallel_tiles(int(n), 1, 4, 1, threads, progress, [&](int x0, int, int x1, int) {
    std::vector<double> lambert(soa.padded);
    std::vector<unsigned char> clip(soa.padded);
    std::vector<RTCRay> rays;
    std::vector<uint32_t> to;                      // per ray: the polygon it arrives at
    std::vector<std::pair<uint32_t, double>> row;  // (j, unoccluded factor) of the rays in order
    // Per receiver (scene polygon) R: the shadow from c and the shades on
    // it (first, count in `shades`).
    std::vector<Shadow> shadow;
    std::vector<Shade> shades;
    std::vector<uint32_t> first(polys + 1);
    // Flat receivers' targets found hidden (by their place in tgt_*), and
    // how many of each patch's; a run's verdicts.
    std::vector<unsigned char> hidden(tgt_x.size());
    std::vector<uint32_t> hidden_count(n);
    std::vector<signed char> verdict;
    std::vector<const Shade*> near;                // the shades over one patch's targets
    std::vector<unsigned char> way;
    std::vector<std::array<double, 2>> projected;  // one patch's targets, projected
    // Whether the segment from c to target y meets one of the shade's
    // blocker's triangles: the reference's own test.
    auto blocked = [&](const Vec3& c, const Vec3& y, const Shade& h) {
      for (uint32_t k = h.tri_first; k < h.tri_end; ++k) {
        const auto& tv = scene.tri_vertex[k];
        if (segment_meets_triangle(c, y - c, kSegmentMargin, 1 - kSegmentMargin, scene.vertex[tv[0]],
                                   scene.vertex[tv[1]], scene.vertex[tv[2]]))
          return true;
      }
      return false;
    };
    // Whether the segments to patch j's targets are hidden: the number
    // that arrive, given the shades over them (near) and their points on
    // the receiver's plane.
    auto arrive = [&](const Vec3& c, size_t j, const std::array<double, 2>* points) {
      const size_t count = targets[j].size();
      int arrived = int(count);
      for (size_t t = 0; t < count; ++t)
        for (const Shade* h : near) {
          const int inside = h->covers(points[t]);
          if (inside < 0) continue;
          if (inside > 0 || blocked(c, targets[j][t], *h)) {
            --arrived;
            break;
          }
        }
      return arrived;
    };
    for (int i = x0; i < x1; ++i) {
      double* f_row = &f[size_t(i) * n];
      rays.clear();
      to.clear();
      row.clear();
      const Vec3 c = centre[size_t(i)];
      const Vec3 o = c - occ.centre;
      // Lambert's factors from c to every patch at once; the few patches that
      // reach behind c's tangent plane by the reference's clipping code.
      // (exact: the area-to-area factor, scalar, per pair below).
      if (!exact) lambert_row(soa, c, normal[size_t(i)], lambert.data(), clip.data());
      for (size_t j = 0; j < n; ++j) {
        // (A clipped lane: centre_form_factor's steps, its centre and
        // normals computed once.)
        auto clipped = [&] {
          const Vec3 r = c - mesh.patches[j].v[0];
          if (j == size_t(i) || !(dot(normal[j], r) > 1e-9 * length(r))) return 0.0;
          return point_polygon_form_factor(c, normal[size_t(i)], mesh.patches[j].corners());
        };
        const double unoccluded = exact ? exact_form_factor(mesh, size_t(i), j) : clip[j] ? clipped() : lambert[j];
        f_row[j] = unoccluded > 0 ? unoccluded : 0.0;
      }
      const int from = mesh.patches[size_t(i)].polygon;
      // The shades on every receiver.
      shadow.clear();
      shades.clear();
      for (uint32_t q = 0; q < polys && shadows; ++q) {
        first[q] = uint32_t(shades.size());
        const Receiver& r = receivers[q];
        shadow.emplace_back(c, r, size, far);
        if (int(q) == from || !shadow.back().valid) continue;
        // Shaft culling (Haines and Wallace 1994): only polygons that
        // overlap the box of c and R, and reach into the pyramid from c
        // over R, can meet a segment to it.
        Box b = r.box;
        b.add(c);
        b.lo = b.lo - Vec3{slack, slack, slack}, b.hi = b.hi + Vec3{slack, slack, slack};
        const Pyramid shaft = r.pyramid ? Pyramid(c, r.corners, slack) : Pyramid{};  // else boxes alone
        for (uint32_t p = 0; p < polys; ++p) {
          if (int(p) == from || p == q || !poly_box[p].overlaps(b)) continue;
          if (shaft.excludes(scene.polygon_vertices(p))) continue;
          const uint32_t t0 = scene.poly_tri_first[p], t1 = scene.poly_tri_first[p + 1];
          if (whole_shade[p]) {
            if (!shadow.back().add(scene.polygon_vertices(p), t0, t1, shades)) shadow.back().valid = false;
            continue;
          }
          for (uint32_t t = t0; t < t1; ++t) {
            const auto& tv = scene.tri_vertex[t];
            const Vec3 tri[3] = {scene.vertex[tv[0]], scene.vertex[tv[1]], scene.vertex[tv[2]]};
            if (!shadow.back().add(tri, t, t + 1, shades)) shadow.back().valid = false;
          }
        }
      }
      first[polys] = uint32_t(shades.size());
      // Per receiver: 0 Embree; 1 its targets binned on its plane; 2 each
      // pair's targets projected from c. A flat receiver's targets stand
      // for their projections while c is high enough above it that their
      // rounding off the plane moves a projection by less than half a
      // shade's growth (thickness * size / h <= grow / 2).
      way.assign(polys, 0);
      for (uint32_t q = 0; q < polys && shadows; ++q)
        if (shadow[q].valid)
          way[q] = receivers[q].flat_targets &&
                           2 * receivers[q].thickness * size <= shadow[q].grow * shadow[q].h
                       ? 1
                       : 2;
      // Flat receivers: each shade against the targets in its bins (a run
      // of bins a row), classified a vector at a time; the exact test
      // where a target is near a shade's edge.
      std::fill(hidden.begin(), hidden.end(), 0);
      std::fill(hidden_count.begin(), hidden_count.end(), 0);
      uint64_t tests = 0;
      for (uint32_t q = 0; q < polys && shadows; ++q) {
        if (way[q] != 1) continue;
        for (uint32_t k = first[q]; k < first[q + 1]; ++k) {
          const Shade& h = shades[k];
          const Cells cells(receiver_box[q], h.box);
          for (int y = cells.y0; y <= cells.y1; ++y) {
            const size_t row0 = q * kCells + size_t(y * kBins);
            const uint32_t lo = tgt_first[row0 + size_t(cells.x0)], hi = tgt_first[row0 + size_t(cells.x1) + 1];
            if (lo == hi) continue;
            verdict.resize(hi - lo);
            classify_points(&tgt_x[lo], &tgt_y[lo], hi - lo, h.outer, h.core, h.deep, verdict.data());
            tests += hi - lo;
            for (uint32_t g = lo; g < hi; ++g) {
              // Eight targets outside the shade (verdict < 0: the sign bit)
              // skipped at once: most are.
              if (hi - g >= 8) {
                uint64_t word;
                std::memcpy(&word, &verdict[g - lo], 8);
                if ((word & 0x8080808080808080ull) == 0x8080808080808080ull) {
                  g += 7;
                  continue;
                }
              }
              const signed char v = verdict[g - lo];
              if (v < 0 || hidden[g]) continue;
              const uint32_t j = tgt_patch[g];
              if (!(f_row[j] > 0)) continue;
              if (v > 0 || blocked(c, targets[j][tgt_index[g]], h)) hidden[g] = 1, ++hidden_count[j];
            }
          }
        }
      }
      uint64_t spared = 0, shaded = tests;
      for (size_t j = 0; j < n; ++j) {
        const double unoccluded = f_row[j];
        if (!(unoccluded > 0)) continue;
        const uint32_t q = poly_of[j];
        if (way[q] == 1) {  // classified above
          const size_t m = targets[j].size();
          if (hidden_count[j] == 0)
            ++spared;  // every segment arrives: f_row[j] stands
          else
            f_row[j] = unoccluded * double(m - hidden_count[j]) / double(m);
          continue;
        }
        if (way[q] != 0) {
          near.clear();
          const std::array<double, 2>* points = flat_targets[j].data();
          {
            // A warped receiver: the targets' projections, every shade.
            Box2 box;
            projected.clear();
            for (size_t t = 0; t < targets[j].size(); ++t) {
              projected.push_back(shadow[q].project(flat_targets[j][t], target_height[j][t]));
              box.add(projected.back());
            }
            points = projected.data();
            for (uint32_t k = first[q]; k < first[q + 1]; ++k)
              if (shades[k].box.overlaps(box)) near.push_back(&shades[k]);
          }
          if (near.empty()) {
            ++spared;  // no segment can be blocked: f_row[j] stands
            continue;
          }
          shaded += targets[j].size();
          f_row[j] = unoccluded * arrive(c, j, points) / double(targets[j].size());
          continue;
        }
        // Else Embree: every segment cast.
        row.emplace_back(uint32_t(j), unoccluded);
        for (const Vec3& y : targets[j]) {
          const Vec3 d = y - c;
          RTCRay r{};
          r.org_x = float(o.x), r.org_y = float(o.y), r.org_z = float(o.z);
          r.dir_x = float(d.x), r.dir_y = float(d.y), r.dir_z = float(d.z);
          r.tnear = float(kSegmentMargin);
          r.tfar = float(1 - kSegmentMargin);
          r.mask = 0xffffffffu;
          r.flags = 0;
          r.id = unsigned(rays.size());
          rays.push_back(r);
          to.push_back(q);
        }
      }
      if (!rays.empty()) {
        SkipContext context;
        rtcInitIntersectContext(&context.base);
        context.occ = &occ;
        context.from = uint32_t(from);
        context.to = to.data();
        rtcOccluded1M(occ.scene, &context.base, rays.data(), unsigned(rays.size()), sizeof(RTCRay));
      }
      cast += rays.size();
      culled += spared;
      by_shades += shaded;
      // Blocked rays come back with tfar = -inf.
      size_t r = 0;
      for (const auto& [j, unoccluded] : row) {
        const size_t m = targets[j].size();
        int arrived = 0;
        for (size_t q = 0; q < m; ++q, ++r) arrived += rays[r].tfar >= 0 ? 1 : 0;
        f_row[j] = unoccluded * arrived / double(m);
      }
    }
  });
  if (counts) {
    counts->rays = cast;
    counts->culled_pairs = culled;
    counts->shaded = by_shades;
  }
  return f;
}

SolveResult solve_radiosity(const std::vector<Patch>& patches, const FormFactors& f, RadiositySolver solver,
                            double tolerance, int max_iterations, int threads, UninitVector<float>* single) {
  // Progressive refinement costs O(n) a shot: the shared solver.
  if (solver == RadiositySolver::progressive)
    return lockstep::solve_radiosity(patches, f, solver, tolerance, max_iterations);
  const double goal = tolerance * radiosity_system_check(patches, f);
  const size_t n = patches.size();
  tbb::task_arena arena(resolve_threads(threads));
  // The sweeps read F in float: each reads the matrix from memory (136 MB
  // at 4,119 patches in double), and half the bytes take half the time;
  // one pass makes the copy (on the threads), in the caller's storage when
  // it keeps one. B stays in double; a factor rounded to float moves B by
  // a relative 6e-8 of its share.
  UninitVector<float> own;
  UninitVector<float>& ff = single ? *single : own;
  if (ff.size() != n * n) ff = UninitVector<float>(n * n);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 16), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = r.begin() * n; k < r.end() * n; ++k) ff[k] = float(f[k]);
    });
  });
  // The system as structure of arrays, channel by channel.
  std::vector<double> e[3], rho[3], old_b[3], new_b[3];
  for (int c = 0; c < 3; ++c) {
    e[c].resize(n), rho[c].resize(n);
    for (size_t i = 0; i < n; ++i) e[c][i] = patches[i].emission[c], rho[c][i] = patches[i].rho[c];
    old_b[c] = e[c];
    new_b[c].resize(n);
  }
  const double* old_p[3] = {old_b[0].data(), old_b[1].data(), old_b[2].data()};
  const double* new_p[3] = {new_b[0].data(), new_b[1].data(), new_b[2].data()};
  // Row i in one pass over F's row: its residual in the last sweep's B (the
  // stopping test) and its new B_i (Jacobi from the last sweep's B,
  // Gauss-Seidel from this sweep's below i): sweep k+1 is computed with
  // the residual of sweep k, and dropped when that one is small enough.
  const bool gs = solver == RadiositySolver::gauss_seidel;
  auto row = [&](size_t i) {
    double g[9];
    gather_row(&ff[i * n], n, old_p, gs ? i : 0, new_p, g);
    double worst = 0;
    for (int c = 0; c < 3; ++c) {
      const double last = g[c] + g[6 + c];        // sum_j F_ij B_j, last sweep's B
      const double fresh = gs ? g[3 + c] + g[6 + c] : last;
      worst = std::max(worst, std::abs(old_b[c][i] - e[c][i] - rho[c][i] * last));
      new_b[c][i] = e[c][i] + rho[c][i] * fresh;
    }
    return worst;
  };
  SolveResult out;
  for (;;) {
    double worst = 0;
    if (gs) {  // in order: row i reads this sweep's B below i
      for (size_t i = 0; i < n; ++i) worst = std::max(worst, row(i));
    } else {  // Jacobi: rows independent, on the threads
      worst = arena.execute([&] {
        return tbb::parallel_reduce(
            tbb::blocked_range<size_t>(0, n, 64), 0.0,
            [&](const tbb::blocked_range<size_t>& r, double w) {
              for (size_t i = r.begin(); i < r.end(); ++i) w = std::max(w, row(i));
              return w;
            },
            [](double a, double b) { return std::max(a, b); });
      });
    }
    out.residual = worst;
    if (worst <= goal || out.iterations >= max_iterations) break;
    for (int c = 0; c < 3; ++c) old_b[c].swap(new_b[c]);
    std::swap(old_p, new_p);
    ++out.iterations;
  }
  out.b.resize(n);
  for (size_t i = 0; i < n; ++i) out.b[i] = {old_b[0][i], old_b[1][i], old_b[2][i]};
  return out;
}

FormFactors radiosity_form_factors_hemicube(const PatchMesh& mesh, int res, int threads,
                                                    const std::function<void(double)>& progress, FormFactors storage) {
  const size_t n = mesh.patches.size();
  FormFactors f = std::move(storage);
  if (f.size() != n * n) f = FormFactors(n * n);  // each row zeroed by its own task: the first touch spread
  const HemicubeWeights w = hemicube_weights(res);
  const RasterSettings s = radiosity_item_buffer();
  const Scene shared = patch_scene(mesh, View{});
  const double near = hemicube_near(mesh);
  parallel_tiles(int(n), 1, 4, 1, threads, progress, [&](int x0, int, int x1, int) {
    Scene items = shared;  // each task its own view
    Visibility vis;
    for (int i = x0; i < x1; ++i) {
      std::fill_n(&f[size_t(i) * n], n, 0.0);
      const Patch& from = mesh.patches[size_t(i)];
      const Vec3 c = from.centre(), normal = from.normal();
      for (int face = 0; face < 5; ++face) {
        items.view = hemicube_view(c, normal, face, res, near, hemicube_turn(size_t(i)));
        const ScreenMesh screen = view_scene(items, res, res, s, 1);
        zbuffer_visibility(screen, s, 1, vis);
        add_hemicube_face(mesh, items, screen, vis, w, size_t(i), face, &f[size_t(i) * n]);
      }
    }
  });
  return f;
}

Image radiosity_with(const Scene& scene, const FrameOptions& opts, FrameStats* stats, const embree::Device& device,
                     RadiosityScratch* scratch) {
  std::unique_lock<std::mutex> keep;
  if (scratch) keep = std::unique_lock<std::mutex>(scratch->busy, std::try_to_lock);
  FormFactors kept = keep.owns_lock() ? std::move(scratch->f) : FormFactors{};
  const RadiositySettings rs = radiosity_settings(opts.params, scene.source);
  auto part = [&](double lo, double hi) -> std::function<void(double)> {
    if (!opts.progress) return {};
    return [&opts, lo, hi](double x) { opts.progress(lo + (hi - lo) * x); };
  };
  RayCounts counts;
  RadiositySolution sol = solve_scene(
      scene, rs,
      [&](const PatchMesh& mesh, FormFactors storage) {
        if (storage.empty()) storage = std::move(kept);  // the session's, on the first round
        return rs.method == FormFactorMethod::hemicube
                   ? radiosity_form_factors_hemicube(mesh, rs.hemicube, opts.threads, part(0, 0.8), std::move(storage))
                   : radiosity_form_factors_rays(scene, mesh, rs.rays, opts.threads, device, part(0, 0.8), &counts,
                                                 rs.method, std::move(storage));
      },
      [&](const std::vector<Patch>& p, const FormFactors& m, RadiositySolver r, double t, int k) {
        return solve_radiosity(p, m, r, t, k, opts.threads, keep.owns_lock() ? &scratch->single : nullptr);
      });
  const PatchMesh& mesh = sol.mesh;
  const SolveResult& solved = sol.solved;
  if (keep.owns_lock()) scratch->f = std::move(sol.f);  // the next frame's storage
  const Scene items = patch_scene(mesh, scene.view);
  const RasterSettings s = radiosity_item_buffer();
  const ScreenMesh screen = view_scene(items, opts.width, opts.height, s, opts.threads);
  Visibility vis;
  zbuffer_visibility(screen, s, opts.threads, vis);
  const std::vector<Vec3> vertex_b = vertex_radiosity(mesh, solved.b);
  Image image = radiosity_image(items, mesh, vertex_b, screen, vis, scene.background);
  radiosity_sides(mesh, solved.b, vertex_b, opts, stats);
  if (stats) {
    radiosity_notes(sol, rs, *stats);
    stats->build_seconds = counts.build_seconds;  // the Embree BVH (rays, exact)
    if (rs.method != FormFactorMethod::hemicube)
      stats->counts.insert(stats->counts.end(), {{"rays", counts.rays},
                                                 {"shade_tests", counts.shaded},
                                                 {"clear_pairs", counts.culled_pairs}});
  }
  if (opts.progress) opts.progress(1.0);
  return image;
}

Image radiosity(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  return radiosity_with(scene, opts, stats, embree::Device::create());
}

}  // namespace lockstep::opt::simd
