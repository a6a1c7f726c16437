// lockstep optimized: splatting (see optimized/volume_splat_simd.h; the contract:
// core/volume_render.h; the reference: reference/volume_splat.cpp).
//
// The reference's method, its order and its sheets, computed faster:
//   classify      every voxel through the transfer function in double, as the
//                 reference, on TBB slabs of z slices; alpha = 0 voxels drop out;
//   order         the reference's stable sort by depth (depth computed by its
//                 expression, ties in index order) as a bucket sort: buckets
//                 by depth (monotone: a bucket never holds a deeper voxel than
//                 the next one), filled stably in index order, each sorted by
//                 (depth, index) -- the same permutation, in O(n); sheets (the
//                 reference's runs of equal depth) marked as it marks them;
//   bin           each splat's pixel box (the reference's: reach_x, reach_y
//                 around the projected centre) into image tiles of 64 x 32,
//                 chunk by chunk of the depth order, so a tile reads its
//                 splats in depth order;
//   footprint     q(x, y) = ixx dx^2 + 2 ixy dx dy + iyy dy^2 completes to
//                 a (x - m_y)^2 + c Y^2 on row y (m_y the row's centre, sheared
//                 by the covariance; Y = cy - y): the 2-D footprint exp(-q/2) is
//                 a row factor E(Y) times a 1-D profile G(x - m_y). Both are
//                 tabulated once per frame on a fine grid of S phases per pixel
//                 (row p of a table holds the profile at offsets j - p/S, so a
//                 footprint row is contiguous in the table), S chosen so that
//                 linear interpolation between phases is within 5e-6 of the
//                 peak (a / (8 S^2), a the Gaussian's curvature): no exp per
//                 pixel. Which pixels a footprint covers (q <= 9) is decided
//                 per row in double by the reference's own expression at the
//                 row's two ends (the span between is convex), so the row
//                 covers exactly the reference's pixels;
//   accumulate    per footprint row in Highway float vectors (8 lanes on AVX2,
//                 16 on AVX-512): tau = s E G, alpha = 1 - exp(-tau) (Highway's
//                 Expm1), w = (1 - A) alpha, C += w c, A += w, a pixel at
//                 A >= 1 - eps skipped. A sheet of one splat in a tile (any
//                 oblique view: every depth distinct) goes straight under the
//                 tile; a sheet of several (views along an axis) adds its optical
//                 depths per pixel first, then goes under at once, as the
//                 reference's sheet buffer;
//   tiles         TBB over the tiles (optimized/tiling.h): each tile
//                 composites the splats overlapping it, in depth order, into
//                 its own float buffers, so compositing order per pixel is the
//                 reference's.
// What differs from the reference: float against double (optical depths,
// compositing), the tables' interpolation, Highway's expm1; and where a pixel's
// opacity sits at 1 - eps, float and double may stop it one splat apart (a
// difference up to eps, as the ray caster's termination flips). The bound the
// row is held to, and what was measured: registry/volume_rows.cpp splat_family.
#ifndef LOCKSTEP_VOLUME_SPLAT_SHARED
#define LOCKSTEP_VOLUME_SPLAT_SHARED
#include <cstddef>
#include <cstdint>

#include "core/image.h"
#include "core/math.h"
#include "core/volume.h"
#include "core/volume_render.h"
#include "io/volume_settings.h"

namespace lockstep::opt::splat_kernels {

inline constexpr int kTileW = 64, kTileH = 32;  // at most
// Vectors of at most 8 floats (footprint rows are a few pixels wide), and the
// profile table's margin on either side of a row (a vector starts at most
// kLanes - 1 pixels before the footprint and ends as far past it).
inline constexpr int kLanes = 8;
inline constexpr int kPad = kLanes;

// A classified voxel: its depth (once in order, its sheet: the reference's
// runs of equal depth, numbered), the voxel and its value.
struct Key {
  double depth;
  uint32_t index;
  float value;
};
// What the transfer function gives it: sigma V norm (the optical depth at the
// footprint's peak) and its colour.
struct Colour {
  float s, r, g, b;
};
// The frame's two big arrays of n entries share one allocation per slot kind
// (fresh pages cost more than the work here: a page fault per 4 KB): the keys
// in index order become the colours in depth order.
union Slot {
  Key key;
  Colour colour;
};

// Everything a tile reads (built once per frame).
struct Ctx {
  const Volume* volume = nullptr;
  const vr::View* view = nullptr;
  int width = 0, height = 0;
  double pixel = 1;
  Vec3 right, up;
  double ixx = 0, iyy = 0, ixy = 0;  // the projected covariance's inverse (world units)
  int reach_x = 0, reach_y = 0;
  double shear = 0;   // ixy / ixx: row y's centre is m_y = cx - shear (cy - y)
  double row_c = 0;   // iyy - ixy^2 / ixx: q on row y is ixx (dx + shear dy)^2 + row_c dy^2
  double inv_ixx = 0, inv_pixel = 0;
  double ax = 0;      // ixx pixel^2: q = ax (x - m_y)^2 + row_c dy^2 in pixels
  int phases = 1;     // S
  int rt_x = 0, rt_y = 0;
  size_t len_x = 0, len_y = 0;
  const float* tx = nullptr;  // (S + 1) x len_x: G((j - kPad - rt_x) - p / S)
  const float* ty = nullptr;  // (S + 1) x len_y: E((j - rt_y) - p / S)
  bool terminate = false;
  float limit = 1;  // 1 - eps
  const Key* order = nullptr;       // depth order; depth holds the sheet
  const Slot* colour = nullptr;     // per position in order
  uint32_t nx = 1, ny = 1;
  double inv_nx = 1, inv_ny = 1;
};

// The reference's projected centre of voxel idx, in pixels, by its expression.
// idx / n by a reciprocal (exact after one correction: idx < 2^32).
inline uint32_t Divide(uint32_t idx, uint32_t n, double inv) {
  uint32_t q = uint32_t(double(idx) * inv);
  if (uint64_t(q) * n > idx) --q;
  else if (uint64_t(q + 1) * n <= idx) ++q;
  return q;
}

inline void Centre(const Ctx& c, uint32_t idx, double& cx, double& cy) {
  const uint32_t row = Divide(idx, c.nx, c.inv_nx), k = Divide(row, c.ny, c.inv_ny);
  const int i = int(idx - row * c.nx), j = int(row - k * c.ny);
  const Vec3 rel = c.volume->position(i, j, int(k)) - c.view->corner;
  cx = dot(rel, c.right) / c.pixel - 0.5;
  cy = -dot(rel, c.up) / c.pixel - 0.5;
}

}  // namespace lockstep::opt::splat_kernels
#endif  // LOCKSTEP_VOLUME_SPLAT_SHARED

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "optimized/volume_splat_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/aligned_allocator.h"
#include "hwy/contrib/math/math-inl.h"
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace lockstep::opt::splat_kernels {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Vectors are aligned to the tile's rows (x - x0 a multiple of the lanes), so
// that a splat's loads of the tile's buffers meet the previous splat's stores
// at the same addresses (unaligned, overlapping ones failed store forwarding:
// 3x slower).
using DF = hn::CappedTag<float, kLanes>;
using VF = hn::Vec<DF>;

// A tile's planes: the image under construction (C, A) and the sheet being
// gathered (optical depth and optical depth times colour), row stride `stride`
// (padded by a vector: the last vector of a row may run past the tile).
struct Tile {
  int x0, y0, x1, y1;
  size_t stride;
  float* acc[4];    // r, g, b, a
  float* sheet[4];  // tau, tau r, tau g, tau b
  int bx0, by0, bx1, by1;  // the sheet's box (inclusive; empty when bx0 > bx1)
};

// The reference's test: does the footprint centred at (cx, cy) cover pixel
// (x, y)? Its expression, in double (the build does not contract to FMA).
HWY_INLINE bool Covers(const Ctx& c, double cx, double cy, int x, int y) {
  const double dx = (x - cx) * c.pixel, dy = (cy - y) * c.pixel;
  const double q = c.ixx * dx * dx + 2 * c.ixy * dx * dy + c.iyy * dy * dy;
  return !(q > 9.0);
}

// One splat into the tile: fused (a sheet of one here: straight under the
// tile's image) or gathered into the sheet planes.
template <bool kFused>
HWY_INLINE void Footprint(const Ctx& c, uint32_t at, Tile& t) {
  const DF d;
  const size_t N = hn::Lanes(d);
  const uint32_t idx = c.order[at].index;
  const Colour& sp = c.colour[at].colour;
  double cx, cy;
  Centre(c, idx, cx, cy);
  const int bx0 = std::max({0, int(std::floor(cx)) - c.reach_x, t.x0});
  const int bx1 = std::min({c.width - 1, int(std::ceil(cx)) + c.reach_x, t.x1 - 1});
  const int by0 = std::max({0, int(std::floor(cy)) - c.reach_y, t.y0});
  const int by1 = std::min({c.height - 1, int(std::ceil(cy)) + c.reach_y, t.y1 - 1});
  if (bx0 > bx1 || by0 > by1) return;
  const int S = c.phases;
  // The row factor's phase (cy's fraction).
  const double fby = std::floor(cy);
  const int iby = int(fby);
  const double uy = (cy - fby) * S;
  const int py = std::min(int(uy), S - 1);
  const float fy = float(uy - py);
  const float* eya = c.ty + size_t(py) * c.len_y;
  const float* eyb = eya + c.len_y;
  const VF s = hn::Set(d, sp.s);
  const VF one = hn::Set(d, 1.0f), zero = hn::Zero(d), limit = hn::Set(d, c.limit);
  const VF cr = hn::Set(d, sp.r), cg = hn::Set(d, sp.g), cb = hn::Set(d, sp.b);
  for (int y = by0; y <= by1; ++y) {
    // The covered span of row y: around the row's centre m, half-width h where
    // ax (x - m)^2 = 9 - row_c dy^2. Its ends are where the reference's q
    // crosses 9; where an end lies within rounding of an integer (q's error,
    // ~1e-14, over its slope 2 ax h along the row, with a wide margin) the
    // reference's own expression decides.
    const double dyw = (cy - y) * c.pixel;
    const double m = cx - c.shear * (cy - y);
    const double rem = 9.0 - c.row_c * dyw * dyw;
    int lo, hi;
    const double h = rem > 0 ? std::sqrt(rem * c.inv_ixx) * c.inv_pixel : 0.0;
    if (!(h > 1e-6)) {
      lo = hi = int(std::lround(m));
      if (!Covers(c, cx, cy, lo, y)) continue;
    } else {
      const double lf = m - h, hf = m + h;
      lo = int(std::ceil(lf));
      hi = int(std::floor(hf));
      // (With ax h >= 1e-3, 1e-6 covers 1e-9 / (ax h); below, always decide.)
      const double tol = c.ax * h >= 1e-3 ? 1e-6 : 2.0;
      if (lo - lf < tol || lf - (lo - 1) < tol) {
        for (int n = 0; n < 3 && Covers(c, cx, cy, lo - 1, y); ++n) --lo;
        while (lo <= hi + 1 && !Covers(c, cx, cy, lo, y)) ++lo;
      }
      if (hf - hi < tol || (hi + 1) - hf < tol) {
        for (int n = 0; n < 3 && Covers(c, cx, cy, hi + 1, y); ++n) ++hi;
        while (hi >= lo - 1 && !Covers(c, cx, cy, hi, y)) --hi;
      }
    }
    const double fb = std::floor(m);
    const int b = int(fb);
    lo = std::max({lo, bx0, b - c.rt_x + 1});
    hi = std::min({hi, bx1, b + c.rt_x});
    if (lo > hi) continue;
    // The profile's phase (m's fraction) and the row factor.
    const double u = (m - fb) * S;
    const int p = std::min(int(u), S - 1);
    const VF f = hn::Set(d, float(u - p));
    const size_t jy = size_t(y - iby + c.rt_y);
    const float e = eya[jy] + fy * (eyb[jy] - eya[jy]);
    const VF rs = hn::Mul(s, hn::Set(d, e));
    const int xa = t.x0 + (lo - t.x0) / int(N) * int(N);
    const float* ga = c.tx + size_t(p) * c.len_x + size_t(xa - b + c.rt_x + kPad);
    const float* gb = ga + c.len_x;
    const size_t row = size_t(y - t.y0) * t.stride;
    const VF flo = hn::Set(d, float(lo)), fhi = hn::Set(d, float(hi));
    for (int x = xa; x <= hi; x += int(N)) {
      const size_t o = row + size_t(x - t.x0);
      const size_t q = size_t(x - xa);
      const VF a0 = hn::LoadU(d, ga + q);
      const VF tau = hn::Mul(rs, hn::MulAdd(f, hn::Sub(hn::LoadU(d, gb + q), a0), a0));
      const VF A = hn::Load(d, t.acc[3] + o);
      const VF xs = hn::Iota(d, float(x));
      auto mask = hn::And(hn::And(hn::Ge(xs, flo), hn::Le(xs, fhi)), hn::Gt(tau, zero));
      if (c.terminate) mask = hn::And(mask, hn::Lt(A, limit));
      if (hn::AllFalse(d, mask)) continue;
      if constexpr (kFused) {
        const VF alpha = hn::Neg(hn::Expm1(d, hn::Neg(tau)));
        const VF w = hn::IfThenElseZero(mask, hn::Mul(hn::Sub(one, A), alpha));
        hn::Store(hn::MulAdd(w, cr, hn::Load(d, t.acc[0] + o)), d, t.acc[0] + o);
        hn::Store(hn::MulAdd(w, cg, hn::Load(d, t.acc[1] + o)), d, t.acc[1] + o);
        hn::Store(hn::MulAdd(w, cb, hn::Load(d, t.acc[2] + o)), d, t.acc[2] + o);
        hn::Store(hn::Add(A, w), d, t.acc[3] + o);
      } else {
        const VF tm = hn::IfThenElseZero(mask, tau);
        hn::Store(hn::Add(hn::Load(d, t.sheet[0] + o), tm), d, t.sheet[0] + o);
        hn::Store(hn::MulAdd(tm, cr, hn::Load(d, t.sheet[1] + o)), d, t.sheet[1] + o);
        hn::Store(hn::MulAdd(tm, cg, hn::Load(d, t.sheet[2] + o)), d, t.sheet[2] + o);
        hn::Store(hn::MulAdd(tm, cb, hn::Load(d, t.sheet[3] + o)), d, t.sheet[3] + o);
      }
    }
    if constexpr (!kFused) {
      t.bx0 = std::min(t.bx0, lo), t.bx1 = std::max(t.bx1, hi);
      t.by0 = std::min(t.by0, y), t.by1 = std::max(t.by1, y);
    }
  }
}

// The gathered sheet under the tile's image (the reference's flush): per pixel
// with tau > 0, alpha = 1 - exp(-tau), the colour the sheet's extinction-weighted
// mean; then the sheet planes are cleared.
HWY_INLINE void Flush(Tile& t) {
  if (t.bx0 > t.bx1) return;
  const DF d;
  const size_t N = hn::Lanes(d);
  const VF one = hn::Set(d, 1.0f), zero = hn::Zero(d);
  const VF flo = hn::Set(d, float(t.bx0)), fhi = hn::Set(d, float(t.bx1));
  for (int y = t.by0; y <= t.by1; ++y) {
    const size_t row = size_t(y - t.y0) * t.stride;
    for (int x = t.x0 + (t.bx0 - t.x0) / int(N) * int(N); x <= t.bx1; x += int(N)) {
      const size_t o = row + size_t(x - t.x0);
      const VF tau = hn::Load(d, t.sheet[0] + o);
      const VF xs = hn::Iota(d, float(x));
      const auto mask = hn::And(hn::And(hn::Ge(xs, flo), hn::Le(xs, fhi)), hn::Gt(tau, zero));
      if (hn::AllFalse(d, mask)) continue;
      const VF A = hn::Load(d, t.acc[3] + o);
      const VF w = hn::Mul(hn::Sub(one, A), hn::Neg(hn::Expm1(d, hn::Neg(tau))));
      for (int ch = 0; ch < 3; ++ch) {
        const VF add = hn::IfThenElseZero(mask, hn::Mul(w, hn::Div(hn::Load(d, t.sheet[ch + 1] + o), tau)));
        hn::Store(hn::Add(hn::Load(d, t.acc[ch] + o), add), d, t.acc[ch] + o);
      }
      hn::Store(hn::Add(A, hn::IfThenElseZero(mask, w)), d, t.acc[3] + o);
      for (int ch = 0; ch < 4; ++ch) hn::Store(zero, d, t.sheet[ch] + o);
    }
  }
  t.bx0 = t.by0 = 1 << 30;
  t.bx1 = t.by1 = -1;
}

// One tile: its splats (positions in c.splats, in depth order), sheet by sheet.
void SplatTile(const Ctx& c, int x0, int y0, int x1, int y1, const uint32_t* list, size_t n, Image* image) {
  const DF d;
  const size_t N = hn::Lanes(d);
  const size_t tw = size_t(x1 - x0), th = size_t(y1 - y0);
  Tile t;
  t.x0 = x0, t.y0 = y0, t.x1 = x1, t.y1 = y1;
  t.stride = (tw + N - 1) / N * N + N;
  const size_t plane = t.stride * th;
  auto buf = hwy::AllocateAligned<float>(plane * 8);
  std::fill_n(buf.get(), plane * 8, 0.0f);
  for (int ch = 0; ch < 4; ++ch) {
    t.acc[ch] = buf.get() + size_t(ch) * plane;
    t.sheet[ch] = buf.get() + size_t(4 + ch) * plane;
  }
  t.bx0 = t.by0 = 1 << 30;
  t.bx1 = t.by1 = -1;
  for (size_t a = 0; a < n;) {
    const double sheet = c.order[list[a]].depth;
    size_t e = a + 1;
    while (e < n && c.order[list[e]].depth == sheet) ++e;
    if (e - a == 1) {
      Footprint<true>(c, list[a], t);
    } else {
      for (size_t q = a; q < e; ++q) Footprint<false>(c, list[q], t);
      Flush(t);
    }
    a = e;
  }
  for (size_t y = 0; y < th; ++y)
    for (size_t x = 0; x < tw; ++x) {
      float* px = image->pixel(x0 + int(x), y0 + int(y));
      for (int ch = 0; ch < 4; ++ch) px[ch] = t.acc[ch][y * t.stride + x];
    }
}

}  // namespace HWY_NAMESPACE
}  // namespace lockstep::opt::splat_kernels
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "optimized/tiling.h"
#include "optimized/volume_splat_simd.h"

namespace lockstep::opt::splat_kernels {
HWY_EXPORT(SplatTile);
}  // namespace lockstep::opt::splat_kernels

namespace lockstep::opt::simd {

namespace {

namespace sk = splat_kernels;

using sk::Key;

// The value ranges where the transfer function's alpha is exactly 0 by the
// reference's arithmetic (TransferFunction::eval): below the first point or
// above the last when that point's alpha is 0, and between two neighbouring
// points whose alphas are both 0 (a.a + t (b.a - a.a) = 0). Values in them
// need no evaluation; every other value is evaluated, as the reference does.
struct ClearRanges {
  std::vector<std::pair<double, double>> r;
  explicit ClearRanges(const TransferFunction& tf) {
    const auto& p = tf.points;
    const double inf = std::numeric_limits<double>::infinity();
    if (p.front().a == 0) r.push_back({-inf, p.front().value});
    for (size_t q = 0; q + 1 < p.size(); ++q)
      if (p[q].a == 0 && p[q + 1].a == 0) r.push_back({p[q].value, p[q + 1].value});
    if (p.back().a == 0) r.push_back({p.back().value, inf});
  }
  bool clear(double v) const {
    for (const auto& [lo, hi] : r)
      if (v >= lo && v <= hi) return true;
    return false;
  }
};

// Ranges [begin, end) of n items cut into parts pieces.
size_t cut(size_t n, int parts, int q) { return n * size_t(q) / size_t(parts); }

// The footprint every voxel shares: the reference's constants, by its
// expressions (reference/volume_splat.cpp).
struct Shape {
  double pixel;
  Vec3 right, up;
  double voxel_volume, norm;
  double ixx, iyy, ixy, det;
  int reach_x, reach_y;
};

Shape shape_of(const Volume& v, const vr::View& view) {
  Shape f;
  f.pixel = length(view.du);
  f.right = view.du / f.pixel;
  f.up = -view.dv / f.pixel;
  f.voxel_volume = v.spacing.x * v.spacing.y * v.spacing.z;
  const double kSigma = vr::kSplatSigma, kCutoff = vr::kSplatCutoff;
  const Vec3 var{std::pow(kSigma * v.spacing.x, 2), std::pow(kSigma * v.spacing.y, 2),
                 std::pow(kSigma * v.spacing.z, 2)};
  const double sxx = dot(mul(f.right, f.right), var), syy = dot(mul(f.up, f.up), var),
               sxy = dot(mul(f.right, f.up), var);
  f.det = sxx * syy - sxy * sxy;
  f.ixx = syy / f.det, f.iyy = sxx / f.det, f.ixy = -sxy / f.det;
  f.norm = 1.0 / (2 * std::numbers::pi * std::sqrt(f.det));
  f.reach_x = int(std::ceil(kCutoff * std::sqrt(sxx) / f.pixel));
  f.reach_y = int(std::ceil(kCutoff * std::sqrt(syy) / f.pixel));
  return f;
}

// Voxels are numbered in 32 bits; the tables need a proper covariance and a
// footprint narrower than 4096 pixels (a handful of voxels in a large frame
// is wider than the frame many times over).
bool drawable(const Volume& v, const Shape& f) {
  return !v.data.empty() && v.data.size() < size_t(std::numeric_limits<uint32_t>::max()) && f.det > 0 && f.ixx > 0 &&
         f.reach_x <= 4096 && f.reach_y <= 4096;
}

}  // namespace

bool volume_splat_handles(const Volume& v, const FrameOptions& options) {
  if (v.data.empty()) return false;
  const vr::Settings s = vr::settings(options.params, v.source, vr::Mode::kSplat);
  return drawable(v, shape_of(v, vr::make_view(v, s, options.width, options.height)));
}

Image volume_splat(const Volume& v, const FrameOptions& options, FrameStats* stats) {
  const vr::Settings s = vr::settings(options.params, v.source, vr::Mode::kSplat);
  if (v.data.empty()) throw std::invalid_argument("opt::simd::volume_splat: an empty volume (see volume_splat_handles)");
  const vr::View view = vr::make_view(v, s, options.width, options.height);
  const int threads = resolve_threads(options.threads);
  const Shape shape = shape_of(v, view);
  if (!drawable(v, shape))
    throw std::invalid_argument("opt::simd::volume_splat: a volume or footprint it does not draw (see volume_splat_handles)");
  const double pixel = shape.pixel, voxel_volume = shape.voxel_volume, norm = shape.norm;
  const Vec3 right = shape.right, up = shape.up;
  const double ixx = shape.ixx, iyy = shape.iyy, ixy = shape.ixy;
  const int reach_x = shape.reach_x, reach_y = shape.reach_y;
  const double dt0 = std::min({v.spacing.x, v.spacing.y, v.spacing.z});

  // 1. Classification, slabs of z slices in parallel: which voxels have
  // alpha > 0 (a byte each), counted per slab; then their keys in index order
  // (depth by the reference's expression), each slab at its offset.
  const int slabs = std::max(1, std::min(v.nz, threads * 8));
  auto slab_k = [&](int q) { return int(cut(size_t(v.nz), slabs, q)); };
  const size_t plane = size_t(v.nx) * size_t(v.ny);
  // The large scratch buffers on huge pages where the kernel allows (core/large_buffer.h).
  UninitVector<uint8_t> visible(v.data.size());
  std::vector<size_t> slab_at(size_t(slabs) + 1, 0);
  const ClearRanges clear(s.tf);
  parallel_tiles(1, slabs, 1, 1, threads, nullptr, [&](int, int c0, int, int c1) {
    for (int q = c0; q < c1; ++q) {
      size_t count = 0;
      for (size_t at = size_t(slab_k(q)) * plane; at < size_t(slab_k(q + 1)) * plane; ++at) {
        const float value = v.data[at];
        uint8_t on = 0;
        if (!clear.clear(value)) {
          double rgba[4];
          s.tf.eval(value, rgba);
          on = rgba[3] > 0;
        }
        visible[at] = on;
        count += on;
      }
      slab_at[size_t(q) + 1] = count;
    }
  });
  for (int q = 0; q < slabs; ++q) slab_at[size_t(q) + 1] += slab_at[size_t(q)];
  const size_t n = slab_at.back();
  UninitVector<sk::Slot> slots(n);
  parallel_tiles(1, slabs, 1, 1, threads, nullptr, [&](int, int c0, int, int c1) {
    for (int q = c0; q < c1; ++q) {
      size_t out = slab_at[size_t(q)];
      for (int k = slab_k(q); k < slab_k(q + 1); ++k)
        for (int j = 0; j < v.ny; ++j)
          for (int i = 0; i < v.nx; ++i) {
            const size_t at = v.index(i, j, k);
            if (visible[at]) slots[out++].key = {dot(v.position(i, j, k), view.dir), uint32_t(at), v.data[at]};
          }
    }
  });
  UninitVector<uint8_t>().swap(visible);  // freed: the keys below take its memory
  // Parts of the index order for the threads: whole slabs each.
  const int parts = std::min(threads, slabs);
  auto part_range = [&](int p) {
    return std::pair<size_t, size_t>(slab_at[cut(size_t(slabs), parts, p)], slab_at[cut(size_t(slabs), parts, p + 1)]);
  };

  // 2. Depth order: the reference's stable sort, as a bucket sort by depth
  // (the bucket is monotone in depth), each bucket filled in index order and
  // sorted by (depth, index).
  UninitVector<Key> order(n);
  if (n > 0) {
    double dmin = std::numeric_limits<double>::infinity(), dmax = -dmin;
    for (size_t q = 0; q < n; ++q) dmin = std::min(dmin, slots[q].key.depth), dmax = std::max(dmax, slots[q].key.depth);
    const size_t buckets = n / 8 + 1;
    const double scale = dmax > dmin ? double(buckets) / (dmax - dmin) : 0.0;
    auto bucket = [&](double depth) { return std::min(buckets - 1, size_t((depth - dmin) * scale)); };
    std::vector<std::vector<uint32_t>> count(static_cast<size_t>(parts));
    parallel_tiles(1, parts, 1, 1, threads, nullptr, [&](int, int p0, int, int p1) {
      for (int p = p0; p < p1; ++p) {
        auto& cnt = count[size_t(p)];
        cnt.assign(buckets, 0);
        const auto [a, b] = part_range(p);
        for (size_t q = a; q < b; ++q) ++cnt[bucket(slots[q].key.depth)];
      }
    });
    std::vector<uint32_t> start(buckets + 1);
    uint32_t at = 0;
    for (size_t b = 0; b < buckets; ++b) {
      start[b] = at;
      for (int p = 0; p < parts; ++p) {
        const uint32_t c = count[size_t(p)][b];
        count[size_t(p)][b] = at;
        at += c;
      }
    }
    start[buckets] = at;
    parallel_tiles(1, parts, 1, 1, threads, nullptr, [&](int, int p0, int, int p1) {
      for (int p = p0; p < p1; ++p) {
        auto& cnt = count[size_t(p)];
        const auto [a, b] = part_range(p);
        for (size_t q = a; q < b; ++q) order[cnt[bucket(slots[q].key.depth)]++] = slots[q].key;
      }
    });
    const int blocks = threads * 8;
    parallel_tiles(1, blocks, 1, 1, threads, nullptr, [&](int, int q0, int, int q1) {
      for (size_t b = cut(buckets, blocks, q0); b < cut(buckets, blocks, q1); ++b) {
        Key* first = order.data() + start[b];
        Key* last = order.data() + start[b + 1];
        // Insertion sort by (depth, index): a bucket holds a few voxels.
        for (Key* x = first + 1; x < last; ++x) {
          const Key k = *x;
          Key* y = x;
          for (; y > first && (k.depth < y[-1].depth || (k.depth == y[-1].depth && k.index < y[-1].index)); --y) *y = y[-1];
          *y = k;
        }
      }
    });
  }

  // 3. The splats' colours (into the slots the keys held), the tiles' lists
  // (each splat in every tile its pixel box overlaps, in depth order) and the
  // sheets: the reference's rule, a new sheet when the depth is past the
  // sheet's first by more than tie; each key's depth becomes its sheet's number.
  // Tiles of 64 x 32 from 256 x 128 pixels up, a quarter of the frame per side
  // below (so that small frames, the properties' 4 to 32 pixels, are cut into
  // tiles too and their borders are tested).
  const int tw = std::clamp(std::clamp((options.width / 4 + 7) / 8 * 8, 8, sk::kTileW), 1, std::max(1, options.width));
  const int th = std::clamp(std::clamp(options.height / 4, 4, sk::kTileH), 1, std::max(1, options.height));
  const int tiles_x = (options.width + tw - 1) / tw, tiles_y = (options.height + th - 1) / th;
  const size_t tiles = size_t(tiles_x) * size_t(tiles_y);
  const int chunks = std::max(1, threads * 4);
  sk::Ctx c;
  c.volume = &v;
  c.view = &view;
  c.width = view.width, c.height = view.height;
  c.pixel = pixel;
  c.right = right, c.up = up;
  c.nx = uint32_t(v.nx), c.ny = uint32_t(v.ny);
  c.inv_nx = 1.0 / v.nx, c.inv_ny = 1.0 / v.ny;
  // The tiles a splat's box overlaps (none when it is off the image).
  auto box = [&](uint32_t idx, int& tx0, int& ty0, int& tx1, int& ty1) {
    double cx, cy;
    sk::Centre(c, idx, cx, cy);
    const int x0 = std::max(0, int(std::floor(cx)) - reach_x);
    const int x1 = std::min(view.width - 1, int(std::ceil(cx)) + reach_x);
    const int y0 = std::max(0, int(std::floor(cy)) - reach_y);
    const int y1 = std::min(view.height - 1, int(std::ceil(cy)) + reach_y);
    if (x0 > x1 || y0 > y1) return false;
    tx0 = x0 / tw, tx1 = x1 / tw, ty0 = y0 / th, ty1 = y1 / th;
    return true;
  };
  std::vector<uint32_t> per(size_t(chunks) * tiles, 0);  // per chunk and tile: entries, then offsets
  parallel_tiles(1, chunks, 1, 1, threads, nullptr, [&](int, int c0, int, int c1) {
    for (int ch = c0; ch < c1; ++ch) {
      uint32_t* cnt = &per[size_t(ch) * tiles];
      for (size_t q = cut(n, chunks, ch); q < cut(n, chunks, ch + 1); ++q) {
        double rgba[4];
        s.tf.eval(order[q].value, rgba);
        const double sigma = -std::log1p(-std::min(rgba[3], 1 - 1e-12)) / dt0;
        slots[q].colour = {float(sigma * voxel_volume * norm), float(rgba[0]), float(rgba[1]), float(rgba[2])};
        int tx0, ty0, tx1, ty1;
        if (!box(order[q].index, tx0, ty0, tx1, ty1)) continue;
        for (int ty = ty0; ty <= ty1; ++ty)
          for (int tx = tx0; tx <= tx1; ++tx) ++cnt[size_t(ty) * size_t(tiles_x) + size_t(tx)];
      }
    }
  });
  // Tile-major, chunk by chunk within a tile: each tile's list in depth order.
  std::vector<size_t> tile_at(tiles + 1, 0);
  {
    size_t at = 0;
    for (size_t t = 0; t < tiles; ++t) {
      tile_at[t] = at;
      for (int ch = 0; ch < chunks; ++ch) {
        const uint32_t k = per[size_t(ch) * tiles + t];
        per[size_t(ch) * tiles + t] = uint32_t(at - tile_at[t]);
        at += k;
      }
    }
    tile_at[tiles] = at;
  }
  UninitVector<uint32_t> lists(tile_at[tiles] + 1);
  parallel_tiles(1, chunks, 1, 1, threads, nullptr, [&](int, int c0, int, int c1) {
    for (int ch = c0; ch < c1; ++ch) {
      uint32_t* off = &per[size_t(ch) * tiles];
      for (size_t q = cut(n, chunks, ch); q < cut(n, chunks, ch + 1); ++q) {
        int tx0, ty0, tx1, ty1;
        if (!box(order[q].index, tx0, ty0, tx1, ty1)) continue;
        for (int ty = ty0; ty <= ty1; ++ty)
          for (int tx = tx0; tx <= tx1; ++tx) {
            const size_t t = size_t(ty) * size_t(tiles_x) + size_t(tx);
            lists[tile_at[t] + off[t]++] = uint32_t(q);
          }
      }
    }
  });
  {
    const double tie = 1e-9 * length(view.hi - view.lo);
    double sheet_depth = 0, sheet = 0;
    for (size_t q = 0; q < n; ++q) {
      if (q == 0 || order[q].depth - sheet_depth > tie) {
        if (q > 0) sheet += 1;
        sheet_depth = order[q].depth;
      }
      order[q].depth = sheet;
    }
  }

  // 4. The footprint tables: S phases per pixel, linear interpolation within
  // 5e-6 of the peak (error <= curvature / (8 S^2)).
  c.ixx = ixx, c.iyy = iyy, c.ixy = ixy;
  c.reach_x = reach_x, c.reach_y = reach_y;
  c.shear = ixy / ixx;
  c.row_c = iyy - ixy * ixy / ixx;
  c.inv_ixx = 1 / ixx, c.inv_pixel = 1 / pixel;
  c.ax = ixx * pixel * pixel;
  const double ax = c.ax, ay = c.row_c * pixel * pixel;  // curvatures per pixel^2
  c.phases = std::clamp(int(std::ceil(std::sqrt(std::max(ax, ay) / (8 * 5e-6)))), 16, 4096);
  c.rt_x = reach_x + 2, c.rt_y = reach_y + 2;
  c.len_x = size_t(2 * c.rt_x + 2 + 2 * sk::kPad + sk::kLanes);
  c.len_y = size_t(2 * c.rt_y + 2);
  std::vector<float> table_x(size_t(c.phases + 1) * c.len_x), table_y(size_t(c.phases + 1) * c.len_y);
  for (int p = 0; p <= c.phases; ++p) {
    for (size_t j = 0; j < c.len_x; ++j) {
      const double t = double(int(j) - sk::kPad - c.rt_x) - double(p) / c.phases;
      table_x[size_t(p) * c.len_x + j] = float(std::exp(-0.5 * ax * t * t));
    }
    for (size_t j = 0; j < c.len_y; ++j) {
      const double t = double(int(j) - c.rt_y) - double(p) / c.phases;
      table_y[size_t(p) * c.len_y + j] = float(std::exp(-0.5 * ay * t * t));
    }
  }
  c.tx = table_x.data();
  c.ty = table_y.data();
  c.terminate = s.eps > 0;
  c.limit = float(1 - s.eps);
  c.order = order.data();
  c.colour = slots.data();

  // 5. The tiles, each compositing its splats in depth order.
  Image image = Image::uninitialized(options.width, options.height);
  parallel_tiles(options.width, options.height, tw, th, options.threads, options.progress,
                 [&](int x0, int y0, int x1, int y1) {
                   const size_t tile = size_t(y0 / th) * size_t(tiles_x) + size_t(x0 / tw);
                   HWY_DYNAMIC_DISPATCH(sk::SplatTile)(c, x0, y0, x1, y1, lists.data() + tile_at[tile],
                                                       tile_at[tile + 1] - tile_at[tile], &image);
                 });
  if (stats) stats->items = uint64_t(view.width) * uint64_t(view.height);
  return image;
}

}  // namespace lockstep::opt::simd
#endif  // HWY_ONCE
