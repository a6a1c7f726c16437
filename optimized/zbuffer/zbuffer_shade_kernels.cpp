// Z-buffer shading kernels, Highway SIMD (declared in zbuffer_simd_kernels.h):
//   shade_tile()   a tile's visible samples' colours, every Shading mode, in
//                  float structure-of-arrays lanes, box-filtered into the image;
//   flat_colors()  the set-up's flat colours, with the same lighting.
// The lighting is core/shading.h's (Phong's model with the NFF light
// extension), in float lanes, double ones where a high shine needs them.
#include "optimized/zbuffer/zbuffer_simd_kernels.h"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cmath>
#include <cstdlib>

#include "core/shading.h"

// foreach_target.h first: it re-includes this file once per target.
// clang-format off
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "optimized/zbuffer/zbuffer_shade_kernels.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/contrib/math/math-inl.h"
#include "hwy/highway.h"
#include "optimized/zbuffer/zbuffer_simd_kernels-inl.h"
// clang-format on

HWY_BEFORE_NAMESPACE();
namespace lockstep::opt::zsimd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

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
HWY_INLINE void FlatLit(D d, const ShadeParams& p, const V pos_in[3], const V nrm[3],
                        const V kd[3], V ks, V shine, V col[3]) {
  const V zero = hn::Zero(d), one = hn::Set(d, hn::TFromD<D>(1));
  auto dot3 = [](const V a[3], const V b[3]) {
    return hn::MulAdd(a[0], b[0], hn::MulAdd(a[1], b[1], hn::Mul(a[2], b[2])));
  };
  V view[3];
  for (int c = 0; c < 3; ++c) view[c] = hn::Sub(hn::Set(d, hn::TFromD<D>(p.eye[c])), pos_in[c]);
  const V inv = hn::Div(one, hn::Sqrt(dot3(view, view)));
  for (int c = 0; c < 3; ++c) view[c] = hn::Mul(view[c], inv);
  // (nrm: turned towards the eye already, in double: FlatColors.)
  Lighting(d, p.light, p.nlights, Shading::kPhong, 1.0f, 1.0f, pos_in, nrm, view, kd, ks, shine,
           hn::Eq(zero, zero), col);
}

// view_scene's lit() turns the face normal n towards the eye e before lighting
// at p: n is negated when dot(n, normalize(e - p)) < 0, in double. FlatColors
// takes that decision on its double inputs, before FlatLit rounds them to
// float: in float, a face seen nearly edge-on (the eye within float rounding,
// relatively, of its plane) could be turned the other way than by the reference, and lit
// from the other side (CullingAgree.zbuffer__simd, deep mode;
// corpus/counterexamples/culling_agree.edge_on_or_soup.zbuffer.simd-1.txt).
//
// FacingSure, per lane, with d = e - p (the reference's very operation) and
// the products a_k = n_k d_k: S = (a_0 + a_1) + a_2 and C = |a_0| + |a_1| +
// |a_2|. Where |S| > 2^-44 C (and |d|'s largest component M lies in
// (2^-400, 2^500), with C > 2^-600 M: no overflow, and the underflow of any
// product or quotient is far below the margin), the sign of S is the sign of
// the exact n.d (S is within 3.01u C of it, u = 2^-53) and of the reference's
// rounded dot(n, d / |d|) (within about 8u C / |d| of n.d / |d|): the margin
// 2^-44 = 512u is some 50 times what the two need. There the face is turned
// where S < 0 (away). Elsewhere -- (nearly) edge-on faces, inputs out of those
// ranges or not finite -- the mask is false, and the caller takes the
// reference's expression itself (FacingByReference).
template <class D, class V = hn::Vec<D>>
HWY_INLINE hn::Mask<D> FacingSure(D d, const double eye[3], const V pos[3], const V nrm[3],
                                  hn::Mask<D>& away) {
  const V to[3] = {hn::Sub(hn::Set(d, eye[0]), pos[0]), hn::Sub(hn::Set(d, eye[1]), pos[1]),
                   hn::Sub(hn::Set(d, eye[2]), pos[2])};
  const V a[3] = {hn::Mul(nrm[0], to[0]), hn::Mul(nrm[1], to[1]), hn::Mul(nrm[2], to[2])};
  const V s = hn::Add(hn::Add(a[0], a[1]), a[2]);
  const V c = hn::Add(hn::Add(hn::Abs(a[0]), hn::Abs(a[1])), hn::Abs(a[2]));
  const V m = hn::Max(hn::Max(hn::Abs(to[0]), hn::Abs(to[1])), hn::Abs(to[2]));
  away = hn::Lt(s, hn::Zero(d));
  return hn::And(hn::And(hn::Gt(hn::Abs(s), hn::Mul(c, hn::Set(d, 0x1p-44))),
                         hn::Gt(c, hn::Mul(m, hn::Set(d, 0x1p-600)))),
                 hn::And(hn::Gt(m, hn::Set(d, 0x1p-400)), hn::Lt(m, hn::Set(d, 0x1p500))));
}

// The reference's decision for requests at .. at + m - 1 (core/viewing.cpp's
// lit(), operation for operation): flip[l] = 1 where it turns the normal, else
// 0 (also past m). For a vector holding a lane FacingSure leaves undecided;
// out of line: this rare path, inlined, made every FlatColors call ~10% slower.
HWY_NOINLINE void FacingByReference(const double eye[3], const double* const* in, size_t at,
                                    size_t m, size_t lanes, double* flip) {
  const Vec3 e{eye[0], eye[1], eye[2]};
  for (size_t l = 0; l < lanes; ++l) {
    flip[l] = 0;
    if (l >= m) continue;
    const size_t j = at + l;
    const Vec3 p{in[0][j], in[1][j], in[2][j]}, n{in[3][j], in[4][j], in[5][j]};
    if (dot(n, normalize(e - p)) < 0) flip[l] = 1;
  }
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
    // The faces turned towards the eye, as view_scene's lit() turns them.
    {
      hn::Mask<decltype(dd)> away_lo, away_hi;
      const auto sure_lo = FacingSure(dd, p.flat_eye, lo, lo + 3, away_lo);
      const auto sure_hi = FacingSure(dd, p.flat_eye, hi, hi + 3, away_hi);
      if (!hn::AllTrue(dd, hn::And(sure_lo, sure_hi))) [[unlikely]] {
        HWY_ALIGN double flip[hn::MaxLanes(df)];
        FacingByReference(p.flat_eye, in, i, std::min(N, n - i), N, flip);
        away_lo = hn::Gt(hn::Load(dd, flip), hn::Zero(dd));
        away_hi = hn::Gt(hn::Load(dd, flip + H), hn::Zero(dd));
      }
      for (int k = 3; k < 6; ++k) {
        lo[k] = hn::IfThenElse(away_lo, hn::Neg(lo[k]), lo[k]);
        hi[k] = hn::IfThenElse(away_hi, hn::Neg(hi[k]), hi[k]);
      }
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

}  // namespace HWY_NAMESPACE
}  // namespace lockstep::opt::zsimd
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace lockstep::opt::zsimd {

HWY_EXPORT(ShadeTile);
HWY_EXPORT(FlatColors);

void shade_tile(const ShadeParams& p, const int32_t* tri, const TilePlanes* const* where,
                int cols, int rows, float* rgb, float* z, float* image, size_t image_stride,
                float* depth, size_t depth_stride) {
  HWY_DYNAMIC_DISPATCH(ShadeTile)
  (p, tri, where, cols, rows, rgb, z, image, image_stride, depth, depth_stride);
}

void flat_colors(const ShadeParams& p, size_t n, const double* const* in, const uint32_t* id,
                 const FlatSurface* surface, float* const* out) {
  HWY_DYNAMIC_DISPATCH(FlatColors)(p, n, in, id, surface, out);
}

}  // namespace lockstep::opt::zsimd
#endif  // HWY_ONCE
