// Z-buffer raster kernels, Highway SIMD: one tile at a time, 16 samples per
// vector (8 on AVX2). The shading kernels are zbuffer_shade_kernels.cpp, the
// set-up's zbuffer_setup_kernels.cpp; the declarations zbuffer_simd_kernels.h.
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
#include "optimized/zbuffer/zbuffer_simd_kernels.h"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cmath>
#include <cstdlib>

// foreach_target.h first: it re-includes this file once per target.
// clang-format off
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "optimized/zbuffer/zbuffer_raster_kernels.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "optimized/zbuffer/zbuffer_simd_kernels-inl.h"
// clang-format on

HWY_BEFORE_NAMESPACE();
namespace lockstep::opt::zsimd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

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

}  // namespace HWY_NAMESPACE
}  // namespace lockstep::opt::zsimd
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace lockstep::opt::zsimd {

HWY_EXPORT(RasterTileFloat);
HWY_EXPORT(RasterTileDouble);
HWY_EXPORT(TargetName);

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
