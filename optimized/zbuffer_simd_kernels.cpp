// Z-buffer kernels, Highway SIMD: one tile at a time, 16 samples per vector
// (8 on AVX2), in the raster and in the shading.
//
// Rasterisation (raster_tile): Pineda's edge functions over the triangle's
// bounding box clipped to the tile, one sample plane (one sample offset) at a
// time, a row of N = 16 samples per vector (8 on AVX2; 4 or 8 in double). The contract
// (core/raster.h) wants the exact integer edge functions on the snapped
// vertices with the top-left rule, so that coverage is bit-identical to the
// reference's; |coordinates| < 2^25 puts the edge functions below 2^52, exact in
// int64 and in double but not in int32. The samples of one sample plane are a
// whole pixel (256 units) apart, so E - bias = e0 + 256 (ex i + ey j) over
// them, and e0 + 256 K >= 0 exactly when floor(e0 / 256) + K >= 0: the test
// runs on E' = floor(e0 / 256) + ex i + ey j, 256 times smaller. Per triangle,
// tile and sample plane, E' is evaluated exactly in int64 at the region's
// corners (scalar):
//   * an edge that is >= 0 over the whole region is dropped (trivially inside);
//   * an edge < 0 over the whole region rejects the triangle for the tile;
//   * if every remaining edge stays within +-2^30 over the region, the lanes run
//     in int32 (E' at a block's first lane from int64, plus lane offsets: every
//     value and partial sum is a value of E' inside the region, so nothing
//     overflows): every triangle whose edges span less than ~2^16 pixels;
//   * otherwise (guard-band giants) the lanes run in double, exact because
//     every value is an integer below 2^53.
// A sample is covered when E'0 | E'1 | E'2 >= 0 (one sign test).
//
// Depth: the reference takes depth from the plane of 1/z (whatever the
// interpolation of the attributes), and every stored depth is affine in 1/z
// (window depth d = (1/n - 1/z)/(1/n - 1/f), reversed n/z), so it is a plane in
// screen space: evaluated per block in double at the block's first lane and per
// lane in float (double for kDouble and kFixed24, whose 24-bit codes float
// cannot hold). kFixed24 rounds d to its integer code, as stored_depth. The
// depth test keeps the earlier triangle on ties (strict nearer()), as the
// reference does, since tiles see their triangles in mesh order.
// Forward flat shading (RasterParams::flat): a passing sample also gets its
// triangle's w = 1/z (a plane, as the depth) and flat colour, by masked stores.
#include "optimized/zbuffer_simd_kernels.h"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cmath>
#include <cstdlib>

#include "core/shading.h"

// foreach_target.h first: it re-includes this file once per target.
// clang-format off
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "optimized/zbuffer_simd_kernels.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/contrib/math/math-inl.h"
#include "hwy/highway.h"
// clang-format on

HWY_BEFORE_NAMESPACE();
namespace lockstep::opt::zsimd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// A mask of dfrom's lanes as a mask of dto's (same lane count, maybe another width).
template <class DTo, class DFrom>
HWY_INLINE hn::Mask<DTo> CastMask(DTo dto, DFrom dfrom, hn::Mask<DFrom> m) {
  if constexpr (sizeof(hn::TFromD<DTo>) == sizeof(hn::TFromD<DFrom>)) {
    return hn::RebindMask(dto, m);
  } else {
    uint8_t bits[8] = {};
    hn::StoreMaskBits(dfrom, m, bits);
    return hn::LoadMaskBits(dto, bits);
  }
}

// Two adjacent doubles a lane, from anywhere: first[l] = at(l)[0], second[l] =
// at(l)[1]. Sixteen-byte loads put together in registers (and deinterleaved),
// instead of two gathers: on this AMD guest 4.2 against 8.4 ns for 8 lanes
// (the gathers' elements are fetched one at a time anyway).
template <class DD, class At>
HWY_INLINE void LoadPairs(DD dd, const At& at, hn::Vec<DD>& first, hn::Vec<DD>& second) {
  constexpr size_t N = hn::MaxLanes(DD());
  if constexpr (N == 1) {
    first = hn::Set(dd, at(0)[0]), second = hn::Set(dd, at(0)[1]);
  } else {
    using D2 = hn::CappedTag<double, 2>;  // (a 16-byte block)
    const D2 d2;
    hn::Vec<DD> lo, hi;
    if constexpr (N == 2) {
      lo = hn::LoadU(d2, at(0)), hi = hn::LoadU(d2, at(1));
    } else if constexpr (N == 4) {
      lo = hn::Combine(dd, hn::LoadU(d2, at(1)), hn::LoadU(d2, at(0)));
      hi = hn::Combine(dd, hn::LoadU(d2, at(3)), hn::LoadU(d2, at(2)));
    } else {
      static_assert(N == 8);
      const hn::Half<DD> d4;
      auto four = [&](int l) {
        return hn::Combine(d4, hn::LoadU(d2, at(l + 1)), hn::LoadU(d2, at(l)));
      };
      lo = hn::Combine(dd, four(2), four(0));
      hi = hn::Combine(dd, four(6), four(4));
    }
    first = hn::ConcatEven(dd, hi, lo), second = hn::ConcatOdd(dd, hi, lo);
  }
}

// Inside-mask of one block in double (long edges): E at the block's first lane
// is e[k] (int64, exact), lane l adds l * sx[k].
template <class DI>
HWY_INLINE hn::Mask<DI> CoverDouble(DI di, const int64_t e[3], const int64_t sx[3]) {
  const hn::CappedTag<double, 8> dd;  // at most as many lanes as di
  const size_t n = hn::Lanes(di), m = hn::Lanes(dd);
  uint8_t bits[8] = {};
  const auto lane = hn::Iota(dd, 0.0);
  for (size_t sub = 0; sub < n; sub += m) {  // m <= 8 lanes a step
    auto all = hn::Set(dd, 0.0);
    auto in = hn::Eq(all, all);
    for (int k = 0; k < 3; ++k) {
      const auto v = hn::MulAdd(lane, hn::Set(dd, double(sx[k])),
                                hn::Set(dd, double(e[k] + int64_t(sub) * sx[k])));
      in = hn::And(in, hn::Ge(v, all));
    }
    uint8_t b[8] = {};
    hn::StoreMaskBits(dd, in, b);
    bits[sub / 8] |= uint8_t(b[0] << (sub % 8));
  }
  return hn::LoadMaskBits(di, bits);
}

// floor(x / 256) for any int64 (an arithmetic shift).
HWY_INLINE int64_t FloorDiv256(int64_t x) { return x >> 8; }

// max - min of three coordinates.
HWY_INLINE int32_t Extent(const int32_t v[3]) {
  return std::max({v[0], v[1], v[2]}) - std::min({v[0], v[1], v[2]});
}

// The stored value from the plane value q (kFixed24: its integer code, as stored_depth).
template <bool kFixed24, class DT, class VT = hn::Vec<DT>>
HWY_INLINE VT Stored(DT dt, VT q) {
  using T = hn::TFromD<DT>;
  if constexpr (kFixed24) {
    q = hn::Min(hn::Max(q, hn::Zero(dt)), hn::Set(dt, T(1)));
    q = hn::Round(hn::Mul(q, hn::Set(dt, T(double((1 << 24) - 1)))));
  }
  return q;
}

// The depth test: q nearer than the stored old (kReversed: larger). ties: a
// tie wins too -- the triangles come in reverse mesh order (TileJob::reverse),
// so that the earliest of equal depths still ends up on top.
template <bool kReversed, class V>
HWY_INLINE auto Closer(V q, V old, bool ties) {
  if constexpr (kReversed) {
    return ties ? hn::Ge(q, old) : hn::Gt(q, old);
  } else {
    return ties ? hn::Le(q, old) : hn::Lt(q, old);
  }
}

// A mask of 16 lanes as its two halves.
template <class D, class DH>
HWY_INLINE void MaskHalves(D d, DH dh, hn::Mask<D> m, hn::Mask<DH>& lo, hn::Mask<DH>& hi) {
#if HWY_TARGET <= HWY_AVX3
  // AVX-512: the mask register's low and high 8 bits (no trip through memory).
  if constexpr (hn::MaxLanes(D()) == 16 && sizeof(hn::TFromD<D>) == 4) {
    const uint32_t raw = uint32_t(m.raw);
    lo = hn::Mask<DH>::FromBits(raw & 0xFFu);
    hi = hn::Mask<DH>::FromBits(raw >> 8);
    return;
  }
#endif
  uint8_t bits[8] = {};
  hn::StoreMaskBits(d, m, bits);
  lo = hn::LoadMaskBits(dh, bits);
  hi = hn::LoadMaskBits(dh, bits + 1);
}

// RasterTileT's two rows a vector, for a region of cols <= 8 columns and rows
// rows: lanes 0-7 are columns 0-7 of row r, lanes 8-15 those of row r + 1;
// at0: the tile buffers' offset of the region's first sample; e, sx, sy: the
// edges there (int32-safe over the region and one row more), q and w likewise.
// Depth is read 8 lanes at a time from both rows (the buffers have a row of
// slack at their end); everything is written through masks.
template <bool kReversed, bool kFixed24, bool kForward, class DT>
HWY_INLINE void PairRows(DT dt, const RasterParams& p, const int64_t e[3], const int64_t sx[3],
                         const int64_t sy[3], double q_first, double qsx, double qsy,
                         double w_first, double wsx, double wsy, const hn::Vec<DT> flat[3],
                         int cols, int rows, size_t at0, int W,
                         hn::Vec<hn::Rebind<int32_t, DT>> tri_id, bool ties,
                         const ForwardFlat& fl, bool skip_empty, hn::TFromD<DT>* depth,
                         int32_t* tri) {
  using T = hn::TFromD<DT>;
  const hn::Rebind<int32_t, DT> di;
  const hn::Half<DT> dh;
  const hn::Half<decltype(di)> dhi;
  using VI = hn::Vec<decltype(di)>;
  using VT = hn::Vec<DT>;
  const VI iota = hn::Iota(di, 0);
  const VI col = hn::And(iota, hn::Set(di, 7)), row = hn::ShiftRight<3>(iota);
  VI lane_off[3];
  for (int k = 0; k < 3; ++k)
    lane_off[k] = hn::Add(hn::Mul(col, hn::Set(di, int32_t(sx[k]))),
                          hn::Mul(row, hn::Set(di, int32_t(sy[k]))));
  const VT colf = hn::ConvertTo(dt, col), rowf = hn::ConvertTo(dt, row);
  const VT q_lane = hn::Add(hn::Mul(colf, hn::Set(dt, T(qsx))), hn::Mul(rowf, hn::Set(dt, T(qsy))));
  const VT w_lane = hn::Add(hn::Mul(colf, hn::Set(dt, T(wsx))), hn::Mul(rowf, hn::Set(dt, T(wsy))));
  const auto in_cols = hn::Lt(col, hn::Set(di, cols));
  const auto first_row = hn::Lt(iota, hn::Set(di, 8));
  const VI minus1 = hn::Set(di, -1);
  for (int r = 0; r < rows; r += 2) {
    VI v[3];
    for (int k = 0; k < 3; ++k) v[k] = hn::Add(hn::Set(di, int32_t(e[k] + sy[k] * r)), lane_off[k]);
    auto cover = hn::And(hn::Gt(hn::Or(hn::Or(v[0], v[1]), v[2]), minus1), in_cols);
    if (r + 1 >= rows) cover = hn::And(cover, first_row);
    if (skip_empty && hn::AllFalse(di, cover)) continue;
    const size_t a0 = at0 + size_t(r) * size_t(W), a1 = a0 + size_t(W);
    const VT q = Stored<kFixed24>(dt, hn::Add(hn::Set(dt, T(q_first + qsy * r)), q_lane));
    const VT old = hn::Combine(dt, hn::LoadU(dh, depth + a1), hn::LoadU(dh, depth + a0));
    const auto closer = Closer<kReversed>(q, old, ties);
    const auto pass = hn::And(hn::RebindMask(dt, cover), closer);
    hn::Mask<decltype(dh)> m0, m1;
    MaskHalves(dt, dh, pass, m0, m1);
    hn::Mask<decltype(dhi)> i0, i1;
    MaskHalves(di, dhi, hn::RebindMask(di, pass), i0, i1);
    // Depth blended and stored whole (the next triangle's load of these bytes
    // is then forwarded from the store, not held up behind a masked one).
    const VT nd = hn::IfThenElse(pass, q, old);
    hn::StoreU(hn::LowerHalf(dh, nd), dh, depth + a0);
    hn::StoreU(hn::UpperHalf(dh, nd), dh, depth + a1);
    if constexpr (!kForward) {  // (drawn forward, shading needs no triangle ids)
      hn::BlendedStore(hn::LowerHalf(dhi, tri_id), i0, dhi, tri + a0);
      hn::BlendedStore(hn::UpperHalf(dhi, tri_id), i1, dhi, tri + a1);
    } else {
      const VT w = hn::Add(hn::Set(dt, T(w_first + wsy * r)), w_lane);
      hn::BlendedStore(hn::LowerHalf(dh, w), m0, dh, fl.w + a0);
      hn::BlendedStore(hn::UpperHalf(dh, w), m1, dh, fl.w + a1);
      for (int c = 0; c < 3; ++c) {
        hn::BlendedStore(hn::LowerHalf(dh, flat[c]), m0, dh, fl.rgb[c] + a0);
        hn::BlendedStore(hn::UpperHalf(dh, flat[c]), m1, dh, fl.rgb[c] + a1);
      }
    }
  }
}

// kReversed, kFixed24: the depth format, fixed at compile time (the inner loop
// has no branch on it).
template <bool kReversed, bool kFixed24, bool kForward, class DT>
HWY_INLINE void RasterTileT(DT dt, const RasterParams& p, const TileJob& t, hn::TFromD<DT>* depth,
                            int32_t* tri, int32_t* count) {
  // Two rows a vector (PairRows) where 16 float lanes fit.
  constexpr bool kPairs = sizeof(hn::TFromD<DT>) == 4 && hn::MaxLanes(DT()) == 16;
  using T = hn::TFromD<DT>;
  const hn::Rebind<int32_t, DT> di;
  using VI = hn::Vec<decltype(di)>;
  using VT = hn::Vec<DT>;
  const int N = int(hn::Lanes(dt));
  const int W = p.buf_w, H = p.buf_h;
  HWY_DASSERT(W % N == 0);  // (tile_size: a power of two, at least 16)
  const VI iota_i = hn::Iota(di, 0);
  const VT iota_t = hn::Iota(dt, 0);
  const VI minus1 = hn::Set(di, -1);
  constexpr int64_t kLimit = int64_t(1) << 30;
  // The forward planes' pointers, copied: held in registers, not reloaded
  // through p after every store (which the compiler cannot prove leaves p alone).
  ForwardFlat fl;
  if constexpr (kForward) fl = *p.flat;

  for (int ll = 0; ll < t.nlists; ++ll) {
    const int l = t.reverse ? t.nlists - 1 - ll : ll;
    const std::vector<uint32_t>& list = *t.lists[l].ids;
    const TriSetup* const tris = t.lists[l].tris;
    const int32_t first = t.lists[l].first;
    const size_t n = list.size();
    for (size_t k = 0; k < n; ++k) {
      const size_t li = t.reverse ? n - 1 - k : k;
      const uint32_t id = list[li];
      // The triangle four ahead (its set-up's cache lines): the lists read the
      // set-up arrays out of order, and far beyond the caches on big meshes.
      if (k + 4 < n) {
        const char* ahead = reinterpret_cast<const char*>(&tris[list[t.reverse ? li - 4 : li + 4]]);
        for (size_t b = 0; b < sizeof(TriSetup); b += 64) __builtin_prefetch(ahead + b);
      }
      const TriSetup& s = tris[id];
      const int ri0 = std::max(int(s.i0), t.x0), ri1 = std::min(int(s.i1), t.x1 - 1);
      const int rj0 = std::max(int(s.j0), t.y0), rj1 = std::min(int(s.j1), t.y1 - 1);
      if (ri0 > ri1 || rj0 > rj1) continue;
      const int r0 = rj0 - t.y0, rows = rj1 - rj0 + 1;
      const VI tri_id = hn::Set(di, first + int32_t(id));
      // Two rows a vector (lanes 0-7 row r, 8-15 row r + 1, from the region's
      // own first column) for a region at most 8 pixels wide, with 16 lanes,
      // when coverage is not counted: a small triangle takes half the blocks.
      bool pairs = kPairs && N == 16 && count == nullptr && ri1 - ri0 < 8;
      // A small triangle (its vertices within 16 px of each other both ways):
      // its edge values over any such region are below 2^19 in magnitude, so
      // the pairs need no range tests (and take no branches on them).
      const bool small = pairs && Extent(s.ax) < 16 * kSubpixel && Extent(s.ay) < 16 * kSubpixel;
      for (int smp = 0; smp < p.spp; ++smp) {
      retry:
        // tile-local first column (pairs: a multiple of 8 when the region fits in
        // that group of 8: neighbours then read and write the same 32 bytes)
        const int a8 = ((ri0 - t.x0) & ~7);
        int c0 = pairs ? (ri1 - t.x0 - a8 < 8 ? a8 : ri0 - t.x0) : ((ri0 - t.x0) / N) * N;
        int nb = pairs ? 1 : (ri1 - t.x0 - c0) / N + 1;
        // Blocks from the region's own first column where that takes fewer
        // (a region 9 to 16 wide: one block a row, not two). They end within
        // the row: they end before the aligned ones' last block does (one more
        // block, from at most N - 1 columns further left), which ends at most
        // at the row's end (W is a multiple of N).
        if (!pairs) {
          const int nb_own = (ri1 - ri0) / N + 1;
          if (nb_own < nb) nb = nb_own, c0 = ri0 - t.x0;
        }
        // The region's extent in pixels (pairs: 8 columns, and a row past the last).
        const int64_t wspan = pairs ? 7 : int64_t(nb * N - 1), hspan = pairs ? rows : rows - 1;
        const int64_t px = int64_t(t.x0 + c0) * kSubpixel + p.offsets[smp][0];
        const int64_t py = int64_t(rj0) * kSubpixel + p.offsets[smp][1];
        // The three edges at the region's first sample, and their steps per pixel.
        int64_t e[3], sx[3], sy[3];
        bool reject = false, narrow = true;
        for (int k = 0; k < 3; ++k) {
          // Samples of one plane are 256 units apart: E - bias = e0 + 256 K with
          // K = ex i + ey j (i, j pixels from the first sample), and
          // e0 + 256 K >= 0  <=>  K >= ceil(-e0 / 256)  <=>  floor(e0 / 256) + K >= 0,
          // exactly: the same test on numbers 256 times smaller.
          e[k] = FloorDiv256(int64_t(s.ex[k]) * (px - s.ax[k]) + int64_t(s.ey[k]) * (py - s.ay[k]) -
                             s.bias[k]);
          sx[k] = s.ex[k];
          sy[k] = s.ey[k];
          if (small) continue;
          const int64_t dx = sx[k] * wspan, dy = sy[k] * hspan;
          const int64_t lo = e[k] + std::min<int64_t>(0, dx) + std::min<int64_t>(0, dy);
          const int64_t hi = e[k] + std::max<int64_t>(0, dx) + std::max<int64_t>(0, dy);
          if (hi < 0) reject = true;
          if (lo >= 0) {
            e[k] = sx[k] = sy[k] = 0;  // inside over the whole region
          } else if (lo <= -kLimit || hi >= kLimit) {
            narrow = false;
          }
        }
        if (pairs && !narrow) {  // (pairs run in int32 only)
          pairs = false;
          goto retry;
        }
        if (reject) continue;
        // Depth plane at the region's first sample, per pixel along x and y.
        const double q_first = s.q0 + s.qx * double(px - s.x0()) + s.qy * double(py - s.y0());
        const double qsx = s.qx * kSubpixel, qsy = s.qy * kSubpixel;
        // Forward flat shading: w = 1/z the same way, and the colour.
        double w_first = 0, wsx = 0, wsy = 0;
        VT flat[3] = {hn::Zero(dt), hn::Zero(dt), hn::Zero(dt)};
        if constexpr (kForward) {
          const TriSetup::Forward& f = s.fwd;
          w_first = f.w0 + f.wx * double(px - s.x0()) + f.wy * double(py - s.y0());
          wsx = f.wx * kSubpixel, wsy = f.wy * kSubpixel;
          for (int c = 0; c < 3; ++c) flat[c] = hn::Set(dt, T(f.flat[c]));
        }
        const size_t plane = size_t(smp) * size_t(H);
        if constexpr (kPairs) {
          if (pairs) {
            PairRows<kReversed, kFixed24, kForward>(
                dt, p, e, sx, sy, q_first, qsx, qsy, w_first, wsx, wsy, flat, ri1 - t.x0 - c0 + 1, rows,
                (plane + size_t(r0)) * size_t(W) + size_t(c0), W, tri_id, t.reverse, fl, !small, depth, tri);
            continue;
          }
        }
        VI lane_off[3];
        for (int k = 0; k < 3; ++k)
          lane_off[k] = hn::Mul(iota_i, hn::Set(di, int32_t(narrow ? sx[k] : 0)));
        const VT q_lane = hn::Mul(iota_t, hn::Set(dt, T(qsx)));
        const VT w_lane = hn::Mul(iota_t, hn::Set(dt, T(wsx)));
        // int32 lanes (narrow): the edges at the row's first block, stepped by
        // sy a row and by N sx a block (each sum used is E' at a sample of the
        // region; the step past the last row or block, unused, may wrap).
        VI row_v[3], step_y[3], step_b[3];
        for (int k = 0; k < 3; ++k) {
          row_v[k] = hn::Add(hn::Set(di, int32_t(narrow ? e[k] : 0)), lane_off[k]);
          step_y[k] = hn::Set(di, int32_t(narrow ? sy[k] : 0));
          step_b[k] = hn::Set(di, int32_t(narrow ? sx[k] * N : 0));
        }
        for (int r = 0; r < rows; ++r) {
          const double q_row = q_first + qsy * r, w_row = w_first + wsy * r;
          const size_t row = (plane + size_t(r0 + r)) * size_t(W);
          VI v[3] = {row_v[0], row_v[1], row_v[2]};
          for (int k = 0; k < 3; ++k) row_v[k] = hn::Add(row_v[k], step_y[k]);
          for (int b = 0; b < nb; ++b) {
            hn::Mask<decltype(di)> cover;
            if (narrow) {
              cover = hn::Gt(hn::Or(hn::Or(v[0], v[1]), v[2]), minus1);
              for (int k = 0; k < 3; ++k) v[k] = hn::Add(v[k], step_b[k]);
            } else {
              int64_t eb[3];
              for (int k = 0; k < 3; ++k) eb[k] = e[k] + sy[k] * r + sx[k] * (int64_t(b) * N);
              cover = CoverDouble(di, eb, sx);
            }
            if (hn::AllFalse(di, cover)) continue;
            const size_t at = row + size_t(c0 + b * N);
            if (count)
              hn::StoreU(hn::Sub(hn::LoadU(di, count + at), hn::VecFromMask(di, cover)), di,
                         count + at);
            VT q;
            if constexpr (sizeof(T) == 8) {
              // Barycentrics: the exact edge functions (below 2^53) at the lanes.
              VT acc = hn::Zero(dt);
              for (int k = 2; k >= 0; --k) {
                // (s's edges: sx and sy are 0 for an edge dropped above.)
                const int64_t ex = s.ex[k], ey = s.ey[k];
                const int64_t E = ex * (px + int64_t(b * N) * kSubpixel - s.ax[k]) +
                                  ey * (py + int64_t(r) * kSubpixel - s.ay[k]);
                const VT Ek = hn::MulAdd(iota_t, hn::Set(dt, T(double(ex * kSubpixel))),
                                         hn::Set(dt, T(double(E))));
                acc = hn::MulAdd(Ek, hn::Set(dt, T(s.dbl.qv[k])), acc);
              }
              q = Stored<kFixed24>(dt, hn::Div(acc, hn::Set(dt, T(s.dbl.area))));
            } else {
              q = Stored<kFixed24>(dt,
                                   hn::Add(hn::Set(dt, T(q_row + qsx * double(b * N))), q_lane));
            }
            const VT old = hn::LoadU(dt, depth + at);
            const auto closer = Closer<kReversed>(q, old, t.reverse);
            const auto pass = hn::And(CastMask(dt, di, cover), closer);
            // Masked stores (one instruction each on AVX-512; a blend elsewhere).
            hn::BlendedStore(q, pass, dt, depth + at);
            if constexpr (!kForward) {
              hn::BlendedStore(tri_id, CastMask(di, dt, pass), di, tri + at);
            } else {
              const VT w = hn::Add(hn::Set(dt, T(w_row + wsx * double(b * N))), w_lane);
              hn::BlendedStore(w, pass, dt, fl.w + at);
              for (int c = 0; c < 3; ++c) hn::BlendedStore(flat[c], pass, dt, fl.rgb[c] + at);
            }
          }
        }
      }
    }
  }
}

// ---------------------------------------------------------------- shading
//
// A block of N samples holds few distinct triangles (usually one). For each
// distinct triangle the block's lanes get its attribute planes (broadcast, no
// gathers); lighting then runs once over the block. The lighting is
// core/shading.h's, in float (pow as exp(shine log x), as shade_simd.cpp).
// Writes n pixels (alpha 1) of an RGBA image row from three colour vectors;
// 8 at a time with a 4 x 8 transpose in registers (AVX2 and up; 16 as two 8s), streamed past
// the cache when the row is aligned: the frame is written once and not read back.
template <class DF, class VF = hn::Vec<DF>>
HWY_INLINE void WritePixels(DF df, VF r, VF g, VF b, float* dst, int n) {
#if HWY_TARGET <= HWY_AVX3
  if constexpr (hn::MaxLanes(df) == 16) {  // two halves of 8
    const hn::Half<DF> dh;
    if (n > 0)
      WritePixels(dh, hn::LowerHalf(dh, r), hn::LowerHalf(dh, g), hn::LowerHalf(dh, b), dst,
                  std::min(n, 8));
    if (n > 8)
      WritePixels(dh, hn::UpperHalf(dh, r), hn::UpperHalf(dh, g), hn::UpperHalf(dh, b), dst + 32,
                  n - 8);
    return;
  }
#endif
#if HWY_TARGET <= HWY_AVX2
  if (hn::Lanes(df) == 8 && n == 8) {
    const hn::Repartition<double, DF> d64;
    const VF a = hn::Set(df, 1.0f);
    const VF rg_lo = hn::InterleaveLower(df, r, g), rg_hi = hn::InterleaveUpper(df, r, g);
    const VF ba_lo = hn::InterleaveLower(df, b, a), ba_hi = hn::InterleaveUpper(df, b, a);
    auto lo64 = [&](VF x, VF y) {
      return hn::BitCast(df, hn::InterleaveLower(d64, hn::BitCast(d64, x), hn::BitCast(d64, y)));
    };
    auto hi64 = [&](VF x, VF y) {
      return hn::BitCast(df, hn::InterleaveUpper(d64, hn::BitCast(d64, x), hn::BitCast(d64, y)));
    };
    const VF p0 = lo64(rg_lo, ba_lo), p1 = hi64(rg_lo, ba_lo);  // pixels 0 | 4, 1 | 5
    const VF p2 = lo64(rg_hi, ba_hi), p3 = hi64(rg_hi, ba_hi);  // pixels 2 | 6, 3 | 7
    const VF q[4] = {hn::ConcatLowerLower(df, p1, p0), hn::ConcatLowerLower(df, p3, p2),
                     hn::ConcatUpperUpper(df, p1, p0), hn::ConcatUpperUpper(df, p3, p2)};
    if ((reinterpret_cast<uintptr_t>(dst) & 31) == 0) {
      for (int k = 0; k < 4; ++k) hn::Stream(q[k], df, dst + 8 * k);
    } else {
      for (int k = 0; k < 4; ++k) hn::StoreU(q[k], df, dst + 8 * k);
    }
    return;
  }
#endif
  HWY_ALIGN float cr[8], cg[8], cb[8];
  hn::Store(r, df, cr), hn::Store(g, df, cg), hn::Store(b, df, cb);
  for (int k = 0; k < n; ++k) {
    dst[4 * k] = cr[k], dst[4 * k + 1] = cg[k], dst[4 * k + 2] = cb[k], dst[4 * k + 3] = 1.0f;
  }
}

// core/shading.h's lighting in float, per lane: phong (Phong or Blinn-Phong
// specular, pow as exp(shine log x)) or toon, at points pos with unit normals
// nrm (turned towards the viewer) and unit directions to the viewer view;
// material kd (kd * colour), ks, shine per lane. Lanes outside valid get the
// ambient term only. col: the colour.
template <class DF, class VF, class M>
HWY_INLINE void Lighting(DF df, const float* light, int nlights, Shading shading, float bands,
                         float band_div, const VF pos[3], const VF nrm[3], const VF view[3],
                         const VF kd[3], VF ks, VF shine, M valid, VF col[3]) {
  const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f), two = hn::Set(df, 2.0f);
  const VF amb = hn::Set(df, hn::TFromD<DF>(kAmbient));
  auto dot3 = [](const VF a[3], const VF b[3]) {
    return hn::MulAdd(a[0], b[0], hn::MulAdd(a[1], b[1], hn::Mul(a[2], b[2])));
  };
  auto normalize3 = [&](VF a[3]) {
    const VF inv = hn::Div(one, hn::Sqrt(dot3(a, a)));
    for (int c = 0; c < 3; ++c) a[c] = hn::Mul(a[c], inv);
  };
  for (int c = 0; c < 3; ++c) col[c] = hn::Mul(amb, kd[c]);
  for (int l = 0; l < nlights; ++l) {
    const float* li = light + ShadeParams::kLightFloats * l;
    VF L[3] = {hn::Sub(hn::Set(df, li[0]), pos[0]), hn::Sub(hn::Set(df, li[1]), pos[1]),
               hn::Sub(hn::Set(df, li[2]), pos[2])};
    const VF dist = hn::Sqrt(dot3(L, L));
    const VF inv_d = hn::Div(one, dist);
    for (int c = 0; c < 3; ++c) L[c] = hn::Mul(L[c], inv_d);
    const VF ndl = dot3(nrm, L);
    const auto lit = hn::And(hn::Gt(ndl, zero), valid);
    if (hn::AllFalse(df, lit)) continue;
    // core/shading.cpp's light_at: attenuation min(1, 1/(c1 + c2 d + c3 d^2)),
    // then the spot's cone and falloff (Warn): 0 outside, cos^exponent inside.
    // Without c2, c3 and a spot (NFF's lights) it is the same for every lane:
    // its product with the light's colour once, in scalar (the same bits).
    using T = hn::TFromD<DF>;
    const bool uniform = li[7] == 0.0f && li[8] == 0.0f && li[9] == 0.0f;
    VF ip = one;
    if (!uniform)
      ip = hn::Min(one, hn::Div(one, hn::MulAdd(hn::Mul(hn::Set(df, li[8]), dist), dist,
                                                hn::MulAdd(hn::Set(df, li[7]), dist,
                                                           hn::Set(df, li[6])))));
    if (li[9] != 0.0f) {
      const VF dir[3] = {hn::Set(df, li[10]), hn::Set(df, li[11]), hn::Set(df, li[12])};
      const VF cos_angle = hn::Neg(dot3(L, dir));
      const auto inside = hn::Ge(cos_angle, hn::Set(df, li[13]));
      const VF exponent = hn::Set(df, li[14]);
      const auto positive = hn::Gt(cos_angle, zero);
      VF fall = hn::CallExp(
          df, hn::Mul(exponent, hn::CallLog(df, hn::IfThenElse(positive, cos_angle, one))));
      fall = hn::IfThenElse(positive, fall, hn::IfThenElseZero(hn::Eq(exponent, zero), one));
      ip = hn::Mul(ip, hn::IfThenElseZero(inside, fall));
    }
    VF term[3];
    if (shading == Shading::kToon) {
      const VF q =
          hn::Min(one, hn::Div(hn::Floor(hn::Mul(ndl, hn::Set(df, bands))), hn::Set(df, band_div)));
      for (int c = 0; c < 3; ++c) term[c] = hn::Mul(q, kd[c]);
    } else {
      // The specular term only where a lit lane has ks > 0 (elsewhere it is
      // 0 whatever the power: a material without highlights pays nothing).
      const auto shiny = hn::Gt(ks, zero);
      VF spec = zero;
      if (!hn::AllFalse(df, hn::And(shiny, lit))) {
        VF cosine;
        if (shading == Shading::kPhong) {
          VF R[3];  // L mirrored about N
          for (int c = 0; c < 3; ++c) R[c] = hn::MulSub(hn::Mul(two, ndl), nrm[c], L[c]);
          cosine = dot3(R, view);
        } else {
          VF Hv[3] = {hn::Add(L[0], view[0]), hn::Add(L[1], view[1]), hn::Add(L[2], view[2])};
          normalize3(Hv);  // halfway vector (Blinn)
          cosine = dot3(nrm, Hv);
        }
        // ks max(0, cosine)^shine, as std::pow: 0^shine = 0 for shine > 0, x^0 = 1.
        // (exp and log only where a lane has a highlight: lanes are neighbours,
        // often all facing away together.)
        const auto pos_c = hn::Gt(cosine, zero);
        VF pw = hn::IfThenElseZero(hn::Eq(shine, zero), one);
        if (!hn::AllFalse(df, hn::And(hn::And(pos_c, lit), shiny))) {
          const VF safe = hn::IfThenElse(pos_c, cosine, one);
          pw = hn::IfThenElse(pos_c, hn::CallExp(df, hn::Mul(shine, hn::CallLog(df, safe))), pw);
        }
        spec = hn::IfThenElseZero(shiny, hn::Mul(ks, pw));
      }
      for (int c = 0; c < 3; ++c) term[c] = hn::MulAdd(ndl, kd[c], spec);
    }
    const T ip_uniform = std::min(T(1), T(1) / T(li[6]));
    for (int c = 0; c < 3; ++c) {
      const VF scale = uniform ? hn::Set(df, ip_uniform * T(li[3 + c]))
                               : hn::Mul(ip, hn::Set(df, li[3 + c]));
      col[c] = hn::IfThenElse(lit, hn::MulAdd(scale, term[c], col[c]), col[c]);
    }
  }
}

// Flat colours, in float lanes as shade_tile lights a pixel (16 a vector on
// AVX-512): within 1e-5 or so of view_scene's double colour (3.6e-7 on balls-3
// at shine 3.08, 1.1e-5 on balls-2 at shine 250, 1024^2 and 512^2). Where a triangle
// of the vector has a high shine (above kFloatShine, with ks > 0) the vector is lit in
// double lanes instead (each half; the lights are given in float, so within
// about 1e-7): the specular term's slope there, shine x^(shine - 1), turns
// float's 1e-7 in the cosine into up to shine 1e-7 in the colour (1e-2 at
// shine 1e5: 5.6e-3 on corpus/scenes/shiny.nff), while up to kFloatShine it
// stays far below the 1/255 the family allows.
constexpr double kFloatShine = 256;

template <class D, class V = hn::Vec<D>>
HWY_INLINE void FlatLit(D d, const ShadeParams& p, const V pos_in[3], const V nrm_in[3],
                        const V kd[3], V ks, V shine, V col[3]) {
  const V zero = hn::Zero(d), one = hn::Set(d, hn::TFromD<D>(1));
  auto dot3 = [](const V a[3], const V b[3]) {
    return hn::MulAdd(a[0], b[0], hn::MulAdd(a[1], b[1], hn::Mul(a[2], b[2])));
  };
  V view[3], nrm[3];
  for (int c = 0; c < 3; ++c) view[c] = hn::Sub(hn::Set(d, hn::TFromD<D>(p.eye[c])), pos_in[c]);
  const V inv = hn::Div(one, hn::Sqrt(dot3(view, view)));
  for (int c = 0; c < 3; ++c) view[c] = hn::Mul(view[c], inv);
  // view_scene's lit(): the face turned towards the eye.
  const auto away = hn::Lt(dot3(nrm_in, view), zero);
  for (int c = 0; c < 3; ++c) nrm[c] = hn::IfThenElse(away, hn::Neg(nrm_in[c]), nrm_in[c]);
  Lighting(d, p.light, p.nlights, Shading::kPhong, 1.0f, 1.0f, pos_in, nrm, view, kd, ks, shine,
           hn::Eq(zero, zero), col);
}

void FlatColors(const ShadeParams& p, size_t n, const double* const* in, const uint32_t* id,
                const FlatSurface* surface, float* const* out) {
  const hn::ScalableTag<float> df;
  const hn::Repartition<double, decltype(df)> dd;  // half as many lanes
  const hn::Rebind<float, decltype(dd)> dh;         // a half of df
  using VD = hn::Vec<decltype(dd)>;
  using VF = hn::Vec<decltype(df)>;
  const size_t N = hn::Lanes(df), H = hn::Lanes(dd);
  const VD high = hn::Set(dd, kFloatShine);
  constexpr int kAll = kFlatInputs + 5;  // the planes, then the surface's five
  HWY_ALIGN double lanes[5][hn::MaxLanes(df)];
  for (size_t i = 0; i < n; i += N) {
    // (The arrays hold n rounded up to 16: whole vectors.)
    VD lo[kAll], hi[kAll];
    for (int k = 0; k < kFlatInputs; ++k)
      lo[k] = hn::LoadU(dd, in[k] + i), hi[k] = hn::LoadU(dd, in[k] + i + H);
    // One surface over the vector (ids do not decrease): broadcast; else per lane.
    if (id[i] == id[i + N - 1]) {
      const FlatSurface& f = surface[id[i]];
      for (int k = 0; k < 5; ++k) lo[kFlatInputs + k] = hi[kFlatInputs + k] = hn::Set(dd, f.k[k]);
    } else {
      for (size_t l = 0; l < N; ++l)
        for (int k = 0; k < 5; ++k) lanes[k][l] = surface[id[i + l]].k[k];
      for (int k = 0; k < 5; ++k)
        lo[kFlatInputs + k] = hn::Load(dd, lanes[k]), hi[kFlatInputs + k] = hn::Load(dd, lanes[k] + H);
    }
    const VD zero = hn::Zero(dd);
    const auto high_lo = hn::And(hn::Gt(lo[10], high), hn::Gt(lo[9], zero));
    const auto high_hi = hn::And(hn::Gt(hi[10], high), hn::Gt(hi[9], zero));
    if (!hn::AllFalse(dd, hn::Or(high_lo, high_hi))) {
      for (const VD* half : {lo, hi}) {
        VD col[3];
        FlatLit(dd, p, half, half + 3, half + 6, half[9], half[10], col);
        const size_t at = i + (half == lo ? 0 : H);
        for (int c = 0; c < 3; ++c) hn::StoreU(hn::DemoteTo(dh, col[c]), dh, out[c] + at);
      }
      continue;
    }
    VF v[kAll];
    for (int k = 0; k < kAll; ++k)
      v[k] = hn::Combine(df, hn::DemoteTo(dh, hi[k]), hn::DemoteTo(dh, lo[k]));
    VF col[3];
    FlatLit(df, p, v, v + 3, v + 6, v[9], v[10], col);
    for (int c = 0; c < 3; ++c) hn::StoreU(col[c], df, out[c] + i);
  }
}

// kFlat: flat shading without silhouettes, fixed at compile time (the
// benchmarks' case: the compiler then keeps no normal, light or Gouraud state,
// which at 16 lanes otherwise spills to the stack).
template <bool kFlat>
HWY_INLINE void ShadeTileT(const ShadeParams& p, const int32_t* tri, const TilePlanes* const* where,
                           int cols, int rows, float* rgb, float* zout, float* image,
                           size_t image_stride, float* depth, size_t depth_stride) {
  const hn::CappedTag<float, 16> df;
  const hn::RebindToSigned<decltype(df)> di;
  using VF = hn::Vec<decltype(df)>;
  using VI = hn::Vec<decltype(di)>;
  const int N = int(hn::Lanes(df));
  const int W = p.buf_w, H = p.buf_h;
  const size_t plane = size_t(W) * size_t(H);
  // Samples 0 .. spp-2 accumulate in rgb and zout; the last one writes the image.
  if (p.spp > 1) {
    std::fill_n(rgb, 3 * plane, 0.0f);
    std::fill_n(zout, plane, HUGE_VALF);
  }
  const VF inv_spp = hn::Set(df, 1.0f / float(p.spp));
  // The settings as locals: the stores below may alias p as far as the compiler knows.
  const int spp = p.spp, nlights = p.nlights;
  const bool perspective = p.perspective, silhouette = !kFlat && p.silhouette;
  const bool forward = kFlat && p.forward_w != nullptr;
  const float* const fwd_depth = p.forward_depth;
  const Shading shading = kFlat ? Shading::kFlat : p.shading;
  const float* const light = p.light;
  const bool flat = shading == Shading::kFlat, gouraud = shading == Shading::kGouraud;
  const bool lighting = !flat && !gouraud;
  const bool need_normal = lighting || silhouette;
  const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f);
  const VF inf = hn::Set(df, HUGE_VALF);
  const VI none = hn::Set(di, -1);
  const VF bg[3] = {hn::Set(df, p.background[0]), hn::Set(df, p.background[1]),
                    hn::Set(df, p.background[2])};
  const VF eye[3] = {hn::Set(df, p.eye[0]), hn::Set(df, p.eye[1]), hn::Set(df, p.eye[2])};
  const VF dir0[3] = {hn::Set(df, p.dir0[0]), hn::Set(df, p.dir0[1]), hn::Set(df, p.dir0[2])};
  const VF dir_u[3] = {hn::Set(df, p.dir_u[0]), hn::Set(df, p.dir_u[1]), hn::Set(df, p.dir_u[2])};
  const VF dir_v[3] = {hn::Set(df, p.dir_v[0]), hn::Set(df, p.dir_v[1]), hn::Set(df, p.dir_v[2])};
  const float bands = float(p.toon_bands),
              band_div = float(p.toon_bands - (p.toon_bands > 1 ? 1 : 0));
  HWY_ALIGN int32_t idv[16];
  // Lane l - 1 for lane l (0 for 0): a block's ids shifted, to find its runs.
  static constexpr int32_t kBefore[16] = {0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14};
  const auto lane_before = hn::SetTableIndices(di, kBefore);
  const auto first_lane = hn::FirstN(di, 1);

  auto dot3 = [](const VF a[3], const VF b[3]) {
    return hn::MulAdd(a[0], b[0], hn::MulAdd(a[1], b[1], hn::Mul(a[2], b[2])));
  };
  auto normalize3 = [&](VF a[3]) {
    const VF inv = hn::Div(one, hn::Sqrt(dot3(a, a)));
    for (int c = 0; c < 3; ++c) a[c] = hn::Mul(a[c], inv);
  };

  for (int smp = 0; smp < spp; ++smp) {
    const float ou = float(p.offsets[smp][0]) / float(kSubpixel),
                ov = float(p.offsets[smp][1]) / float(kSubpixel);
    for (int r = 0; r < rows; ++r) {
      const VF v = hn::Set(df, float(r) + ov);
      for (int c0 = 0; c0 < cols; c0 += N) {
        const size_t at = (size_t(smp) * H + size_t(r)) * W + size_t(c0);
        const size_t pix = size_t(r) * W + size_t(c0);
        // Drawn forward: a sample was drawn where its depth is finite (the
        // buffer starts at an infinite far end, which no depth passes; the
        // raster then writes no triangle ids).
        const VI ids = forward ? none : hn::Load(di, tri + at);
        auto remaining =
            forward ? hn::RebindMask(di, hn::Lt(hn::Abs(hn::Load(df, fwd_depth + at)), inf))
                    : hn::Gt(ids, none);
        VF col[3] = {bg[0], bg[1], bg[2]};
        VF z = inf;
        if (!hn::AllFalse(di, remaining)) {
          const auto valid = hn::RebindMask(df, remaining);
          if (!forward) hn::Store(ids, di, idv);
          const VF u = hn::Add(hn::Iota(df, float(c0)), hn::Set(df, ou));
          VF a[ShadeTri::kRows];
          a[0] = one;
          for (int k = 1; k < ShadeTri::kRows; ++k) a[k] = zero;
          VF kd[3] = {zero, zero, zero}, ks = zero, shine = one, fl[3] = {zero, zero, zero};
          // Per lane its triangle's material; whether the block holds more than one.
          VI mat = hn::Zero(di);
          int32_t mat0 = -1;
          bool mixed = false;
          if (forward) {
            // Drawn forward by the raster: w and the colour per sample.
            a[0] = hn::IfThenElse(valid, hn::Load(df, p.forward_w + at), one);
            for (int c = 0; c < 3; ++c) fl[c] = hn::Load(df, p.forward_rgb[c] + at);
            remaining = hn::Ne(ids, ids);  // none: no triangle loop
          }
          // The block's triangles, each broadcast onto its lanes: one per run
          // of equal ids along the lanes (a triangle's samples are neighbours;
          // one seen in two runs is taken twice, to the same values). A bit
          // loop over the runs' first lanes: no chain of dependent vector
          // operations from one triangle to the next.
          const auto starts =
              hn::And(remaining, hn::Or(hn::Ne(ids, hn::TableLookupLanes(ids, lane_before)),
                                        first_lane));
          uint64_t runs = 0;
          hn::StoreMaskBits(di, starts, reinterpret_cast<uint8_t*>(&runs));
          while (runs != 0) {
            const int32_t id = idv[std::countr_zero(runs)];
            runs &= runs - 1;
            const auto mi = hn::Eq(ids, hn::Set(di, id));  // (valid lanes only: id >= 0)
            const auto m = hn::RebindMask(df, mi);
            const TilePlanes& L = *where[id];
            // (Gouraud and flat read past TilePlanes: theirs are LocalPlanes.)
            const auto* full = reinterpret_cast<const LocalPlanes*>(&L);
            auto eval = [&](int k, const float* row) {
              a[k] = hn::IfThenElse(
                  m,
                  hn::MulAdd(hn::Set(df, row[2]), v,
                             hn::MulAdd(hn::Set(df, row[1]), u, hn::Set(df, row[0]))),
                  a[k]);
            };
            eval(0, L.p[0]);
            if (need_normal) eval(1, L.p[1]), eval(2, L.p[2]), eval(3, L.p[3]);
            if (gouraud) eval(4, full->more[0]), eval(5, full->more[1]), eval(6, full->more[2]);
            if (flat)
              for (int c = 0; c < 3; ++c)
                fl[c] = hn::IfThenElse(m, hn::Set(df, full->flat[c]), fl[c]);
            if (lighting) {
              const int32_t material = int32_t(L.tri.material);
              mat = hn::IfThenElse(mi, hn::Set(di, material), mat);
              mixed |= mat0 >= 0 && material != mat0;
              if (mat0 < 0) mat0 = material;
            }
          }
          // The material: one broadcast for the block (a sphere's or a
          // polygon's triangles share theirs), else gathered per lane.
          if (lighting && mat0 >= 0) {
            static_assert(sizeof(ShadeMaterial) == 5 * sizeof(float));
            if (!mixed) {
              const ShadeMaterial& M = p.materials[mat0];
              for (int c = 0; c < 3; ++c) kd[c] = hn::Set(df, M.k[c]);
              ks = hn::Set(df, M.ks), shine = hn::Set(df, M.shine);
            } else {
              const float* table = p.materials[0].k;
              const VI at = hn::Mul(mat, hn::Set(di, 5));
              for (int c = 0; c < 3; ++c) kd[c] = hn::GatherIndex(df, table + c, at);
              ks = hn::GatherIndex(df, table + 3, at), shine = hn::GatherIndex(df, table + 4, at);
            }
          }
          // z = 1 / w; attributes are plane / w (perspective) or the plane (affine).
          z = hn::Div(one, a[0]);
          const VF att = perspective ? z : one;
          // The view ray through the sample (forward component 1), the point
          // eye + z dir and the unit direction to the viewer.
          // (Only lighting and silhouettes need them: flat and Gouraud skip it.)
          VF dir[3], pos[3], view[3], nrm[3];
          if (need_normal) {
            for (int c = 0; c < 3; ++c) {
              dir[c] = hn::MulAdd(dir_v[c], v, hn::MulAdd(dir_u[c], u, dir0[c]));
              pos[c] = hn::MulAdd(z, dir[c], eye[c]);
              view[c] = hn::Neg(dir[c]);
            }
            normalize3(view);
            // The interpolated normal, renormalised (the face normal where it
            // vanishes), turned towards the viewer.
            for (int c = 0; c < 3; ++c) nrm[c] = hn::Mul(a[1 + c], att);
            const VF len2 = dot3(nrm, nrm);
            const auto degenerate = hn::Eq(len2, zero);
            const VF inv = hn::Div(one, hn::Sqrt(hn::IfThenElse(degenerate, one, len2)));
            for (int c = 0; c < 3; ++c) nrm[c] = hn::Mul(nrm[c], inv);
            // (Rare: a drawn sample whose interpolated normal vanishes takes its
            // triangle's face normal, looked up lane by lane.)
            const auto vanished = hn::And(degenerate, valid);
            if (!hn::AllFalse(df, vanished)) {
              HWY_ALIGN float face[3][16] = {};
              for (int l = 0; l < N; ++l)
                if (idv[l] >= 0)
                  for (int c = 0; c < 3; ++c) face[c][l] = where[idv[l]]->tri.face[c];
              for (int c = 0; c < 3; ++c)
                nrm[c] = hn::IfThenElse(vanished, hn::Load(df, face[c]), nrm[c]);
            }
            const auto away = hn::Gt(dot3(nrm, dir), zero);
            for (int c = 0; c < 3; ++c) nrm[c] = hn::IfThenElse(away, hn::Neg(nrm[c]), nrm[c]);
          }
          if (flat) {
            for (int c = 0; c < 3; ++c) col[c] = fl[c];
          } else if (gouraud) {
            for (int c = 0; c < 3; ++c) col[c] = hn::Mul(a[4 + c], att);
          } else {
            Lighting(df, light, nlights, shading, bands, band_div, pos, nrm, view, kd, ks, shine,
                     valid, col);
          }
          if (silhouette) {
            const VF ndv = hn::Abs(dot3(nrm, view));
            const auto edge = hn::Lt(ndv, hn::Set(df, p.silhouette_eps));
            for (int c = 0; c < 3; ++c) col[c] = hn::IfThenElseZero(hn::Not(edge), col[c]);
          }
          for (int c = 0; c < 3; ++c) col[c] = hn::IfThenElse(valid, col[c], bg[c]);
          z = hn::IfThenElse(valid, z, inf);
        }
        if (smp + 1 < spp) {
          for (int c = 0; c < 3; ++c) {
            float* acc = rgb + size_t(c) * plane + pix;
            hn::Store(hn::Add(hn::Load(df, acc), col[c]), df, acc);
          }
          hn::Store(hn::Min(hn::Load(df, zout + pix), z), df, zout + pix);
          continue;
        }
        // The last sample: the box filter's mean, and the nearest sample's eye depth.
        if (spp > 1) {
          for (int c = 0; c < 3; ++c)
            col[c] = hn::Mul(hn::Add(hn::Load(df, rgb + size_t(c) * plane + pix), col[c]), inv_spp);
          z = hn::Min(hn::Load(df, zout + pix), z);
        }
        const int n = std::min(N, cols - c0);
        WritePixels(df, col[0], col[1], col[2], image + size_t(r) * image_stride + 4 * size_t(c0),
                    n);
        float* zrow = depth + size_t(r) * depth_stride + size_t(c0);
        if (n == N) {
          // Streamed past the cache as the colours, when aligned (a page-aligned
          // depth plane, a row of a multiple of 16 pixels).
          if ((reinterpret_cast<uintptr_t>(zrow) & (sizeof(float) * N - 1)) == 0)
            hn::Stream(z, df, zrow);
          else
            hn::StoreU(z, df, zrow);
        } else {
          HWY_ALIGN float zz[16];
          hn::Store(z, df, zz);
          std::copy_n(zz, n, zrow);
        }
      }
    }
  }
}

void ShadeTile(const ShadeParams& p, const int32_t* tri, const TilePlanes* const* where, int cols,
               int rows, float* rgb, float* zout, float* image, size_t image_stride, float* depth,
               size_t depth_stride) {
  if (p.shading == Shading::kFlat && !p.silhouette)
    return ShadeTileT<true>(p, tri, where, cols, rows, rgb, zout, image, image_stride, depth,
                            depth_stride);
  ShadeTileT<false>(p, tri, where, cols, rows, rgb, zout, image, image_stride, depth, depth_stride);
}

void RasterTileFloat(const RasterParams& p, const TileJob& t, float* depth, int32_t* tri,
                     int32_t* count) {
  // 16 lanes where the CPU has them (AVX-512: 8-13% faster frames than 8 lanes,
  // even on Zen 4, which splits them in two), 8 on AVX2.
  const hn::CappedTag<float, 16> d;
  if (p.flat) {
    if (p.depth == DepthFormat::kReversed)
      return RasterTileT<true, false, true>(d, p, t, depth, tri, count);
    if (p.depth == DepthFormat::kFixed24)
      return RasterTileT<false, true, true>(d, p, t, depth, tri, count);
    return RasterTileT<false, false, true>(d, p, t, depth, tri, count);
  }
  if (p.depth == DepthFormat::kReversed)
    return RasterTileT<true, false, false>(d, p, t, depth, tri, count);
  if (p.depth == DepthFormat::kFixed24)
    return RasterTileT<false, true, false>(d, p, t, depth, tri, count);
  RasterTileT<false, false, false>(d, p, t, depth, tri, count);
}
void RasterTileDouble(const RasterParams& p, const TileJob& t, double* depth, int32_t* tri,
                      int32_t* count) {
  const hn::CappedTag<double, 8> d;  // (no forward flat shading: its buffers are float)
  if (p.depth == DepthFormat::kReversed)
    return RasterTileT<true, false, false>(d, p, t, depth, tri, count);
  if (p.depth == DepthFormat::kFixed24)
    return RasterTileT<false, true, false>(d, p, t, depth, tri, count);
  RasterTileT<false, false, false>(d, p, t, depth, tri, count);
}
const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

void BallEntries(const double ce[3], double rho2, bool inverted, double z_occ, double pitch,
                 double half_w, double dy, int cell, int a0, int n, double* out) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const int N = int(hn::Lanes(d));
  const V cx = hn::Set(d, ce[0]), zero = hn::Zero(d);
  const double c2 = ce[0] * ce[0] + ce[1] * ce[1] + ce[2] * ce[2];
  // dot(d, d) and dot(ce, d) without their x terms: the same along the row.
  const V yz2 = hn::Set(d, dy * dy + 1.0), cyz = hn::Set(d, ce[1] * dy + ce[2]);
  const V vc2 = hn::Set(d, c2), vrho2 = hn::Set(d, rho2), inf = hn::Set(d, HUGE_VAL);
  const V lane = hn::Iota(d, 0.0);
  for (int i = 0; i < n; i += N) {
    // The ray through corner a = a0 + i + lane: its distance to the centre.
    const V a = hn::Add(hn::Set(d, double(a0 + i)), lane);
    const V dx = hn::Mul(hn::Sub(hn::Mul(a, hn::Set(d, double(cell))), hn::Set(d, half_w)),
                         hn::Set(d, pitch));
    const V len2 = hn::MulAdd(dx, dx, yz2), t = hn::MulAdd(cx, dx, cyz);
    const V miss2 = hn::Sub(vc2, hn::Div(hn::Mul(t, t), len2));
    const auto meets = hn::And(hn::Gt(t, zero), hn::Lt(miss2, vrho2));
    // Entry at t / |d| - sqrt(rho^2 - miss^2) along the unit ray; eye depth that / |d|.
    const V len = hn::Sqrt(len2);
    const V entry =
        inverted ? hn::Set(d, z_occ)
                 : hn::Div(hn::Sub(hn::Div(t, len), hn::Sqrt(hn::Max(zero, hn::Sub(vrho2, miss2)))),
                           len);
    const V v = hn::IfThenElse(meets, entry, inf);
    if (i + N <= n) {
      hn::StoreU(v, d, out + i);
    } else {
      HWY_ALIGN double tmp[16];
      hn::Store(v, d, tmp);
      for (int k = 0; i + k < n; ++k) out[i + k] = tmp[k];
    }
  }
}

void GrowBounds(const Vec3* points, size_t n, Vec3& lo, Vec3& hi) {
  const hn::ScalableTag<double> d;
  const size_t N = hn::Lanes(d);
  size_t i = 0;
  if (n >= N) {
    hn::Vec<decltype(d)> l[3], h[3];
    for (int c = 0; c < 3; ++c) l[c] = hn::Set(d, lo[c]), h[c] = hn::Set(d, hi[c]);
    for (; i + N <= n; i += N) {
      hn::Vec<decltype(d)> p[3];
      hn::LoadInterleaved3(d, &points[i].x, p[0], p[1], p[2]);
      for (int c = 0; c < 3; ++c) {  // std::min(l, p) = p < l ? p : l, and the like
        l[c] = hn::IfThenElse(hn::Lt(p[c], l[c]), p[c], l[c]);
        h[c] = hn::IfThenElse(hn::Lt(h[c], p[c]), p[c], h[c]);
      }
    }
    HWY_ALIGN double bl[3][16], bh[3][16];
    for (int c = 0; c < 3; ++c) hn::Store(l[c], d, bl[c]), hn::Store(h[c], d, bh[c]);
    for (size_t k = 0; k < N; ++k)
      for (int c = 0; c < 3; ++c)
        lo[c] = std::min(lo[c], bl[c][k]), hi[c] = std::max(hi[c], bh[c][k]);
  }
  for (; i < n; ++i)
    for (int c = 0; c < 3; ++c)
      lo[c] = std::min(lo[c], points[i][c]), hi[c] = std::max(hi[c], points[i][c]);
}

void SphereFaces(const Vec3* world, const std::array<uint32_t, 3>* tri, size_t n, bool flip,
                 const Vec3& eye, double* face, uint8_t* flags) {
  const hn::ScalableTag<double> d;
  const hn::RebindToSigned<decltype(d)> di;
  using V = hn::Vec<decltype(d)>;
  const size_t N = hn::Lanes(d);
  const double* base = &world[0].x;
  const V ex = hn::Set(d, eye.x), ey = hn::Set(d, eye.y), ez = hn::Set(d, eye.z);
  const V zero = hn::Zero(d);
  HWY_ALIGN int64_t at[3][8];
  HWY_ALIGN double out[4][8];
  const int b = flip ? 2 : 1, c = flip ? 1 : 2;
  for (size_t i = 0; i < n; i += N) {
    const size_t m = std::min(N, n - i);
    for (size_t k = 0; k < N; ++k) {  // the tail repeats the last triangle
      const auto& t = tri[i + std::min(k, m - 1)];
      at[0][k] = 3 * int64_t(t[0]), at[1][k] = 3 * int64_t(t[b]), at[2][k] = 3 * int64_t(t[c]);
    }
    V w[3][3];  // vertex, coordinate
    for (int v = 0; v < 3; ++v) {
      const auto idx = hn::Load(di, at[v]);
      for (int x = 0; x < 3; ++x) w[v][x] = hn::GatherIndex(d, base + x, idx);
    }
    // cross(w1 - w0, w2 - w0), its length, the unit normal: core/math.h's operations.
    V e1[3], e2[3];
    for (int x = 0; x < 3; ++x)
      e1[x] = hn::Sub(w[1][x], w[0][x]), e2[x] = hn::Sub(w[2][x], w[0][x]);
    const V fn[3] = {hn::Sub(hn::Mul(e1[1], e2[2]), hn::Mul(e1[2], e2[1])),
                     hn::Sub(hn::Mul(e1[2], e2[0]), hn::Mul(e1[0], e2[2])),
                     hn::Sub(hn::Mul(e1[0], e2[1]), hn::Mul(e1[1], e2[0]))};
    const V len = hn::Sqrt(
        hn::Add(hn::Add(hn::Mul(fn[0], fn[0]), hn::Mul(fn[1], fn[1])), hn::Mul(fn[2], fn[2])));
    const V un[3] = {hn::Div(fn[0], len), hn::Div(fn[1], len), hn::Div(fn[2], len)};
    const V to_eye[3] = {hn::Sub(ex, w[0][0]), hn::Sub(ey, w[0][1]), hn::Sub(ez, w[0][2])};
    const V facing = hn::Add(hn::Add(hn::Mul(un[0], to_eye[0]), hn::Mul(un[1], to_eye[1])),
                             hn::Mul(un[2], to_eye[2]));
    for (int x = 0; x < 3; ++x) hn::Store(un[x], d, out[x]);
    hn::Store(hn::IfThenElse(hn::Eq(len, zero), hn::Set(d, double(kNoFace)),
                             hn::IfThenElseZero(hn::Gt(facing, zero), hn::Set(d, double(kFront)))),
              d, out[3]);
    for (size_t k = 0; k < m; ++k) {
      for (int x = 0; x < 3; ++x) face[3 * (i + k) + size_t(x)] = out[x][k];
      flags[i + k] = uint8_t(out[3][k]);
    }
  }
}

// ---------------------------------------------------------------- the set-up's vertex step
//
// core/viewing.cpp's eye_from_world, inside_all and to_screen on N
// vertices at once, with the very same double operations in the same order
// (no fused multiply-add: the build has -ffp-contract=off), so the same bits;
// llround as trunc plus a correction (exact: x - trunc(x) is exact). The tail
// (fewer than N vertices) runs the same lanes on a padded copy.
// One vector of vertices (world coordinates wx, wy, wz): eye depth ez, the
// snapped x and y (0 where not inside), inside, and with depth w = 1/z and the
// stored depth q.
template <class D, class V = hn::Vec<D>>
struct ProjectLanes {
  D d;
  V eye[3], rt[3], up[3], fw[3];
  V near_z, g, zero, half_w, half_h, pitch, sub, half, one;
  V dm_near, dm_inv_near, dm_range;
  bool reversed = false;
  ProjectLanes(D d_, const Projection& p, const DepthMap* depth) : d(d_) {
    for (int c = 0; c < 3; ++c) {
      eye[c] = hn::Set(d, p.eye[c]), rt[c] = hn::Set(d, p.right[c]);
      up[c] = hn::Set(d, p.up[c]), fw[c] = hn::Set(d, p.forward[c]);
    }
    near_z = hn::Set(d, p.near_z), g = hn::Set(d, p.g), zero = hn::Zero(d);
    half_w = hn::Set(d, p.half_w), half_h = hn::Set(d, p.half_h), pitch = hn::Set(d, p.pitch);
    sub = hn::Set(d, double(kSubpixel)), half = hn::Set(d, 0.5), one = hn::Set(d, 1.0);
    dm_near = hn::Set(d, depth ? depth->near_z : 1.0);
    dm_inv_near = hn::Set(d, depth ? depth->inv_near : 1.0);
    dm_range = hn::Set(d, depth ? depth->range : 1.0);
    reversed = depth && depth->reversed;
  }
  static V dot(const V a[3], const V b[3]) {  // (a.x b.x + a.y b.y) + a.z b.z, as Vec3's dot
    return hn::Add(hn::Add(hn::Mul(a[0], b[0]), hn::Mul(a[1], b[1])), hn::Mul(a[2], b[2]));
  }
  V round_half_away(V x) const {
    const V t = hn::Trunc(x);
    const V f = hn::Sub(x, t);
    return hn::Sub(hn::Add(t, hn::IfThenElseZero(hn::Ge(f, half), one)),
                   hn::IfThenElseZero(hn::Le(f, hn::Neg(half)), one));
  }
  // The eye depth, snapped position and clip test of the vertices w.
  HWY_INLINE void position(const V w[3], V& ez, V& x, V& y, hn::Mask<D>& inside) const {
    const V dv[3] = {hn::Sub(w[0], eye[0]), hn::Sub(w[1], eye[1]), hn::Sub(w[2], eye[2])};
    const V ex = dot(dv, rt), ey = dot(dv, up);
    ez = dot(dv, fw);
    const V gz = hn::Mul(g, ez);
    inside = hn::And(hn::And(hn::Ge(hn::Sub(ez, near_z), zero), hn::Ge(hn::Sub(gz, ex), zero)),
                     hn::And(hn::And(hn::Ge(hn::Add(gz, ex), zero), hn::Ge(hn::Sub(gz, ey), zero)),
                             hn::Ge(hn::Add(gz, ey), zero)));
    const V den = hn::Mul(ez, pitch);
    const V sx = hn::Add(half_w, hn::Div(ex, den));
    const V sy = hn::Sub(half_h, hn::Div(ey, den));
    x = round_half_away(hn::IfThenElseZero(inside, hn::Mul(sx, sub)));
    y = round_half_away(hn::IfThenElseZero(inside, hn::Mul(sy, sub)));
  }
  // DepthMap: w = 1/z, then (1/n - w) / range or n / z.
  HWY_INLINE void depth(V ez, V& w, V& q) const {
    w = hn::Div(one, ez);
    q = reversed ? hn::Div(dm_near, ez) : hn::Div(hn::Sub(dm_inv_near, w), dm_range);
  }
};

void ProjectVertices(const Projection& p, const Vec3* world, size_t n, ProjectedVertex* out,
                     const DepthMap* depth, VertexDepth* depth_out) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const size_t N = hn::Lanes(d);
  const ProjectLanes<decltype(d)> proj(d, p, depth);
  const V one = hn::Set(d, 1.0);
  HWY_ALIGN double zs[16], xs[16], ys[16], ins[16], ws[16], qs[16];
  HWY_ALIGN double pad[3 * 16];
  for (size_t i = 0; i < n; i += N) {
    const size_t m = std::min(N, n - i);
    const double* src = &world[i].x;
    if (m < N) {  // the tail: a copy padded with the last vertex
      for (size_t k = 0; k < N; ++k)
        for (int c = 0; c < 3; ++c) pad[3 * k + c] = world[i + std::min(k, m - 1)][c];
      src = pad;
    }
    V w[3];
    hn::LoadInterleaved3(d, src, w[0], w[1], w[2]);
    V ez, x, y;
    hn::Mask<decltype(d)> inside;
    proj.position(w, ez, x, y, inside);
    hn::Store(ez, d, zs);
    hn::Store(x, d, xs);
    hn::Store(y, d, ys);
    hn::Store(hn::IfThenElseZero(inside, one), d, ins);
    if (depth) {
      V wv, q;
      proj.depth(ez, wv, q);
      hn::Store(wv, d, ws);
      hn::Store(q, d, qs);
      for (size_t k = 0; k < m; ++k) depth_out[i + k] = {ws[k], qs[k]};
    }
    for (size_t k = 0; k < m; ++k) {
      ProjectedVertex& o = out[i + k];
      o.z = zs[k];
      o.x = int32_t(int64_t(xs[k]));
      o.y = int32_t(int64_t(ys[k]));
      o.inside = ins[k] != 0;
    }
  }
}

// SampleGrid::pixels for a vector of triangles of vertices (x[k], y[k]) (the
// floor and ceiling of / 256 are shifts): triangle_step's and set_up_forward's.
template <class DI, class VI = hn::Vec<DI>>
HWY_INLINE void PixelBox(DI di, const SampleGrid& grid, const VI x[3], const VI y[3], VI& i0,
                         VI& i1, VI& j0, VI& j1) {
  static_assert(kSubpixel == 256);
  const VI zero = hn::Zero(di), round = hn::Set(di, kSubpixel - 1);
  const VI xmin = hn::Min(hn::Min(x[0], x[1]), x[2]), xmax = hn::Max(hn::Max(x[0], x[1]), x[2]);
  const VI ymin = hn::Min(hn::Min(y[0], y[1]), y[2]), ymax = hn::Max(hn::Max(y[0], y[1]), y[2]);
  i0 = hn::Max(zero, hn::ShiftRight<8>(hn::Add(hn::Sub(xmin, hn::Set(di, grid.ox1)), round)));
  i1 = hn::Min(hn::Set(di, grid.width - 1), hn::ShiftRight<8>(hn::Sub(xmax, hn::Set(di, grid.ox0))));
  j0 = hn::Max(zero, hn::ShiftRight<8>(hn::Add(hn::Sub(ymin, hn::Set(di, grid.oy1)), round)));
  j1 = hn::Min(hn::Set(di, grid.height - 1), hn::ShiftRight<8>(hn::Sub(ymax, hn::Set(di, grid.oy0))));
}

// One sample per pixel (grid.ox0 == ox1, oy0 == oy1): the triangles of a
// vector (vertices x[k], y[k] in the raster's order, box i0..j1 from PixelBox)
// that are small (vertices within 16 px of each other both ways, a box of at
// most 3 x 3 samples) and cover none of their box's samples: E_k >= bias_k
// for no sample and every edge k, the raster's own test (set_up_forward's
// edges). Such a triangle draws nothing. (Edge values there are below 2^25:
// int32.) 3 x 3: on balls-3 (AVX2, callgrind) 2 x 2 catches too few, 4 x 4
// costs more than the triangles it sorts out save.
// The raster's edges of a vector of triangles (vertices x[k], y[k] in its
// order): edge k from vertex a = k + 1 to b = k + 2, E_k = ex (X - x_a) +
// ey (Y - y_a), a sample covered where E_k >= bias_k (0 on a top or left
// edge, else 1): set_up_forward's and CoversNothing's.
template <class DI, class VI = hn::Vec<DI>>
HWY_INLINE void Edges(DI di, const VI x[3], const VI y[3], VI ex[3], VI ey[3], VI bias[3]) {
  const VI zero = hn::Zero(di);
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    const VI dx = hn::Sub(x[b], x[a]), dy = hn::Sub(y[b], y[a]);
    ex[k] = hn::Neg(dy), ey[k] = dx;
    const auto top_left = hn::Or(hn::And(hn::Eq(dy, zero), hn::Gt(dx, zero)), hn::Lt(dy, zero));
    bias[k] = hn::IfThenZeroElse(top_left, hn::Set(di, 1));
  }
}

template <class DI, class VI = hn::Vec<DI>>
HWY_INLINE hn::Mask<DI> CoversNothing(DI di, const SampleGrid& grid, const VI x[3], const VI y[3],
                                      const VI edge_x[3], const VI edge_y[3], const VI bias[3],
                                      VI i0, VI i1, VI j0, VI j1) {
  static_assert(kSubpixel == 256);
  constexpr int kSide = 3;
  const VI zero = hn::Zero(di), side = hn::Set(di, kSide);
  const VI limit = hn::Set(di, 16 * kSubpixel);
  const VI xmin = hn::Min(hn::Min(x[0], x[1]), x[2]), xmax = hn::Max(hn::Max(x[0], x[1]), x[2]);
  const VI ymin = hn::Min(hn::Min(y[0], y[1]), y[2]), ymax = hn::Max(hn::Max(y[0], y[1]), y[2]);
  const auto small =
      hn::And(hn::And(hn::Lt(hn::Sub(xmax, xmin), limit), hn::Lt(hn::Sub(ymax, ymin), limit)),
              hn::And(hn::Lt(hn::Sub(i1, i0), side), hn::Lt(hn::Sub(j1, j0), side)));
  if (hn::AllFalse(di, small)) return small;
  // Covered where E_k >= bias_k, i.e. E_k > bias_k - 1.
  VI ex[3], ey[3], floor_e[3];
  for (int k = 0; k < 3; ++k)
    ex[k] = edge_x[k], ey[k] = edge_y[k], floor_e[k] = hn::Sub(bias[k], hn::Set(di, 1));
  // The edges at the box's first sample, then stepped: 256 ex a column, 256 ey a row.
  const VI sx0 = hn::Add(hn::ShiftLeft<8>(i0), hn::Set(di, grid.ox0));
  const VI sy0 = hn::Add(hn::ShiftLeft<8>(j0), hn::Set(di, grid.oy0));
  VI row_e[3];
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3;
    row_e[k] = hn::Add(hn::Mul(ex[k], hn::Sub(sx0, x[a])), hn::Mul(ey[k], hn::Sub(sy0, y[a])));
    ex[k] = hn::ShiftLeft<8>(ex[k]), ey[k] = hn::ShiftLeft<8>(ey[k]);
  }
  // Columns and rows past the box's own: never covered.
  const VI cols = hn::Sub(i1, i0), rows = hn::Sub(j1, j0);
  auto covered = hn::Not(hn::Eq(zero, zero));
  for (int r = 0; r < kSide; ++r) {
    const auto row_in = hn::Gt(rows, hn::Set(di, r - 1));
    VI e[3] = {row_e[0], row_e[1], row_e[2]};
    for (int c = 0; c < kSide; ++c) {
      auto in = hn::And(row_in, hn::Gt(cols, hn::Set(di, c - 1)));
      for (int k = 0; k < 3; ++k) {
        in = hn::And(in, hn::Gt(e[k], floor_e[k]));
        e[k] = hn::Add(e[k], ex[k]);
      }
      covered = hn::Or(covered, in);
    }
    if (hn::AllTrue(di, hn::Or(covered, hn::Not(small)))) break;
    for (int k = 0; k < 3; ++k) row_e[k] = hn::Add(row_e[k], ey[k]);
  }
  return hn::AndNot(covered, small);
}

// triangle_step: the vertices' first 16 bytes a lane (ProjectedVertex: z at
// double 0, x and y at int32 2 and 3 of its 24 bytes), LoadPairs, not gathers;
// the area exact in double as in int64. The kept triangles are compressed to
// the front of the arrays as they are found (at most as far as the vector
// just read).
// Whether everything at eye depth >= z_min with its samples in pixels
// [i0, i1] x [j0, j1] loses to the occluders, from the coarse cells
// (zbuffer_setup's OcclusionMap::hidden, the same test).
bool CoarseHidden(const OcclusionCells& occ, int i0, int i1, int j0, int j1, double z_min) {
  static_assert(kOcclusionCell == 4);
  double beyond = -HUGE_VAL;
  const double* coarse = occ.beyond + occ.coarse;
  for (int b = j0 / 8; b <= j1 / 8; ++b)
    for (int a = i0 / 8; a <= i1 / 8; ++a)
      beyond = std::max(beyond, coarse[size_t(b) * size_t(occ.coarse_nx) + size_t(a)]);
  return z_min > beyond;
}

size_t TriangleStep(const ProjectedVertex* pv, uint32_t* a, uint32_t* b, uint32_t* c,
                    uint32_t* tag, size_t n, const SampleGrid& grid, bool cull_projection,
                    const OcclusionCells* occ, TriangleCounts& counts) {
  static_assert(sizeof(ProjectedVertex) == 24 && offsetof(ProjectedVertex, x) == 8 &&
                offsetof(ProjectedVertex, y) == 12 && offsetof(ProjectedVertex, z) == 0);
  const hn::CappedTag<double, 8> dd;
  const hn::Rebind<int32_t, decltype(dd)> di;
  const hn::Rebind<uint32_t, decltype(dd)> du;
  using VD = hn::Vec<decltype(dd)>;
  using VI = hn::Vec<decltype(di)>;
  const size_t N = hn::Lanes(dd);
  const hn::Rebind<uint64_t, decltype(dd)> d64;
  const double* zs = reinterpret_cast<const double*>(pv);
  const VI two = hn::Set(di, 2);
  const VI zero_i = hn::Zero(di);
  const VI lane = hn::Iota(di, 0);
  const VD zero = hn::Zero(dd);
  const bool one_sample = grid.ox0 == grid.ox1 && grid.oy0 == grid.oy1;
  size_t kept = 0;
  for (size_t i = 0; i < n; i += N) {
    const auto ib = hn::LoadU(du, b + i), ic = hn::LoadU(du, c + i);
    VI x[3], y[3];
    VD z[3];
    const uint32_t* const index[3] = {a + i, b + i, c + i};
    for (int k = 0; k < 3; ++k) {
      // Word 0 of the vertex's three 8-byte words: z; word 1: x (low half) and y.
      VD xyd;
      LoadPairs(dd, [&](int l) { return zs + 3 * size_t(index[k][l]); }, z[k], xyd);
      const auto xy = hn::BitCast(d64, xyd);
      x[k] = hn::BitCast(di, hn::TruncateTo(du, xy));
      y[k] = hn::BitCast(di, hn::TruncateTo(du, hn::ShiftRight<32>(xy)));
    }
    // (p1.x - p0.x)(p2.y - p0.y) - (p1.y - p0.y)(p2.x - p0.x), exactly.
    const VD area =
        hn::Sub(hn::Mul(hn::PromoteTo(dd, hn::Sub(x[1], x[0])), hn::PromoteTo(dd, hn::Sub(y[2], y[0]))),
                hn::Mul(hn::PromoteTo(dd, hn::Sub(y[1], y[0])), hn::PromoteTo(dd, hn::Sub(x[2], x[0]))));
    VI i0, i1, j0, j1;
    PixelBox(di, grid, x, y, i0, i1, j0, j1);
    const VD zlo = hn::Min(hn::Min(z[0], z[1]), z[2]);
    // The area's sign in int32 lanes.
    const VI sign = hn::DemoteTo(
        di, hn::IfThenElse(hn::Gt(area, zero), hn::Set(dd, 1.0),
                           hn::IfThenElseZero(hn::Lt(area, zero), hn::Set(dd, -1.0))));
    // Negative area: b and c swapped (the raster's order).
    const auto swap = hn::Lt(sign, zero_i);
    // What drops a triangle, most specific first: degenerate (zero area),
    // culled (positive area, projection culling), no sample (uncounted).
    const auto in_range = hn::Lt(lane, hn::Set(di, int32_t(std::min(N, n - i))));
    const auto degenerate = hn::And(in_range, hn::Eq(sign, zero_i));
    auto left = hn::AndNot(degenerate, in_range);  // (not yet dropped)
    if (cull_projection) {
      const auto culled = hn::And(left, hn::Gt(sign, zero_i));
      counts.culled += hn::CountTrue(di, culled);
      left = hn::AndNot(culled, left);
    }
    counts.degenerate += hn::CountTrue(di, degenerate);
    auto none = hn::Or(hn::Gt(i0, i1), hn::Gt(j0, j1));
    if (one_sample) {  // (or a small triangle that covers no sample in it)
      const VI xs[3] = {x[0], hn::IfThenElse(swap, x[2], x[1]), hn::IfThenElse(swap, x[1], x[2])};
      const VI ys[3] = {y[0], hn::IfThenElse(swap, y[2], y[1]), hn::IfThenElse(swap, y[1], y[2])};
      VI ex[3], ey[3], bias[3];
      Edges(di, xs, ys, ex, ey, bias);
      none = hn::Or(none, CoversNothing(di, grid, xs, ys, ex, ey, bias, i0, i1, j0, j1));
    }
    auto keep = hn::AndNot(none, left);
    if (occ && !hn::AllFalse(di, keep)) {
      // The cells of the box's corners (a box within 2 x 2 cells has no others):
      // fine ones, else coarse ones.
      static_assert(kOcclusionCell == 4);
      VI a0 = hn::ShiftRight<2>(i0), a1 = hn::ShiftRight<2>(i1);
      VI b0 = hn::ShiftRight<2>(j0), b1 = hn::ShiftRight<2>(j1);
      const auto fine = hn::And(hn::Lt(hn::Sub(a1, a0), two), hn::Lt(hn::Sub(b1, b0), two));
      const VI ca0 = hn::ShiftRight<3>(i0), ca1 = hn::ShiftRight<3>(i1);
      const VI cb0 = hn::ShiftRight<3>(j0), cb1 = hn::ShiftRight<3>(j1);
      const auto coarse = hn::And(hn::Lt(hn::Sub(ca1, ca0), two), hn::Lt(hn::Sub(cb1, cb0), two));
      const auto near = hn::And(keep, hn::Or(fine, coarse));
      auto hidden = hn::FirstN(di, 0);
      if (!hn::AllFalse(di, near)) {
        a0 = hn::IfThenElse(fine, a0, ca0), a1 = hn::IfThenElse(fine, a1, ca1);
        b0 = hn::IfThenElse(fine, b0, cb0), b1 = hn::IfThenElse(fine, b1, cb1);
        const VI nx = hn::IfThenElse(fine, hn::Set(di, occ->nx), hn::Set(di, occ->coarse_nx));
        const VI at = hn::IfThenElseZero(hn::Not(fine), hn::Set(di, occ->coarse));
        const VI row0 = hn::Add(at, hn::Mul(b0, nx)), row1 = hn::Add(at, hn::Mul(b1, nx));
        // Cells a0 and a0 + 1 of both rows, two at a time (LoadPairs; a1 is
        // a0 or a0 + 1: where it is a0, cell a0 + 1 is read and ignored: the
        // map has a cell of slack at its end). (Lanes not tested read cell 0.)
        HWY_ALIGN int32_t cell[2][8];
        hn::Store(hn::IfThenElseZero(near, hn::Add(row0, a0)), di, cell[0]);
        hn::Store(hn::IfThenElseZero(near, hn::Add(row1, a0)), di, cell[1]);
        const auto one_column = CastMask(dd, di, hn::Eq(a1, a0));
        VD beyond = hn::Set(dd, -HUGE_VAL);
        for (int r = 0; r < 2; ++r) {
          VD left_cell, right_cell;
          LoadPairs(dd, [&](int l) { return occ->beyond + cell[r][l]; }, left_cell, right_cell);
          beyond = hn::Max(beyond, hn::Max(left_cell, hn::IfThenElse(one_column, left_cell, right_cell)));
        }
        hidden = hn::And(near, CastMask(di, dd, hn::Gt(zlo, beyond)));
      }
      // Wider boxes: the coarse cells one triangle at a time (few: the large triangles).
      const auto wide = hn::AndNot(hn::Or(fine, coarse), keep);
      if (!hn::AllFalse(di, wide)) {
        HWY_ALIGN int32_t bx[4][8];
        HWY_ALIGN double zl[8];
        hn::Store(i0, di, bx[0]), hn::Store(i1, di, bx[1]);
        hn::Store(j0, di, bx[2]), hn::Store(j1, di, bx[3]);
        hn::Store(zlo, dd, zl);
        HWY_ALIGN int32_t wide_hidden[8];
        hn::Store(hn::VecFromMask(di, wide), di, wide_hidden);
        for (size_t l = 0; l < N; ++l)
          if (wide_hidden[l])
            wide_hidden[l] = CoarseHidden(*occ, bx[0][l], bx[1][l], bx[2][l], bx[3][l], zl[l]) ? -1 : 0;
        hidden = hn::Or(hidden, hn::Gt(zero_i, hn::Load(di, wide_hidden)));
      }
      counts.hidden += hn::CountTrue(di, hidden);
      keep = hn::AndNot(hidden, keep);
    }
    // The kept ones to the front (kept <= i: everything from kept on that the
    // stores may write has been read).
    const auto keep_u = hn::RebindMask(du, keep);
    const auto swap_u = hn::RebindMask(du, swap);
    hn::CompressStore(hn::LoadU(du, a + i), keep_u, du, a + kept);
    hn::CompressStore(hn::IfThenElse(swap_u, ic, ib), keep_u, du, b + kept);
    hn::CompressStore(hn::IfThenElse(swap_u, ib, ic), keep_u, du, c + kept);
    kept += hn::CompressStore(hn::LoadU(du, tag + i), keep_u, du, tag + kept);
  }
  return kept;
}

#if HWY_TARGET <= HWY_AVX3
// AVX-512: eight TriSetups written from their fields' lanes by an 8 x 8
// transpose of 8-byte words in registers (instead of a scalar loop over the
// fields, which was ~45% of set_up_forward). Triangle j's words: int32 fields
// in pairs for its first cache line (ax, ay, ex, ey, the box as int16s, the
// biases as bytes, then zeros), doubles for the second (q0, qx, qy, w0, wx, wy,
// then the flat colour 0 and the padding). Writes the first m.
HWY_INLINE void Transpose8x8(__m512i r[8]) {
  __m512i a[8];
  for (int k = 0; k < 4; ++k) {
    a[2 * k] = _mm512_unpacklo_epi64(r[2 * k], r[2 * k + 1]);  // words 2b of rows 2k, 2k + 1
    a[2 * k + 1] = _mm512_unpackhi_epi64(r[2 * k], r[2 * k + 1]);
  }
  // Column 2b + p (p = 0, 1) is the 16-byte block b of a[p], a[2 + p], a[4 + p], a[6 + p].
  for (int p = 0; p < 2; ++p) {
    const __m512i b0 = _mm512_shuffle_i64x2(a[p], a[2 + p], 0x44);      // blocks 0 1 | 0 1
    const __m512i b1 = _mm512_shuffle_i64x2(a[p], a[2 + p], 0xEE);      // 2 3 | 2 3
    const __m512i b2 = _mm512_shuffle_i64x2(a[4 + p], a[6 + p], 0x44);
    const __m512i b3 = _mm512_shuffle_i64x2(a[4 + p], a[6 + p], 0xEE);
    r[p] = _mm512_shuffle_i64x2(b0, b2, 0x88);      // blocks 0 of all four
    r[2 + p] = _mm512_shuffle_i64x2(b0, b2, 0xDD);  // blocks 1
    r[4 + p] = _mm512_shuffle_i64x2(b1, b3, 0x88);  // blocks 2
    r[6 + p] = _mm512_shuffle_i64x2(b1, b3, 0xDD);  // blocks 3
  }
}

HWY_INLINE void WriteSetUps(const int32_t (*x)[8], const int32_t (*y)[8], const int32_t (*ex)[8],
                            const int32_t (*ey)[8], const int32_t (*bias)[8],
                            const int32_t (*box)[8], const double* q0, const double* qx,
                            const double* qy, const double* w0, const double* wx,
                            const double* wy, size_t m, TriSetup* out) {
  static_assert(offsetof(TriSetup, ax) == 0 && offsetof(TriSetup, ay) == 12 &&
                offsetof(TriSetup, ex) == 24 && offsetof(TriSetup, ey) == 36 &&
                offsetof(TriSetup, i0) == 48 && offsetof(TriSetup, j0) == 52 &&
                offsetof(TriSetup, bias) == 56 && offsetof(TriSetup, q0) == 64 &&
                offsetof(TriSetup, fwd.w0) == 88 && offsetof(TriSetup, fwd.flat) == 112);
  auto lanes = [](const int32_t* v) { return _mm256_load_si256(reinterpret_cast<const __m256i*>(v)); };
  // Two int32 fields as the words (lo | hi << 32).
  auto pair = [](__m256i lo, __m256i hi) {
    return _mm512_or_si512(_mm512_cvtepu32_epi64(lo), _mm512_slli_epi64(_mm512_cvtepu32_epi64(hi), 32));
  };
  // set_box's clamping, then two int16s in an int32: (lo & 0xffff) | hi << 16.
  const __m256i cap = _mm256_set1_epi32(1 << 14), none = _mm256_set1_epi32(-1);
  auto box16 = [&](int a, int b) {
    const __m256i lo = _mm256_min_epi32(lanes(box[a]), cap), hi = _mm256_max_epi32(lanes(box[b]), none);
    return _mm256_or_si256(_mm256_and_si256(lo, _mm256_set1_epi32(0xffff)), _mm256_slli_epi32(hi, 16));
  };
  const __m256i biases = _mm256_or_si256(
      lanes(bias[0]), _mm256_or_si256(_mm256_slli_epi32(lanes(bias[1]), 8), _mm256_slli_epi32(lanes(bias[2]), 16)));
  // ax[k] = x[(k + 1) % 3], as ay.
  __m512i lo[8] = {pair(lanes(x[1]), lanes(x[2])), pair(lanes(x[0]), lanes(y[1])),
                   pair(lanes(y[2]), lanes(y[0])), pair(lanes(ex[0]), lanes(ex[1])),
                   pair(lanes(ex[2]), lanes(ey[0])), pair(lanes(ey[1]), lanes(ey[2])),
                   pair(box16(0, 1), box16(2, 3)), pair(biases, _mm256_setzero_si256())};
  auto words = [](const double* v) { return _mm512_castpd_si512(_mm512_load_pd(v)); };
  __m512i hi[8] = {words(q0), words(qx), words(qy), words(w0), words(wx), words(wy),
                   _mm512_setzero_si512(), _mm512_setzero_si512()};
  Transpose8x8(lo);
  Transpose8x8(hi);
  for (size_t j = 0; j < m; ++j) {
    char* t = reinterpret_cast<char*>(out + j);
    _mm512_storeu_si512(t, lo[j]);
    _mm512_storeu_si512(t + 64, hi[j]);
  }
}
#endif

// set_up_forward: a vector of triangles at a time, their vertices' fields
// fetched into lanes on the stack (Fetch: fetch(i, x, y, w, q) fills vertex
// k's x[k][0 .. N), ... for triangles i ..) and written back per triangle. The
// area is exact in double as in int64 (snapped coordinates stay below 2^25 in
// magnitude inside the guard band: products below 2^52).
// Extra: extra(i, m, exd, eyd, inv_area, w, x, y, box) after the planes, for
// the shading's planes (SetUpShaded; box: i0, i1, j0, j1 as the TriSetup's);
// a no-op for the forward set-up.
struct NoExtra {
  template <class... A>
  void operator()(const A&...) const {}
};
template <class Fetch, class Extra = NoExtra>
HWY_INLINE void SetUpForwardT(const Fetch& fetch, size_t n, const SampleGrid& grid, TriSetup* out,
                              bool tested, const Extra& extra = Extra()) {
  const hn::CappedTag<double, 8> dd;
  const hn::Rebind<int32_t, decltype(dd)> di;
  using VD = hn::Vec<decltype(dd)>;
  using VI = hn::Vec<decltype(di)>;
  const size_t N = hn::Lanes(dd);
  HWY_ALIGN int32_t x_in[3][8], y_in[3][8], box[4][8], ex[3][8], ey[3][8], bias[3][8];
  HWY_ALIGN double w_in[3][8], q_in[3][8], qx[8], qy[8], wx[8], wy[8];
  const VI one_i = hn::Set(di, 1);
  const VD one = hn::Set(dd, 1.0);
  const bool test = !tested && grid.ox0 == grid.ox1 && grid.oy0 == grid.oy1;
  static_assert(kSubpixel == 256);
  for (size_t i = 0; i < n; i += N) {
    const size_t m = std::min(N, n - i);
    fetch(i, x_in, y_in, w_in, q_in);
    VI x[3], y[3];
    for (int k = 0; k < 3; ++k) x[k] = hn::Load(di, x_in[k]), y[k] = hn::Load(di, y_in[k]);
    VI i0, i1, j0, j1;
    PixelBox(di, grid, x, y, i0, i1, j0, j1);
    // Edge k from vertex a = k + 1 to b = k + 2: E_k = ex (X - x_a) + ey (Y - y_a).
    VD exd[3], eyd[3];
    VI exi[3], eyi[3], bi[3];
    Edges(di, x, y, exi, eyi, bi);
    for (int k = 0; k < 3; ++k) {
      hn::Store(exi[k], di, ex[k]);
      hn::Store(eyi[k], di, ey[k]);
      hn::Store(bi[k], di, bias[k]);
      exd[k] = hn::PromoteTo(dd, exi[k]);
      eyd[k] = hn::PromoteTo(dd, eyi[k]);
    }
    // One sample per pixel: a small triangle that covers none of its box's
    // samples would draw nothing: its box is left empty, so it is never binned.
    VI hi = i1;
    if (test)
      hi = hn::IfThenElse(CoversNothing(di, grid, x, y, exi, eyi, bi, i0, i1, j0, j1),
                          hn::Sub(i0, one_i), i1);
    hn::Store(i0, di, box[0]);
    hn::Store(hi, di, box[1]);
    hn::Store(j0, di, box[2]);
    hn::Store(j1, di, box[3]);
    // Twice the area, E_2 at vertex 2, and the planes of q and w.
    const VD area = hn::Add(hn::Mul(exd[2], hn::PromoteTo(dd, hn::Sub(x[2], x[0]))),
                            hn::Mul(eyd[2], hn::PromoteTo(dd, hn::Sub(y[2], y[0]))));
    const VD inv_area = hn::Div(one, area);
    auto gradient = [&](const double (*v)[8], const VD e[3]) {
      const VD v0 = hn::Load(dd, v[0]);
      return hn::Add(hn::Mul(hn::Sub(hn::Load(dd, v[1]), v0), e[1]),
                     hn::Mul(hn::Sub(hn::Load(dd, v[2]), v0), e[2]));
    };
    hn::Store(hn::Div(gradient(q_in, exd), area), dd, qx);
    hn::Store(hn::Div(gradient(q_in, eyd), area), dd, qy);
    hn::Store(hn::Mul(gradient(w_in, exd), inv_area), dd, wx);
    hn::Store(hn::Mul(gradient(w_in, eyd), inv_area), dd, wy);
    extra(i, m, exd, eyd, inv_area, w_in, x_in, y_in, box);
#if HWY_TARGET <= HWY_AVX3
    if constexpr (hn::MaxLanes(dd) == 8) {
      WriteSetUps(x_in, y_in, ex, ey, bias, box, q_in[0], qx, qy, w_in[0], wx, wy, m, out + i);
      continue;
    }
#endif
    for (size_t j = 0; j < m; ++j) {
      TriSetup& t = out[i + j];
      for (int k = 0; k < 3; ++k) {
        const int a = (k + 1) % 3;
        t.ax[k] = x_in[a][j], t.ay[k] = y_in[a][j];
        t.ex[k] = ex[k][j], t.ey[k] = ey[k][j], t.bias[k] = uint8_t(bias[k][j]);
      }
      t.set_box(box[0][j], box[1][j], box[2][j], box[3][j]);
      t.q0 = q_in[0][j], t.qx = qx[j], t.qy = qy[j];
      t.fwd.w0 = w_in[0][j], t.fwd.wx = wx[j], t.fwd.wy = wy[j];
      t.fwd.flat[0] = t.fwd.flat[1] = t.fwd.flat[2] = 0;
    }
  }
}

// From IndexedTris: the vertices' fields fetched from their arrays (no copy of
// the triangles first), 16 bytes at a time (LoadPairs): z and the 8-byte word
// of x and y, then w and the stored depth. (Spare lanes: valid indices, not
// written out.)
// IndexedTris' fetch for SetUpForwardT (set_up_forward, set_up_shaded).
struct FetchIndexed {
  const IndexedTris& tris;
  void operator()(size_t i, int32_t (*x)[8], int32_t (*y)[8], double (*w)[8], double (*q)[8]) const {
    const hn::CappedTag<double, 8> dd;
    const hn::Rebind<int32_t, decltype(dd)> di;
    const hn::Rebind<uint32_t, decltype(dd)> du;
    const hn::Rebind<uint64_t, decltype(dd)> d64;
    static_assert(sizeof(ProjectedVertex) == 24 && offsetof(ProjectedVertex, x) == 8 &&
                  offsetof(ProjectedVertex, y) == 12 && sizeof(VertexDepth) == 16 &&
                  offsetof(VertexDepth, q) == 8);
    const double* pvd = reinterpret_cast<const double*>(tris.pv);
    const double* vd = reinterpret_cast<const double*>(tris.vd);
    const uint32_t* const index[3] = {tris.a, tris.b, tris.c};
    for (int k = 0; k < 3; ++k) {
      const uint32_t* const v = index[k] + i;
      hn::Vec<decltype(dd)> z, xyd, wk, qk;
      LoadPairs(dd, [&](int l) { return pvd + 3 * size_t(v[l]); }, z, xyd);
      const auto xy = hn::BitCast(d64, xyd);
      hn::Store(hn::BitCast(di, hn::TruncateTo(du, xy)), di, x[k]);
      hn::Store(hn::BitCast(di, hn::TruncateTo(du, hn::ShiftRight<32>(xy))), di, y[k]);
      LoadPairs(dd, [&](int l) { return vd + 2 * size_t(v[l]); }, wk, qk);
      hn::Store(wk, dd, w[k]);
      hn::Store(qk, dd, q[k]);
    }
  }
};

void SetUpForward(const IndexedTris& tris, size_t n, const SampleGrid& grid, TriSetup* out,
                  bool tested) {
  SetUpForwardT(FetchIndexed{tris}, n, grid, out, tested);
}

// set_up_shaded: set_up_forward's set-ups from IndexedTris, and per triangle
// the shading's four planes (w, then the normal times w under perspective, the
// normal itself under affine interpolation) from the vertex normals, with
// opt::simd's set_up_shading operations (no contraction): the same bits; moved
// to the triangle's tile where it meets one only, with shade_one_tile's.
void SetUpShaded(const IndexedTris& tris, size_t n, const SampleGrid& grid, TriSetup* out,
                 const Vec3* normal, bool negate, bool perspective, const ShadedPlanes& to) {
  const hn::CappedTag<double, 8> dd;
  const hn::Rebind<int32_t, decltype(dd)> di;
  const hn::Rebind<float, decltype(dd)> df;
  using VD = hn::Vec<decltype(dd)>;
  using VI = hn::Vec<decltype(di)>;
  const double* nd = &normal[0].x;
  const uint32_t* const index[3] = {tris.a, tris.b, tris.c};
  const int tw_log2 = to.tw_log2, th_log2 = to.th_log2;
  const size_t N = hn::Lanes(dd);
  HWY_ALIGN double c[4][3][8];
  HWY_ALIGN float local[4][3][8];
  HWY_ALIGN int32_t one_tile[8];
  auto shading = [&](size_t i, size_t m, const VD exd[3], const VD eyd[3], VD inv_area,
                     const double (*w)[8], const int32_t (*x)[8], const int32_t (*y)[8],
                     const int32_t (*box)[8]) {
    // The vertices' values per row: w; the normal (x, y | y, z a 16-byte load each).
    VD a[4][3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t* const v = index[k] + i;
      VD nx, ny, ny2, nz;
      LoadPairs(dd, [&](int l) { return nd + 3 * size_t(v[l]); }, nx, ny);
      LoadPairs(dd, [&](int l) { return nd + 3 * size_t(v[l]) + 1; }, ny2, nz);
      const VD wk = hn::Load(dd, w[k]);
      const VD value[3] = {negate ? hn::Neg(nx) : nx, negate ? hn::Neg(ny) : ny,
                           negate ? hn::Neg(nz) : nz};
      a[0][k] = wk;
      for (int r = 1; r < 4; ++r) a[r][k] = perspective ? hn::Mul(value[r - 1], wk) : value[r - 1];
    }
    // The tile of the box's top-left pixel, whether the box stays in it, and
    // its top-left corner from vertex 0 in 1/256 px (shade_one_tile's cx - x0).
    const VI i0 = hn::Load(di, box[0]), i1 = hn::Load(di, box[1]);
    const VI j0 = hn::Load(di, box[2]), j1 = hn::Load(di, box[3]);
    const VI tx = hn::ShiftRightSame(i0, tw_log2), ty = hn::ShiftRightSame(j0, th_log2);
    const auto one = hn::And(hn::Eq(tx, hn::ShiftRightSame(i1, tw_log2)),
                             hn::Eq(ty, hn::ShiftRightSame(j1, th_log2)));
    hn::Store(hn::VecFromMask(di, one), di, one_tile);
    const VD dx = hn::PromoteTo(dd, hn::Sub(hn::ShiftLeft<8>(hn::ShiftLeftSame(tx, tw_log2)),
                                            hn::Load(di, x[0])));
    const VD dy = hn::PromoteTo(dd, hn::Sub(hn::ShiftLeft<8>(hn::ShiftLeftSame(ty, th_log2)),
                                            hn::Load(di, y[0])));
    static_assert(kSubpixel == 256);
    const VD subpixel = hn::Set(dd, double(kSubpixel));
    for (int r = 0; r < 4; ++r) {
      const VD d1 = hn::Sub(a[r][1], a[r][0]), d2 = hn::Sub(a[r][2], a[r][0]);
      const VD a0 = a[r][0];
      const VD ax = hn::Mul(hn::Add(hn::Mul(d1, exd[1]), hn::Mul(d2, exd[2])), inv_area);
      const VD ay = hn::Mul(hn::Add(hn::Mul(d1, eyd[1]), hn::Mul(d2, eyd[2])), inv_area);
      hn::Store(a0, dd, c[r][0]);
      hn::Store(ax, dd, c[r][1]);
      hn::Store(ay, dd, c[r][2]);
      hn::Store(hn::DemoteTo(df, hn::Add(hn::Add(a0, hn::Mul(ax, dx)), hn::Mul(ay, dy))), df,
                local[r][0]);
      hn::Store(hn::DemoteTo(df, hn::Mul(ax, subpixel)), df, local[r][1]);
      hn::Store(hn::DemoteTo(df, hn::Mul(ay, subpixel)), df, local[r][2]);
    }
    // The set-ups and TilePlanes four vectors ahead, for writing: the stores
    // are what this loop waits on where the arrays are out of the caches (each
    // line is fetched before it is written; the hardware's prefetch starts
    // late). (Not in the flat set-up: there it costs more than it saves.)
    for (size_t j = i + 4 * N; j < std::min(n, i + 5 * N); ++j) {
      __builtin_prefetch(&out[j], 1);
      __builtin_prefetch(reinterpret_cast<const char*>(&out[j]) + 64, 1);
      __builtin_prefetch(&to.local[j], 1);
    }
    // (The moved planes for every triangle -- unread where not in one tile --
    // the double ones for those only: rare, a branch that predicts well.)
    for (size_t j = 0; j < m; ++j) {
      float* const p = &to.local[i + j].p[0][0];
      for (int r = 0; r < 4; ++r)
        for (int k = 0; k < 3; ++k) p[3 * r + k] = local[r][k][j];
      to.ready[i + j] = one_tile[j] != 0;
      if (!one_tile[j]) {
        double* const d = to.planes + (i + j) * 12;
        for (int r = 0; r < 4; ++r)
          for (int k = 0; k < 3; ++k) d[3 * r + k] = c[r][k][j];
      }
    }
  };
  SetUpForwardT(FetchIndexed{tris}, n, grid, out, true, shading);
}

// From TriVertices: loads.
void SetUpForwardArrays(const TriVertices& tris, size_t n, const SampleGrid& grid, TriSetup* out,
                        bool tested) {
  const hn::CappedTag<double, 8> dd;
  const hn::Rebind<int32_t, decltype(dd)> di;
  auto load = [&](size_t i, int32_t (*x)[8], int32_t (*y)[8], double (*w)[8], double (*q)[8]) {
    for (int k = 0; k < 3; ++k) {
      hn::Store(hn::LoadU(di, tris.x[k] + i), di, x[k]);
      hn::Store(hn::LoadU(di, tris.y[k] + i), di, y[k]);
      hn::Store(hn::LoadU(dd, tris.w[k] + i), dd, w[k]);
      hn::Store(hn::LoadU(dd, tris.q[k] + i), dd, q[k]);
    }
  };
  SetUpForwardT(load, n, grid, out, tested);
}

// ---------------------------------------------------------------- sphere_face_codes
size_t SphereFaceCodes(const double* nx, const double* ny, const double* nz, const double* h,
                       size_t n, const double e[3], double r, double sign, double margin,
                       bool mark_sure, uint32_t* cand, FaceVertices* verts) {
  const hn::CappedTag<double, 8> dd;
  const hn::Rebind<uint32_t, decltype(dd)> du;
  using VD = hn::Vec<decltype(dd)>;
  const size_t N = hn::Lanes(dd);
  const VD ex = hn::Set(dd, e[0]), ey = hn::Set(dd, e[1]), ez = hn::Set(dd, e[2]);
  const VD rv = hn::Set(dd, r), sg = hn::Set(dd, sign);
  const VD lo = hn::Set(dd, -margin), hi = hn::Set(dd, margin);
  const uint32_t sure_bit = mark_sure ? kSureFace : 0;
  const auto iota = hn::Iota(du, 0);
  size_t m = 0, t = 0;
  for (; t + N <= n; t += N) {
    const VD sd = hn::Mul(
        sg, hn::Sub(hn::Add(hn::Add(hn::Mul(hn::LoadU(dd, nx + t), ex), hn::Mul(hn::LoadU(dd, ny + t), ey)),
                            hn::Mul(hn::LoadU(dd, nz + t), ez)),
                    hn::Mul(hn::LoadU(dd, h + t), rv)));
    auto idx = hn::Add(iota, hn::Set(du, uint32_t(t)));
    const auto sure = CastMask(du, dd, hn::Gt(sd, hi)), written = CastMask(du, dd, hn::Ge(sd, lo));
    idx = hn::IfThenElse(sure, hn::Or(idx, hn::Set(du, sure_bit)), idx);
    if (verts) {
      for (int k = 0; k < 3; ++k)
        hn::CompressStore(hn::LoadU(du, verts->in[k] + t), written, du, verts->out[k] + m);
      verts->unsure += hn::CountTrue(du, hn::AndNot(sure, written));
    }
    m += hn::CompressStore(idx, written, du, cand + m);
  }
  for (; t < n; ++t) {  // (the same operations, one face)
    const double sd = sign * (nx[t] * e[0] + ny[t] * e[1] + nz[t] * e[2] - r * h[t]);
    cand[m] = uint32_t(t) | (sd > margin ? sure_bit : 0);
    if (verts && sd >= -margin) {
      for (int k = 0; k < 3; ++k) verts->out[k][m] = verts->in[k][t];
      verts->unsure += !(sd > margin);
    }
    m += sd >= -margin;
  }
  return m;
}

// ---------------------------------------------------------------- polygon_run
//
// Vertex k of each of a vector's N triangles, from one field of its 3N
// vertices (in order: v[0] holds vertices 0 .. N-1, v[1] the next N, v[2] the
// last): every third value, from the third starting at k.
template <class D, class V = hn::Vec<D>>
HWY_INLINE void PerTriangle(D d, const V v[3], V out[3]) {
  HWY_ALIGN hn::TFromD<D> buf[3 * hn::MaxLanes(D())];
  const size_t N = hn::Lanes(d);
  for (size_t j = 0; j < 3; ++j) hn::Store(v[j], d, buf + j * N);
  hn::LoadInterleaved3(d, buf, out[0], out[1], out[2]);
}

// The scalar loop's steps (view_scene_chunks) on N polygons at a time: the
// vertices' fields read a vector of vertices at a time (LoadInterleaved over
// their records), then regrouped per triangle (PerTriangle); the kept
// triangles compressed into out.
size_t PolygonRunStep(const PolygonRun& r, const SampleGrid& grid, PolygonRunOut& out) {
  const hn::CappedTag<double, 8> dd;
  const hn::Rebind<int32_t, decltype(dd)> di;
  using VD = hn::Vec<decltype(dd)>;
  using VI = hn::Vec<decltype(di)>;
  const size_t N = hn::Lanes(dd);
  static_assert(sizeof(Vec3) == 24);
  const double* world = &r.world[0].x;
  const ProjectLanes<decltype(dd)> proj(dd, *r.proj, r.depth);
  const VD zero = hn::Zero(dd), one = hn::Set(dd, 1.0), three = hn::Set(dd, 3.0);
  const VD eye[3] = {hn::Set(dd, r.proj->eye[0]), hn::Set(dd, r.proj->eye[1]),
                     hn::Set(dd, r.proj->eye[2])};
  const VI zero_i = hn::Zero(di);
  auto dot3 = [](VD ax, VD ay, VD az, VD bx, VD by, VD bz) {  // as Vec3's dot
    return hn::Add(hn::Add(hn::Mul(ax, bx), hn::Mul(ay, by)), hn::Mul(az, bz));
  };
  size_t i = 0;
  for (; i + N <= r.n; i += N) {
    VD face[4];  // (n.x, n.y, n.z, d)
    hn::LoadInterleaved4(dd, r.plane + 4 * i, face[0], face[1], face[2], face[3]);
    // A zero face normal: passed over, uncounted.
    auto alive =
        hn::Not(hn::Eq(dot3(face[0], face[1], face[2], face[0], face[1], face[2]), zero));
    // The vertices, a vector of them at a time (c[coordinate][j]: vertices
    // j N .. j N + N - 1), projected (project_vertices' operations), then
    // regrouped per triangle (wv[coordinate][vertex k], ...).
    VD c[3][3], ez_v[3], x_v[3], y_v[3], in_v[3];
    for (size_t j = 0; j < 3; ++j) {
      hn::LoadInterleaved3(dd, world + 3 * (3 * i + j * N), c[0][j], c[1][j], c[2][j]);
      const VD w[3] = {c[0][j], c[1][j], c[2][j]};
      hn::Mask<decltype(dd)> inside;
      proj.position(w, ez_v[j], x_v[j], y_v[j], inside);
      in_v[j] = hn::IfThenElseZero(inside, one);
    }
    VD in[3];
    PerTriangle(dd, in_v, in);
    const auto inside = hn::Gt(hn::Min(hn::Min(in[0], in[1]), in[2]), zero);
    // A polygon that may need clipping: the caller's (view_polygons).
    if (!hn::AllTrue(dd, hn::Or(inside, hn::Not(alive)))) break;
    out.scene_tris += hn::CountTrue(dd, alive);
    VD wv[3][3];
    for (int k = 0; k < 3; ++k) PerTriangle(dd, c[k], wv[k]);
    // World-space culling: dot(face, eye - w0) > 0 for a front face.
    if (r.cull_world) {
      const VD facing = dot3(face[0], face[1], face[2], hn::Sub(eye[0], wv[0][0]),
                             hn::Sub(eye[1], wv[1][0]), hn::Sub(eye[2], wv[2][0]));
      const auto culled = hn::AndNot(hn::Gt(facing, zero), alive);
      out.culled += hn::CountTrue(dd, culled);
      alive = hn::AndNot(culled, alive);
    }
    if (hn::AllFalse(dd, alive)) continue;
    // The snapped area, exact in double as in int64: degenerate at 0, culled in
    // projection space when positive (a front face is counter-clockwise as
    // seen, y down), and b and c swapped when negative (the raster's order).
    VD xd[3], yd[3];
    PerTriangle(dd, x_v, xd);
    PerTriangle(dd, y_v, yd);
    VI x[3], y[3];
    for (int k = 0; k < 3; ++k) x[k] = hn::DemoteTo(di, xd[k]), y[k] = hn::DemoteTo(di, yd[k]);
    const VD area = hn::Sub(
        hn::Mul(hn::PromoteTo(dd, hn::Sub(x[1], x[0])), hn::PromoteTo(dd, hn::Sub(y[2], y[0]))),
        hn::Mul(hn::PromoteTo(dd, hn::Sub(y[1], y[0])), hn::PromoteTo(dd, hn::Sub(x[2], x[0]))));
    const auto degenerate = hn::And(hn::Eq(area, zero), alive);
    out.degenerate += hn::CountTrue(dd, degenerate);
    alive = hn::AndNot(degenerate, alive);
    if (r.cull_projection) {
      const auto culled = hn::And(hn::Gt(area, zero), alive);
      out.culled += hn::CountTrue(dd, culled);
      alive = hn::AndNot(culled, alive);
    }
    // No sample of the grid in the box: left out.
    VI i0, i1, j0, j1;
    PixelBox(di, grid, x, y, i0, i1, j0, j1);
    const auto none = CastMask(dd, di, hn::Or(hn::Gt(i0, i1), hn::Gt(j0, j1)));
    const auto kept = hn::AndNot(none, alive);
    if (hn::AllFalse(dd, kept)) continue;
    const auto kept_i = CastMask(di, dd, kept);
    const auto swap = hn::Lt(area, zero);
    const auto swap_i = hn::Gt(hn::DemoteTo(di, hn::IfThenElseZero(swap, one)), zero_i);
    // The kept triangles' vertices in the raster's order, w and the stored depth.
    VD w[3], q[3];
    {
      VD w_v[3], q_v[3];
      for (size_t j = 0; j < 3; ++j) proj.depth(ez_v[j], w_v[j], q_v[j]);
      PerTriangle(dd, w_v, w);
      PerTriangle(dd, q_v, q);
    }
    const size_t at = out.kept;
    for (int k = 0; k < 3; ++k) {
      const int from = k == 0 ? 0 : k == 1 ? 2 : 1;  // where swapped
      hn::CompressStore(hn::IfThenElse(swap_i, x[from], x[k]), kept_i, di, out.x[k] + at);
      hn::CompressStore(hn::IfThenElse(swap_i, y[from], y[k]), kept_i, di, out.y[k] + at);
      hn::CompressStore(hn::IfThenElse(swap, w[from], w[k]), kept, dd, out.w[k] + at);
      hn::CompressStore(hn::IfThenElse(swap, q[from], q[k]), kept, dd, out.q[k] + at);
    }
    // The flat colour's inputs: the centroid ((0 + v0 + v1 + v2) / 3, as the
    // scalar loop sums it) and the face normal.
    for (int k = 0; k < 3; ++k) {
      const VD centroid =
          hn::Div(hn::Add(hn::Add(hn::Add(zero, wv[k][0]), wv[k][1]), wv[k][2]), three);
      hn::CompressStore(centroid, kept, dd, out.centroid[k] + at);
      hn::CompressStore(face[k], kept, dd, out.face[k] + at);
    }
    out.kept += hn::CountTrue(dd, kept);
  }
  return i;
}

}  // namespace HWY_NAMESPACE
}  // namespace lockstep::opt::zsimd
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace lockstep::opt::zsimd {

HWY_EXPORT(RasterTileFloat);
HWY_EXPORT(RasterTileDouble);
HWY_EXPORT(TargetName);
HWY_EXPORT(ShadeTile);
HWY_EXPORT(ProjectVertices);
HWY_EXPORT(FlatColors);
HWY_EXPORT(SphereFaces);

void sphere_faces(const Vec3* world, const std::array<uint32_t, 3>* tri, size_t n, bool flip,
                  const Vec3& eye, double* face, uint8_t* flags) {
  HWY_DYNAMIC_DISPATCH(SphereFaces)(world, tri, n, flip, eye, face, flags);
}

void flat_colors(const ShadeParams& p, size_t n, const double* const* in, const uint32_t* id,
                 const FlatSurface* surface, float* const* out) {
  HWY_DYNAMIC_DISPATCH(FlatColors)(p, n, in, id, surface, out);
}
HWY_EXPORT(GrowBounds);
HWY_EXPORT(BallEntries);

void ball_entries(const double ce[3], double rho2, bool inverted, double z_occ, double pitch,
                  double half_w, double dy, int cell, int a0, int n, double* out) {
  HWY_DYNAMIC_DISPATCH(BallEntries)(ce, rho2, inverted, z_occ, pitch, half_w, dy, cell, a0, n, out);
}
HWY_EXPORT(SetUpForward);
HWY_EXPORT(TriangleStep);

size_t triangle_step(const ProjectedVertex* pv, uint32_t* a, uint32_t* b, uint32_t* c,
                     uint32_t* tag, size_t n, const SampleGrid& grid, bool cull_projection,
                     const OcclusionCells* occ, TriangleCounts& counts) {
  return HWY_DYNAMIC_DISPATCH(TriangleStep)(pv, a, b, c, tag, n, grid, cull_projection, occ, counts);
}

void set_up_forward(const IndexedTris& tris, size_t n, const SampleGrid& grid, TriSetup* out,
                    bool tested) {
  HWY_DYNAMIC_DISPATCH(SetUpForward)(tris, n, grid, out, tested);
}
HWY_EXPORT(SetUpShaded);
void set_up_shaded(const IndexedTris& tris, size_t n, const SampleGrid& grid, TriSetup* out,
                   const Vec3* normal, bool negate, bool perspective, const ShadedPlanes& to) {
  HWY_DYNAMIC_DISPATCH(SetUpShaded)(tris, n, grid, out, normal, negate, perspective, to);
}
HWY_EXPORT(SetUpForwardArrays);
void set_up_forward(const TriVertices& tris, size_t n, const SampleGrid& grid, TriSetup* out,
                    bool tested) {
  HWY_DYNAMIC_DISPATCH(SetUpForwardArrays)(tris, n, grid, out, tested);
}
HWY_EXPORT(SphereFaceCodes);
size_t sphere_face_codes(const double* nx, const double* ny, const double* nz, const double* h,
                         size_t n, const double e[3], double r, double sign, double margin,
                         bool mark_sure, uint32_t* cand, FaceVertices* verts) {
  return HWY_DYNAMIC_DISPATCH(SphereFaceCodes)(nx, ny, nz, h, n, e, r, sign, margin, mark_sure,
                                               cand, verts);
}
HWY_EXPORT(PolygonRunStep);
size_t polygon_run(const PolygonRun& run, const SampleGrid& grid, PolygonRunOut& out) {
  return HWY_DYNAMIC_DISPATCH(PolygonRunStep)(run, grid, out);
}

void grow_bounds(const Vec3* points, size_t n, Vec3& lo, Vec3& hi) {
  HWY_DYNAMIC_DISPATCH(GrowBounds)(points, n, lo, hi);
}

void project_vertices(const Projection& p, const Vec3* world, size_t n, ProjectedVertex* out,
                      const DepthMap* depth, VertexDepth* depth_out) {
  HWY_DYNAMIC_DISPATCH(ProjectVertices)(p, world, n, out, depth, depth_out);
}

void shade_tile(const ShadeParams& p, const int32_t* tri, const TilePlanes* const* where,
                int cols, int rows, float* rgb, float* z, float* image, size_t image_stride,
                float* depth, size_t depth_stride) {
  HWY_DYNAMIC_DISPATCH(ShadeTile)
  (p, tri, where, cols, rows, rgb, z, image, image_stride, depth, depth_stride);
}

void raster_tile(const RasterParams& p, const TileJob& t, float* depth, int32_t* tri,
                 int32_t* count) {
  HWY_DYNAMIC_DISPATCH(RasterTileFloat)(p, t, depth, tri, count);
}
void raster_tile(const RasterParams& p, const TileJob& t, double* depth, int32_t* tri,
                 int32_t* count) {
  HWY_DYNAMIC_DISPATCH(RasterTileDouble)(p, t, depth, tri, count);
}
const char* target_name() { return HWY_DYNAMIC_DISPATCH(TargetName)(); }

}  // namespace lockstep::opt::zsimd

namespace lockstep::opt {
const char* zsimd_target_name() { return zsimd::target_name(); }
}  // namespace lockstep::opt
#endif  // HWY_ONCE
