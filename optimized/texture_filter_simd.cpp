// lockstep optimized: texture filtering with Highway and TBB (optimized/texture_filter_simd.h).
//
// Laid out as Highway's dispatched kernels (hwy/examples/skeleton.cc): the
// structs once, the kernels once per target (this file includes itself
// through foreach_target.h), the entry point once (HWY_ONCE) calling the
// best target the CPU has.
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "core/error.h"
#include "core/large_buffer.h"
#include "core/timer.h"
#include "optimized/mask_bytes.h"
#include "optimized/texture_filter_simd.h"
#include "optimized/tiling.h"

#ifndef LOCKSTEP_TEXTURE_SIMD_SHARED
#define LOCKSTEP_TEXTURE_SIMD_SHARED
namespace lockstep::opt::texture_kernels {

// One level: level 0 is the texture's own texels (not copied), the others own theirs.
struct Level {
  int w = 0, h = 0;
  const float* data = nullptr;  // w * h * 4
  UninitVector<float> own;
};

struct Pyramid {
  std::vector<Level> levels;
  Wrap wrap = Wrap::repeat;
  double w0 = 1, h0 = 1;
  // Per level: its scale against level 0 (n_l / n_0), its size and 1 / size,
  // its texels (tables for the trilinear kernel).
  std::vector<double> sx, sy, w, h, inv_w, inv_h;
  std::vector<const float*> data;
  // Repeat with every side a power of two (the pyramid of a power-of-two
  // texture is one): a texel index wraps by a mask, a row by a shift.
  bool pow2_repeat = false;
  std::vector<int64_t> mask_w, mask_h, log2_w;
  void tables() {
    sx.clear(), sy.clear(), w.clear(), h.clear(), inv_w.clear(), inv_h.clear(), data.clear();
    mask_w.clear(), mask_h.clear(), log2_w.clear();
    auto pow2 = [](int n) { return n > 0 && (n & (n - 1)) == 0; };
    pow2_repeat = wrap == Wrap::repeat;
    for (const Level& l : levels) {
      pow2_repeat = pow2_repeat && pow2(l.w) && pow2(l.h);
      mask_w.push_back(l.w - 1);
      mask_h.push_back(l.h - 1);
      int lw = 0;
      while ((int64_t(1) << lw) < l.w) ++lw;
      log2_w.push_back(lw);
      sx.push_back(l.w / w0);
      sy.push_back(l.h / h0);
      w.push_back(l.w);
      h.push_back(l.h);
      inv_w.push_back(1.0 / l.w);
      inv_h.push_back(1.0 / l.h);
      data.push_back(l.data);
    }
  }
};

inline int64_t wrap_fast(int64_t i, int64_t n, Wrap w) {
  if (uint64_t(i) < uint64_t(n)) return i;
  return wrap_index(i, n, w);
}

// The pixel centres x0 .. x0 + n - 1 of row y (n <= 64): whether each sees
// the quad, its texel point and derivatives (row_coords: the same operations
// in the same order as TexelMap::texel_at and derivatives, so the same
// doubles, for the filters with steps in them) or its texel point and level
// of detail (row_coords_trilinear), a vector of doubles at a time.
struct RowCoords {
  double a[64], b[64], lod[64];
  double dadx[64], dbdx[64], dady[64], dbdy[64];
  uint8_t valid[64];
  int count = 0;  // pixels that see the quad (of the n asked for)
};

// Whether any of the bytes p[0 .. m - 1] (m <= 8) is set.
inline bool any_byte(const uint8_t* p, int m) {
  uint64_t word = 0;
  std::memcpy(&word, p, size_t(std::clamp(m, 0, 8)));
  return word != 0;
}

}  // namespace lockstep::opt::texture_kernels
#endif  // LOCKSTEP_TEXTURE_SIMD_SHARED

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "optimized/texture_filter_simd.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "hwy/contrib/math/math-inl.h"

HWY_BEFORE_NAMESPACE();
namespace lockstep::opt::texture_kernels {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

#if HWY_TARGET == HWY_SCALAR
// A texel is a 4-lane vector: the scalar target (never chosen on x86, whose
// baseline has 128-bit vectors) has none.
void BuildRows(const Level&, Level&, Wrap, int, int) { throw std::runtime_error("texture simd: no 128-bit vectors"); }
void AreaAt(const Pyramid&, const TexelMap&, int, int, float*) {
  throw std::runtime_error("texture simd: no 128-bit vectors");
}
void FilterRows(const Pyramid&, const TexelMap&, const TextureFilterSettings&, const float*, Image&, int, int, int,
                int, uint64_t*) {
  throw std::runtime_error("texture simd: no 128-bit vectors");
}
#else
using D4 = hn::FixedTag<float, 4>;
using V4 = hn::Vec<D4>;

HWY_INLINE V4 fetch(const Level& l, int64_t i, int64_t j, Wrap w) {
  const D4 d;
  return hn::LoadU(d, l.data + (size_t(wrap_fast(j, l.h, w)) * size_t(l.w) + size_t(wrap_fast(i, l.w, w))) * 4);
}

// Rows [y0, y1) of the level below `fine`, by core/texture.h's rule: the
// 2 x 2 average of even sizes in vectors, odd sizes by their overlap weights.
void BuildRows(const Level& fine, Level& coarse, Wrap wrap, int y0, int y1) {
  const D4 d;
  const bool even = fine.w % 2 == 0 && fine.h % 2 == 0 && coarse.w * 2 == fine.w && coarse.h * 2 == fine.h;
  for (int j = y0; j < y1; ++j) {
        float* out = coarse.own.data() + size_t(j) * coarse.w * 4;
        if (even) {
          const float* r0 = fine.data + size_t(2 * j) * fine.w * 4;
          const float* r1 = r0 + size_t(fine.w) * 4;
          const V4 q = hn::Set(d, 0.25f);
          for (int i = 0; i < coarse.w; ++i) {
            const V4 s = hn::Add(hn::Add(hn::LoadU(d, r0 + 8 * i), hn::LoadU(d, r0 + 8 * i + 4)),
                                 hn::Add(hn::LoadU(d, r1 + 8 * i), hn::LoadU(d, r1 + 8 * i + 4)));
            hn::StoreU(hn::Mul(s, q), d, out + 4 * i);
          }
        } else {
          double wy[3];
          const int fy = mip_box_weights(j, fine.h, coarse.h, wy);
          for (int i = 0; i < coarse.w; ++i) {
            double wx[3];
            const int fx = mip_box_weights(i, fine.w, coarse.w, wx);
            V4 s = hn::Zero(d);
            for (int dy = 0; dy < 3; ++dy)
              for (int dx = 0; dx < 3; ++dx)
                if (wx[dx] > 0 && wy[dy] > 0)
                  s = hn::MulAdd(fetch(fine, fx + dx, fy + dy, wrap), hn::Set(d, float(wx[dx] * wy[dy])), s);
            hn::StoreU(s, d, out + 4 * i);
          }
        }
  }
}

HWY_INLINE V4 point(const Pyramid& p, double a, double b) {
  return fetch(p.levels[0], int64_t(std::floor(a)), int64_t(std::floor(b)), p.wrap);
}

HWY_INLINE V4 bilinear(const Pyramid& p, int level, double a, double b) {
  const D4 d;
  const Level& l = p.levels[size_t(level)];
  const double x = a * l.w / p.w0 - 0.5, y = b * l.h / p.h0 - 0.5;
  const double i0 = std::floor(x), j0 = std::floor(y);
  const V4 fx = hn::Set(d, float(x - i0)), fy = hn::Set(d, float(y - j0));
  const int64_t i = int64_t(i0), j = int64_t(j0);
  const V4 t00 = fetch(l, i, j, p.wrap), t10 = fetch(l, i + 1, j, p.wrap);
  const V4 t01 = fetch(l, i, j + 1, p.wrap), t11 = fetch(l, i + 1, j + 1, p.wrap);
  const V4 top = hn::MulAdd(hn::Sub(t10, t00), fx, t00);
  const V4 bottom = hn::MulAdd(hn::Sub(t11, t01), fx, t01);
  return hn::MulAdd(hn::Sub(bottom, top), fy, top);
}

HWY_INLINE double lod_of(double dadx, double dbdx, double dady, double dbdy) {
  return std::log2(std::max(std::hypot(dadx, dbdx), std::hypot(dady, dbdy)));
}

V4 ewa_level(const Pyramid& p, int level, double a, double b, double du0, double dv0, double du1, double dv1) {
  const D4 d;
  const int last = int(p.levels.size()) - 1;
  if (level >= last) return fetch(p.levels[size_t(last)], 0, 0, p.wrap);
  const Level& l = p.levels[size_t(level)];
  const double sx = l.w / p.w0, sy = l.h / p.h0;
  const double s = a * sx - 0.5, tt = b * sy - 0.5;
  du0 *= sx;
  du1 *= sx;
  dv0 *= sy;
  dv1 *= sy;
  double A = dv0 * dv0 + dv1 * dv1 + 1;
  double B = -2 * (du0 * dv0 + du1 * dv1);
  double C = du0 * du0 + du1 * du1 + 1;
  const double inv_f = 1 / (A * C - B * B * 0.25);
  A *= inv_f;
  B *= inv_f;
  C *= inv_f;
  const double det = -B * B + 4 * A * C, inv_det = 1 / det;
  const double u_sqrt = std::sqrt(det * C), v_sqrt = std::sqrt(A * det);
  const int64_t s0 = int64_t(std::ceil(s - 2 * inv_det * u_sqrt)), s1 = int64_t(std::floor(s + 2 * inv_det * u_sqrt));
  const int64_t t0 = int64_t(std::ceil(tt - 2 * inv_det * v_sqrt)), t1 = int64_t(std::floor(tt + 2 * inv_det * v_sqrt));
  const float floor_w = std::exp(-2.0f);
  V4 sum = hn::Zero(d);
  float weights = 0;
  for (int64_t it = t0; it <= t1; ++it) {
    const double v = it - tt;
    for (int64_t is = s0; is <= s1; ++is) {
      const double u = is - s;
      const double r2 = A * u * u + B * u * v + C * v * v;
      if (r2 < 1) {
        const float w = std::exp(-2.0f * float(r2)) - floor_w;
        sum = hn::MulAdd(fetch(l, is, it, p.wrap), hn::Set(d, w), sum);
        weights += w;
      }
    }
  }
  return weights > 0 ? hn::Mul(sum, hn::Set(d, 1.0f / weights)) : bilinear(p, level, a, b);
}

V4 ewa(const Pyramid& p, double max_ecc, double a, double b, double dadx, double dbdx, double dady, double dbdy) {
  const D4 d;
  double du0 = dadx, dv0 = dbdx, du1 = dady, dv1 = dbdy;
  if (du0 * du0 + dv0 * dv0 < du1 * du1 + dv1 * dv1) {
    std::swap(du0, du1);
    std::swap(dv0, dv1);
  }
  const double major = std::hypot(du0, dv0);
  double minor = std::hypot(du1, dv1);
  if (minor * max_ecc < major && minor > 0) {
    const double scale = major / (minor * max_ecc);
    du1 *= scale;
    dv1 *= scale;
    minor *= scale;
  }
  if (minor == 0) return bilinear(p, 0, a, b);
  const double lod = std::max(0.0, std::log2(minor));
  const int lo = int(std::floor(lod));
  const V4 c0 = ewa_level(p, lo, a, b, du0, dv0, du1, dv1), c1 = ewa_level(p, lo + 1, a, b, du0, dv0, du1, dv1);
  return hn::MulAdd(hn::Sub(c1, c0), hn::Set(d, float(lod - lo)), c0);
}

// Area sampling: the footprint polygon (as the reference builds it) cut into
// texel rows; the texels wholly inside a row's span are summed without
// clipping, only the two ends of each row are clipped.
V4 area(const Pyramid& p, const TexelMap& map, int x, int y) {
  const D4 d;
  const Polygon2 fp = map.footprint(x, y);
  V4 sum = hn::Zero(d);
  if (fp.size() < 3) return sum;
  const Level& l = p.levels[0];
  double lo_y = fp[0].y, hi_y = lo_y;
  for (const Point2& q : fp) {
    lo_y = std::min(lo_y, q.y);
    hi_y = std::max(hi_y, q.y);
  }
  double total = 0;
  for (int64_t j = int64_t(std::floor(lo_y)); double(j) < hi_y; ++j) {
    const Polygon2 strip = clip_half_plane(clip_half_plane(fp, 0, 1, -double(j)), 0, -1, double(j + 1));
    if (strip.size() < 3) continue;
    double lo_x = strip[0].x, hi_x = lo_x;
    for (const Point2& q : strip) {
      lo_x = std::min(lo_x, q.x);
      hi_x = std::max(hi_x, q.x);
    }
    // Where the strip's polygon spans the whole texel row height: the x range
    // on both of its horizontal edges (a convex polygon holds the cell
    // [i, i+1] x [j, j+1] when it holds its four corners).
    double in_lo = -1e300, in_hi = 1e300;
    for (double yy : {double(j), double(j + 1)}) {
      double l0 = 1e300, h0 = -1e300;
      for (size_t k = 0, n = strip.size(); k < n; ++k) {
        const Point2& a0 = strip[k];
        const Point2& a1 = strip[(k + 1) % n];
        if ((a0.y - yy) * (a1.y - yy) > 0) continue;
        if (a0.y == a1.y) {
          if (a0.y == yy) {
            l0 = std::min({l0, a0.x, a1.x});
            h0 = std::max({h0, a0.x, a1.x});
          }
          continue;
        }
        const double xx = a0.x + (yy - a0.y) / (a1.y - a0.y) * (a1.x - a0.x);
        l0 = std::min(l0, xx);
        h0 = std::max(h0, xx);
      }
      in_lo = std::max(in_lo, l0);
      in_hi = std::min(in_hi, h0);
    }
    const int64_t full0 = int64_t(std::ceil(in_lo)), full1 = int64_t(std::floor(in_hi));  // cells [full0, full1)
    V4 row = hn::Zero(d);
    double row_area = 0;
    for (int64_t i = int64_t(std::floor(lo_x)); double(i) < hi_x; ++i) {
      if (i >= full0 && i + 1 <= full1) {
        if (i == full0) {
          for (int64_t k = full0; k < full1; ++k) row = hn::Add(row, fetch(l, k, j, p.wrap));
          row_area += double(full1 - full0);
        }
        continue;
      }
      const Polygon2 cell = clip_half_plane(clip_half_plane(strip, 1, 0, -double(i)), -1, 0, double(i + 1));
      const double ar = std::abs(polygon_area(cell));
      if (ar == 0) continue;
      row = hn::MulAdd(fetch(l, i, j, p.wrap), hn::Set(d, float(ar)), row);
      row_area += ar;
    }
    sum = hn::Add(sum, row);
    total += row_area;
  }
  return total > 0 ? hn::Mul(sum, hn::Set(d, float(1 / total))) : sum;
}

// The homogeneous texel point (hx, hy, hz) of the pixel centres x0 + k ..
// x0 + k + L - 1 of row y, a vector of doubles at a time: body(k, hx, hy, hz)
// for k = 0, L, 2L, ... < n (the operations and order of TexelMap::texel_at).
template <class Body>
HWY_INLINE void ForEachPoint(const TexelMap& map, int y, int x0, int n, const Body& body) {
  const hn::ScalableTag<double> dd;
  using VD = hn::Vec<decltype(dd)>;
  const auto& m = map.to_texel.m;
  const double py = y + 0.5;
  const VD m0 = hn::Set(dd, m[0]), m3 = hn::Set(dd, m[3]), m6 = hn::Set(dd, m[6]);
  const VD cx = hn::Set(dd, m[1] * py), cy = hn::Set(dd, m[4] * py), cz = hn::Set(dd, m[7] * py);
  const VD ex = hn::Set(dd, m[2]), ey = hn::Set(dd, m[5]), ez = hn::Set(dd, m[8]);
  const VD half = hn::Set(dd, 0.5);
  for (int k = 0; k < n; k += int(hn::Lanes(dd))) {
    const VD px = hn::Add(hn::Iota(dd, double(x0 + k)), half);
    body(k, hn::Add(hn::Add(hn::Mul(m0, px), cx), ex), hn::Add(hn::Add(hn::Mul(m3, px), cy), ey),
         hn::Add(hn::Add(hn::Mul(m6, px), cz), ez));
  }
}

// Whether texel point (a, b) = (hx, hy) / hz sees the quad (TexelMap::texel_at
// and on_quad): in front of the camera, beyond hither, on the quad; false for NaN.
template <class VD>
HWY_INLINE auto SeesQuad(const TexelMap& map, VD hz, VD inv_hz, VD a, VD b) {
  const hn::DFromV<VD> dd;
  const VD zero = hn::Zero(dd);
  auto ok = hn::And(hn::Gt(hz, zero), hn::Lt(hz, hn::Set(dd, HUGE_VAL)));
  ok = hn::And(ok, hn::Ge(inv_hz, hn::Set(dd, map.hither)));
  ok = hn::And(ok, hn::And(hn::Ge(a, zero), hn::Ge(b, zero)));
  return hn::And(ok, hn::And(hn::Le(a, hn::Set(dd, map.tex_w * map.repeat_u)),
                             hn::Le(b, hn::Set(dd, map.tex_h * map.repeat_v))));
}

// rc.valid[k .. k + L - 1] from a mask (L <= 8 lanes of doubles, k + L <= 64),
// rc.count advanced by the lanes set of the first n - k; whether any lane is set.
template <class D, class M>
HWY_INLINE bool StoreValid(D dd, M ok, int k, int n, RowCoords& rc) {
  uint8_t bits[8] = {};
  hn::StoreMaskBits(dd, ok, bits);
  const int lanes = int(hn::Lanes(dd));
  const uint64_t bytes = bits_to_bytes(bits[0]);
  std::memcpy(rc.valid + k, &bytes, size_t(lanes));
  const unsigned in_segment = n - k >= 8 ? 0xffu : (1u << (n - k)) - 1;
  rc.count += std::popcount(unsigned(bits[0]) & in_segment);
  return bits[0] != 0;
}

void row_coords(const TexelMap& map, int y, int x0, int n, RowCoords& rc) {
  rc.count = 0;
  const hn::ScalableTag<double> dd;
  using VD = hn::Vec<decltype(dd)>;
  const auto& m = map.to_texel.m;
  const VD m0 = hn::Set(dd, m[0]), m3 = hn::Set(dd, m[3]), m6 = hn::Set(dd, m[6]);
  const VD m1 = hn::Set(dd, m[1]), m4 = hn::Set(dd, m[4]), m7 = hn::Set(dd, m[7]);
  const VD one = hn::Set(dd, 1.0);
  ForEachPoint(map, y, x0, n, [&](int k, VD hx, VD hy, VD hz) {
    const VD a = hn::Div(hx, hz), b = hn::Div(hy, hz);
    const auto ok = SeesQuad(map, hz, hn::Div(one, hz), a, b);
    const VD iw2 = hn::Div(one, hn::Mul(hz, hz));
    hn::StoreU(a, dd, rc.a + k);
    hn::StoreU(b, dd, rc.b + k);
    hn::StoreU(hn::Mul(hn::Sub(hn::Mul(m0, hz), hn::Mul(hx, m6)), iw2), dd, rc.dadx + k);
    hn::StoreU(hn::Mul(hn::Sub(hn::Mul(m3, hz), hn::Mul(hy, m6)), iw2), dd, rc.dbdx + k);
    hn::StoreU(hn::Mul(hn::Sub(hn::Mul(m1, hz), hn::Mul(hx, m7)), iw2), dd, rc.dady + k);
    hn::StoreU(hn::Mul(hn::Sub(hn::Mul(m4, hz), hn::Mul(hy, m7)), iw2), dd, rc.dbdy + k);
    StoreValid(dd, ok, k, n, rc);
  });
}

// The same for trilinear alone, which is continuous in the texel point and
// the level of detail (so a last-bit difference from the reference's doubles
// moves its colour by as little): one division a pixel (1 / w, then the
// point and the derivatives by products), the level of detail from a float
// log2 (relative error ~1e-7: a blend weight off by that), and nothing but
// validity for vectors that miss the quad.
void row_coords_trilinear(const TexelMap& map, int y, int x0, int n, RowCoords& rc) {
  rc.count = 0;
  const hn::ScalableTag<double> dd;
  const hn::Rebind<float, decltype(dd)> df;
  using VD = hn::Vec<decltype(dd)>;
  const auto& m = map.to_texel.m;
  const VD m0 = hn::Set(dd, m[0]), m3 = hn::Set(dd, m[3]), m6 = hn::Set(dd, m[6]);
  const VD m1 = hn::Set(dd, m[1]), m4 = hn::Set(dd, m[4]), m7 = hn::Set(dd, m[7]);
  const VD one = hn::Set(dd, 1.0);
  const auto halff = hn::Set(df, 0.5f);
  ForEachPoint(map, y, x0, n, [&](int k, VD hx, VD hy, VD hz) {
    const VD inv = hn::Div(one, hz);
    const VD a = hn::Mul(hx, inv), b = hn::Mul(hy, inv);
    hn::StoreU(a, dd, rc.a + k);
    hn::StoreU(b, dd, rc.b + k);
    if (!StoreValid(dd, SeesQuad(map, hz, inv, a, b), k, n, rc)) {
      hn::StoreU(hn::Zero(dd), dd, rc.lod + k);
      return;
    }
    // d(a, b)/dx = (m0 - a m6, m3 - b m6) / w, d(a, b)/dy = (m1 - a m7, m4 - b m7) / w.
    const VD dadx = hn::Mul(hn::NegMulAdd(a, m6, m0), inv), dbdx = hn::Mul(hn::NegMulAdd(b, m6, m3), inv);
    const VD dady = hn::Mul(hn::NegMulAdd(a, m7, m1), inv), dbdy = hn::Mul(hn::NegMulAdd(b, m7, m4), inv);
    const VD rx = hn::MulAdd(dadx, dadx, hn::Mul(dbdx, dbdx));
    const VD ry = hn::MulAdd(dady, dady, hn::Mul(dbdy, dbdy));
    const auto r = hn::DemoteTo(df, hn::Max(rx, ry));
    hn::StoreU(hn::PromoteTo(dd, hn::Mul(halff, hn::Log2(df, r))), dd, rc.lod + k);
  });
}

// Trilinear for the n pixels of one row segment whose coordinates rc holds:
// the level pair, bilinear positions, weights and wrapped texel indices of
// every pixel in double vectors, then per pixel eight 16-byte texel loads and
// the blends. Positions use the level's scale (n_l / n_0) as one factor, where
// the reference multiplies then divides: a last-bit difference in a position,
// which bilinear interpolation (continuous in it) turns into one of the same
// size in the colour.
void trilinear_segment(const Pyramid& p, const RowCoords& rc, int n, float* out, V4 background) {
  const hn::ScalableTag<double> dd;
  const hn::RebindToSigned<decltype(dd)> di;
  using VD = hn::Vec<decltype(dd)>;
  using VI = hn::Vec<decltype(di)>;
  const int L = int(hn::Lanes(dd));
  const int last = int(p.levels.size()) - 1;
  const hn::Rebind<float, decltype(dd)> df;
  alignas(64) double lev_d[64];
  alignas(64) float t[64], fx[2][64], fy[2][64];
  // The four texels of each pixel and slot, as addresses.
  alignas(64) int64_t idx[2][4][64];
  // Whether any pixel of each vector sees the quad (the others are skipped).
  bool any[64 / 2 + 1], blend[64 / 2 + 1];  // blend: some pixel of the vector uses the second level
  for (int k = 0, v = 0; k < n; k += L, ++v) {
    any[v] = any_byte(rc.valid + k, std::min(n - k, L));
  }
  // The level pair of each pixel, in vectors: lambda <= 0 (or NaN) the finest
  // level alone, lambda >= last the coarsest alone, else floor(lambda) and the
  // next, blended by the fraction (the reference's comparisons exactly).
  {
    const VD zero = hn::Zero(dd), vlast = hn::Set(dd, double(last));
    for (int k = 0, v = 0; k < n; k += L, ++v) {
      const VD lod = hn::LoadU(dd, rc.lod + k);
      const auto low = hn::Not(hn::Gt(lod, zero));  // also NaN
      const auto high = hn::Ge(lod, vlast);
      const VD lo = hn::IfThenElse(low, zero, hn::IfThenElse(high, vlast, hn::Floor(lod)));
      const VD tt = hn::IfThenZeroElse(hn::Or(low, high), hn::Sub(lod, lo));
      hn::Store(lo, dd, lev_d + k);
      hn::Store(hn::DemoteTo(df, tt), df, t + k);
      blend[v] = !hn::AllFalse(dd, hn::Gt(tt, zero));
    }
  }
  const VD half = hn::Set(dd, 0.5), one = hn::Set(dd, 1.0), zero = hn::Zero(dd);
  // The texel indices i and i + 1 on a side of `size` texels, wrapped. Repeat:
  // i - size floor(i / size) with the quotient by the reciprocal (its
  // rounding can leave the result one period out: put back), i + 1 the next
  // one round the period.
  auto wrap_pair = [&](VD i, VD size, VD inv, VD& a, VD& b) {
    switch (p.wrap) {
      case Wrap::repeat: {
        VD r = hn::Sub(i, hn::Mul(size, hn::Floor(hn::Mul(i, inv))));
        r = hn::IfThenElse(hn::Lt(r, zero), hn::Add(r, size), r);
        r = hn::IfThenElse(hn::Ge(r, size), hn::Sub(r, size), r);
        a = r;
        const VD r1 = hn::Add(r, one);
        b = hn::IfThenElse(hn::Ge(r1, size), hn::Sub(r1, size), r1);
        return;
      }
      case Wrap::clamp:
        a = hn::Min(hn::Max(i, zero), hn::Sub(size, one));
        b = hn::Min(hn::Max(hn::Add(i, one), zero), hn::Sub(size, one));
        return;
      case Wrap::mirror: {
        const VD period = hn::Add(size, size);
        auto m = [&](VD x) {
          VD r = hn::Sub(x, hn::Mul(period, hn::Floor(hn::Mul(x, hn::Mul(inv, half)))));
          r = hn::IfThenElse(hn::Lt(r, zero), hn::Add(r, period), r);
          r = hn::IfThenElse(hn::Ge(r, period), hn::Sub(r, period), r);
          return hn::IfThenElse(hn::Lt(r, size), r, hn::Sub(hn::Sub(period, one), r));
        };
        a = m(i);
        b = m(hn::Add(i, one));
        return;
      }
    }
    a = b = i;
  };
  static_assert(sizeof(const float*) == sizeof(int64_t), "addresses as 64-bit lanes");
  const auto* level_address = reinterpret_cast<const int64_t*>(p.data.data());
  for (int k = 0, v = 0; k < n; k += L, ++v) {
    if (!any[v]) continue;
    const VD a = hn::LoadU(dd, rc.a + k), b = hn::LoadU(dd, rc.b + k);
    const VD lo = hn::Load(dd, lev_d + k);
    for (int s = 0; s < (blend[v] ? 2 : 1); ++s) {
      // This slot's level per lane, and its tables: one broadcast when every
      // lane has the same level (neighbouring pixels nearly always do), else
      // gathered.
      const VD lvl = s == 0 ? lo : hn::Min(hn::Add(lo, one), hn::Set(dd, double(last)));
      const double first = lev_d[k] + (s == 0 ? 0 : (lev_d[k] < last ? 1 : 0));
      VD sxv, syv, w, h, iwv, ihv;
      VI base, mw, mh, lw;
      if (hn::AllTrue(dd, hn::Eq(lvl, hn::Set(dd, first)))) {
        const size_t l = size_t(first);
        sxv = hn::Set(dd, p.sx[l]), syv = hn::Set(dd, p.sy[l]), w = hn::Set(dd, p.w[l]), h = hn::Set(dd, p.h[l]);
        iwv = hn::Set(dd, p.inv_w[l]), ihv = hn::Set(dd, p.inv_h[l]);
        base = hn::Set(di, level_address[l]);
        mw = hn::Set(di, p.mask_w[l]), mh = hn::Set(di, p.mask_h[l]), lw = hn::Set(di, p.log2_w[l]);
      } else {
        const auto li = hn::ConvertTo(di, lvl);
        sxv = hn::GatherIndex(dd, p.sx.data(), li), syv = hn::GatherIndex(dd, p.sy.data(), li);
        w = hn::GatherIndex(dd, p.w.data(), li), h = hn::GatherIndex(dd, p.h.data(), li);
        iwv = hn::GatherIndex(dd, p.inv_w.data(), li), ihv = hn::GatherIndex(dd, p.inv_h.data(), li);
        base = hn::GatherIndex(di, level_address, li);
        mw = hn::GatherIndex(di, p.mask_w.data(), li), mh = hn::GatherIndex(di, p.mask_h.data(), li);
        lw = hn::GatherIndex(di, p.log2_w.data(), li);
      }
      const VD x = hn::Sub(hn::Mul(a, sxv), half);
      const VD y = hn::Sub(hn::Mul(b, syv), half);
      const VD i0 = hn::Floor(x), j0 = hn::Floor(y);
      hn::Store(hn::DemoteTo(df, hn::Sub(x, i0)), df, fx[s] + k);
      hn::Store(hn::DemoteTo(df, hn::Sub(y, j0)), df, fy[s] + k);
      if (p.pow2_repeat) {
        // Two's complement: i & (n - 1) is i mod n for negative i too.
        const VI i = hn::ConvertTo(di, i0), j = hn::ConvertTo(di, j0), one_i = hn::Set(di, 1);
        const VI ia = hn::And(i, mw), ib = hn::And(hn::Add(i, one_i), mw);
        const VI ja = hn::Shl(hn::And(j, mh), lw), jb = hn::Shl(hn::And(hn::Add(j, one_i), mh), lw);
        auto address = [&](VI index) { return hn::Add(base, hn::ShiftLeft<4>(index)); };
        hn::Store(address(hn::Add(ja, ia)), di, idx[s][0] + k);
        hn::Store(address(hn::Add(ja, ib)), di, idx[s][1] + k);
        hn::Store(address(hn::Add(jb, ia)), di, idx[s][2] + k);
        hn::Store(address(hn::Add(jb, ib)), di, idx[s][3] + k);
        continue;
      }
      VD ia, ib, ja, jb;
      wrap_pair(i0, w, iwv, ia, ib);
      wrap_pair(j0, h, ihv, ja, jb);
      ja = hn::Mul(ja, w);
      jb = hn::Mul(jb, w);
      // Byte addresses: the level's texels + 16 bytes a texel.
      auto address = [&](VD index) { return hn::Add(base, hn::ShiftLeft<4>(hn::ConvertTo(di, index))); };
      hn::Store(address(hn::Add(ja, ia)), di, idx[s][0] + k);
      hn::Store(address(hn::Add(ja, ib)), di, idx[s][1] + k);
      hn::Store(address(hn::Add(jb, ia)), di, idx[s][2] + k);
      hn::Store(address(hn::Add(jb, ib)), di, idx[s][3] + k);
    }
  }
  const D4 d;
  auto texel = [&](int s, int corner, int k) {
    return hn::LoadU(d, reinterpret_cast<const float*>(idx[s][corner][k]));
  };
  auto bilerp = [&](int s, int k) {
    const V4 t00 = texel(s, 0, k), t10 = texel(s, 1, k), t01 = texel(s, 2, k), t11 = texel(s, 3, k);
    const V4 wx = hn::Set(d, fx[s][k]), wy = hn::Set(d, fy[s][k]);
    const V4 top = hn::MulAdd(hn::Sub(t10, t00), wx, t00);
    const V4 bottom = hn::MulAdd(hn::Sub(t11, t01), wx, t01);
    return hn::MulAdd(hn::Sub(bottom, top), wy, top);
  };
  for (int k = 0; k < n; ++k) {
    V4 c = background;
    if (rc.valid[k]) {
      c = bilerp(0, k);
      if (t[k] > 0) c = hn::MulAdd(hn::Sub(bilerp(1, k), c), hn::Set(d, t[k]), c);
    }
    hn::StoreU(c, d, out + 4 * size_t(k));
  }
}


// Anisotropic filtering for the n pixels of one row segment: each pixel's
// probes (the reference's count, axis and level) gathered into batches of 64
// and filtered by the trilinear kernel, then averaged per pixel. The probe
// count ceil(pmax / pmin) and the axis (the longer derivative) are steps: the
// lengths come from sqrt(x^2 + y^2), and where that could put the ratio or
// the comparison on the other side of a step from the reference's hypot
// (within 1e-9 of it), from hypot itself.
void aniso_segment(const Pyramid& p, const RowCoords& rc, int n, int max_probes, float* out, V4 background) {
  const D4 d;
  RowCoords probes;
  alignas(16) float colours[64 * 4];
  int owner[64];
  V4 sum[64];
  int count[64];
  int m = 0;
  auto flush = [&] {
    if (m == 0) return;
    trilinear_segment(p, probes, m, colours, background);
    for (int j = 0; j < m; ++j) sum[owner[j]] = hn::Add(sum[owner[j]], hn::Load(d, colours + 4 * j));
    m = 0;
  };
  for (int k = 0; k < n; ++k) {
    sum[k] = hn::Zero(d);
    count[k] = 0;
    if (!rc.valid[k]) continue;
    const double dadx = rc.dadx[k], dbdx = rc.dbdx[k], dady = rc.dady[k], dbdy = rc.dbdy[k];
    double px = std::sqrt(dadx * dadx + dbdx * dbdx), py = std::sqrt(dady * dady + dbdy * dbdy);
    double pmax = std::max(px, py), pmin = std::min(px, py);
    const double r = pmin > 0 ? pmax / pmin : 0;
    if (!(std::abs(px - py) > 1e-9 * pmax) || !(std::abs(r - std::round(r)) > 1e-9 * r) || !std::isfinite(r)) {
      px = std::hypot(dadx, dbdx);
      py = std::hypot(dady, dbdy);
      pmax = std::max(px, py);
      pmin = std::min(px, py);
    }
    int np = pmin > 0 ? int(std::ceil(pmax / pmin)) : max_probes;
    np = std::clamp(np, 1, max_probes);
    const double lod = std::log2(pmax / np);
    const double ax = px >= py ? dadx : dady, ay = px >= py ? dbdx : dbdy;
    count[k] = np;
    for (int j = 0; j < np; ++j) {
      if (m == 64) flush();
      const double s = (j + 0.5) / np - 0.5;
      probes.a[m] = rc.a[k] + s * ax;
      probes.b[m] = rc.b[k] + s * ay;
      probes.lod[m] = lod;
      probes.valid[m] = 1;
      owner[m] = k;
      ++m;
    }
  }
  flush();
  for (int k = 0; k < n; ++k)
    hn::StoreU(count[k] ? hn::Mul(sum[k], hn::Set(d, 1.0f / float(count[k]))) : background, d, out + 4 * size_t(k));
}

// Area sampling at pixel (x, y) whose centre sees the quad (AreaSampler).
void AreaAt(const Pyramid& pyr, const TexelMap& map, int x, int y, float* out) {
  hn::StoreU(area(pyr, map, x, y), D4(), out);
}

void FilterRows(const Pyramid& pyr, const TexelMap& map, const TextureFilterSettings& f, const float* bg, Image& img,
                int x0, int y0, int x1, int y1, uint64_t* count) {
  const D4 d;
  const V4 background = hn::LoadU(d, bg);
    uint64_t n = 0;
  RowCoords rc;
  for (int y = y0; y < y1; ++y) {
    if (f.filter == TextureFilter::trilinear) {
      row_coords_trilinear(map, y, x0, x1 - x0, rc);
      trilinear_segment(pyr, rc, x1 - x0, img.pixel(x0, y), background);
      n += uint64_t(rc.count);
      continue;
    }
    row_coords(map, y, x0, x1 - x0, rc);
    if (f.filter == TextureFilter::aniso) {
      aniso_segment(pyr, rc, x1 - x0, f.n, img.pixel(x0, y), background);
      n += uint64_t(rc.count);
      continue;
    }
    for (int x = x0; x < x1; ++x) {
      const int k = x - x0;
      V4 c = background;
      if (rc.valid[k]) {
        ++n;
        const double a = rc.a[k], b = rc.b[k];
        const double dadx = rc.dadx[k], dbdx = rc.dbdx[k], dady = rc.dady[k], dbdy = rc.dbdy[k];
        switch (f.filter) {
          case TextureFilter::point:
            c = point(pyr, a, b);
            break;
          case TextureFilter::bilinear:
            c = bilinear(pyr, 0, a, b);
            break;
          case TextureFilter::area:
            c = area(pyr, map, x, y);
            break;
          case TextureFilter::super: {
            V4 s = hn::Zero(d);
            for (int sy = 0; sy < f.n; ++sy)
              for (int sx = 0; sx < f.n; ++sx) {
                double sa, sb;
                const bool hit =
                    map.texel_at(x + (sx + 0.5) / f.n, y + (sy + 0.5) / f.n, sa, sb) && map.on_quad(sa, sb);
                s = hn::Add(s, hit ? point(pyr, sa, sb) : background);
              }
            c = hn::Mul(s, hn::Set(d, 1.0f / float(f.n * f.n)));
            break;
          }
          case TextureFilter::mip_nearest: {
            // The reference's rounding exactly (a level is a step: no ulp may move it).
            const double lod = lod_of(dadx, dbdx, dady, dbdy);
            int level = lod <= 0.5 ? 0 : int(std::ceil(lod + 0.5)) - 1;
            level = std::min(level, int(pyr.levels.size()) - 1);
            c = bilinear(pyr, level, a, b);
            break;
          }
          case TextureFilter::trilinear:  // by the row kernels above
          case TextureFilter::aniso:
            break;
          case TextureFilter::ewa:
            c = ewa(pyr, f.n, a, b, dadx, dbdx, dady, dbdy);
            break;
        }
      }
      hn::StoreU(c, d, img.pixel(x, y));
    }
  }
  *count = n;
}
#endif  // HWY_TARGET == HWY_SCALAR

}  // namespace HWY_NAMESPACE
}  // namespace lockstep::opt::texture_kernels
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace lockstep::opt::texture_kernels {
HWY_EXPORT(BuildRows);
HWY_EXPORT(FilterRows);
HWY_EXPORT(AreaAt);
}  // namespace lockstep::opt::texture_kernels

namespace lockstep::opt::simd {

namespace {

using namespace texture_kernels;

// The pyramid by core/texture.h's rule, a level's rows in parallel; the 2 x 2
// average of even sizes in vectors, odd sizes by their overlap weights.
Pyramid build_pyramid(const Texture& t, bool whole, int threads) {
  Pyramid p;
  p.wrap = t.wrap;
  p.w0 = t.width;
  p.h0 = t.height;
  Level base;
  base.w = t.width;
  base.h = t.height;
  base.data = t.rgba.data();
  p.levels.push_back(std::move(base));
  if (!whole) {
    p.tables();
    return p;
  }
  while (p.levels.back().w > 1 || p.levels.back().h > 1) {
    const Level& fine = p.levels.back();
    Level coarse;
    coarse.w = mip_next_size(fine.w);
    coarse.h = mip_next_size(fine.h);
    coarse.own.resize(size_t(coarse.w) * coarse.h * 4);
    coarse.data = coarse.own.data();
    const Level& fine_ref = fine;
    parallel_tiles(coarse.w, coarse.h, coarse.w, 16, threads, {}, [&](int, int y0, int, int y1) {
      HWY_DYNAMIC_DISPATCH(BuildRows)(fine_ref, coarse, p.wrap, y0, y1);
    });
    p.levels.push_back(std::move(coarse));
  }
  p.tables();
  return p;
}

}  // namespace

Image texture_filter(const TextureScene& scene, const FrameOptions& opts, FrameStats* stats) {
  const TextureFilterSettings f = texture_filter_settings(opts.params, scene.source);
  const Texture& tex = scene.texture;
  if (tex.width < 1 || tex.height < 1) throw InputError(scene.source, 0, "empty texture");
  const TexelMap map = TexelMap::make(scene, opts.width, opts.height);
  // A filter per tile, when the settings name one (error=E): parallel_tiles'
  // tiles below are the plan's.
  const TextureFilterPlan plan = texture_filter_plan(opts.params, opts.width, opts.height, scene.source);
  const bool mip = plan.tiles.empty() ? uses_pyramid(f.filter) : plan.uses(uses_pyramid);
  // The pyramid, timed apart (a one-shot cost: an application builds it once per texture).
  const Stopwatch build_watch;
  const Pyramid pyr = build_pyramid(tex, mip, opts.threads);
  const double build_seconds = build_watch.seconds();
  const float bg[4] = {float(scene.background.x), float(scene.background.y), float(scene.background.z), 1};
  Image img = Image::uninitialized(opts.width, opts.height);
  std::atomic<uint64_t> lookups{0};
  parallel_tiles(opts.width, opts.height, kFilterTileW, kFilterTileH, opts.threads, opts.progress,
                 [&](int x0, int y0, int x1, int y1) {
    uint64_t n = 0;
    HWY_DYNAMIC_DISPATCH(FilterRows)(pyr, map, plan.tiles.empty() ? f : plan.at(x0, y0), bg, img, x0, y0, x1, y1, &n);
    lookups += n;
  });
  if (stats) {
    stats->items = lookups.load();
    stats->build_seconds = build_seconds;
  }
  return img;
}

struct AreaSampler::Impl {
  Pyramid pyr;
  TexelMap map;
  std::array<float, 4> background;
};

AreaSampler::AreaSampler(const TextureScene& scene, int width, int height)
    : impl_(new Impl{build_pyramid(scene.texture, false, 1), TexelMap::make(scene, width, height),
                     {float(scene.background.x), float(scene.background.y), float(scene.background.z), 1}}) {}

AreaSampler::~AreaSampler() = default;

std::array<float, 4> AreaSampler::at(int x, int y) const {
  double a, b;
  if (!impl_->map.texel_at(x + 0.5, y + 0.5, a, b) || !impl_->map.on_quad(a, b)) return impl_->background;
  std::array<float, 4> out;
  HWY_DYNAMIC_DISPATCH(AreaAt)(impl_->pyr, impl_->map, x, y, out.data());
  return out;
}

}  // namespace lockstep::opt::simd
#endif  // HWY_ONCE
