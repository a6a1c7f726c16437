// Alpha compositing, optimized with Highway SIMD and TBB.
//
// Premultiplied over, C = Cf + (1 - af) Cb on all four channels, on interleaved
// RGBA: a vector holds whole pixels (4 floats per 128-bit block) and each
// pixel's alpha is broadcast within its block. Highway compiles the kernels for
// each target (AVX2, AVX-512, ...) and dispatches to the best the CPU has, as in
// ray_cast_simd_kernels.cpp.
//
// Memory traffic is the cost, so every image is streamed through memory once:
// the frame is cut into bands of rows (TBB, optimized/tiling.h), a band into
// chunks of kChunk pixels, and a chunk goes through ALL layers before the next
// one starts. The accumulator of a chunk (16 KB in float) stays in L1; each
// layer's pixels are read exactly once; the output is written once, with
// non-temporal (streaming) stores, by the pass of the last layer. Two layers
// are one fused pass: out = L0 over L1.
//
// Front to back, with stack.early_stop, a chunk is split into blocks of kBlock
// pixels: once every pixel of a block has alpha exactly 1, no further layer is
// read for that block (their contribution (1 - 1) Cb is exactly 0, so the result
// is the same as without stopping), and a chunk whose blocks are all done stops.
//
// Float: the same operations in the same order as the reference's premultiplied
// path (1 - af, times Cb, plus Cf; no FMA: -ffp-contract=off and Highway's Mul
// then Add), so premultiplied stacks are bit-identical to the reference.
// Straight layers are premultiplied on the fly (c * a), where the reference
// uses the straight formula instead: a few ulps apart.
//
// 8 bits: computed in 16-bit lanes with the exact rounding of ref::mul255,
// t = x a + 128, (t + (t >> 8)) >> 8, and a saturating add; straight layers are
// premultiplied with the same mul255 first; the result q is written as q / 255
// (a true division, as the reference does). Bit-identical to the reference.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/error.h"
#include "optimized/composite_simd.h"
#include "optimized/tiling.h"

#ifndef LOCKSTEP_COMPOSITE_SIMD_SHARED
#define LOCKSTEP_COMPOSITE_SIMD_SHARED
namespace lockstep::opt::composite_kernels {

// Pixels per chunk (the accumulator: 16 KB of float RGBA, 4 KB of 8-bit) and
// per early-termination block (1 KB of float RGBA).
inline constexpr size_t kChunk = 1024;
inline constexpr size_t kBlock = 64;

// The stack, flattened: layers in the order they are composited (seq[0] first:
// the front for front-to-back, the back for back-to-front).
struct Plan {
  std::vector<const float*> f;    // float RGBA per layer (Storage::f32)
  std::vector<const uint8_t*> q;  // 8-bit RGBA per layer (Storage::unorm8)
  std::vector<uint8_t> straight;  // 1: the layer is straight alpha
  bool ftb = true;                // the accumulator is in front of the next layer
  bool early_stop = false;        // front-to-back with stack.early_stop
};

// ---- scalar pixels, for vector tails and the scalar target. The same
// arithmetic, in the same order, as reference/composite.cpp.
inline void prem_px(const float* s, int straight, float* d) {
  if (straight) {
    d[0] = s[0] * s[3], d[1] = s[1] * s[3], d[2] = s[2] * s[3], d[3] = s[3];
  } else {
    d[0] = s[0], d[1] = s[1], d[2] = s[2], d[3] = s[3];
  }
}
inline bool over_px(const float* f, int fs, const float* b, int bs, float* o) {
  float F[4], B[4];
  prem_px(f, fs, F);
  prem_px(b, bs, B);
  const float t = 1.0f - F[3];
  for (int c = 0; c < 4; ++c) o[c] = F[c] + t * B[c];
  return o[3] == 1.0f;
}
inline bool copy_px(const float* s, int straight, float* o) {
  prem_px(s, straight, o);
  return o[3] == 1.0f;
}
inline uint32_t mul255_px(uint32_t x, uint32_t a) {
  const uint32_t t = x * a + 128u;
  return (t + (t >> 8)) >> 8;
}
inline void prem8_px(const uint8_t* s, int straight, uint32_t* d) {
  for (int c = 0; c < 3; ++c) d[c] = straight ? mul255_px(s[c], s[3]) : s[c];
  d[3] = s[3];
}
inline bool over8_px(const uint8_t* f, int fs, const uint8_t* b, int bs, uint8_t* o) {
  uint32_t F[4], B[4];
  prem8_px(f, fs, F);
  prem8_px(b, bs, B);
  const uint32_t t = 255u - F[3];
  for (int c = 0; c < 4; ++c) {
    const uint32_t s = F[c] + mul255_px(B[c], t);
    o[c] = uint8_t(s < 255u ? s : 255u);
  }
  return o[3] == 255;
}
inline bool copy8_px(const uint8_t* s, int straight, uint8_t* o) {
  uint32_t P[4];
  prem8_px(s, straight, P);
  for (int c = 0; c < 4; ++c) o[c] = uint8_t(P[c]);
  return o[3] == 255;
}

}  // namespace lockstep::opt::composite_kernels
#endif  // LOCKSTEP_COMPOSITE_SIMD_SHARED

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "optimized/composite_simd.cpp"
#include "hwy/cache_control.h"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace lockstep::opt::composite_kernels {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

#if HWY_TARGET == HWY_SCALAR
// One float per vector cannot hold a pixel: the scalar target runs the scalar pixels.
bool OverF(const float* f, int fs, const float* b, int bs, float* out, size_t n, int) {
  bool ok = true;
  for (size_t i = 0; i < 4 * n; i += 4) ok = over_px(f + i, fs, b + i, bs, out + i) && ok;
  return ok;
}
bool CopyF(const float* s, int st, float* out, size_t n, int) {
  bool ok = true;
  for (size_t i = 0; i < 4 * n; i += 4) ok = copy_px(s + i, st, out + i) && ok;
  return ok;
}
bool OpaqueF(const float* s, size_t n) {
  for (size_t i = 0; i < n; ++i)
    if (s[4 * i + 3] != 1.0f) return false;
  return true;
}
bool Over8(const uint8_t* f, int fs, const uint8_t* b, int bs, uint8_t* out, size_t n) {
  bool ok = true;
  for (size_t i = 0; i < 4 * n; i += 4) ok = over8_px(f + i, fs, b + i, bs, out + i) && ok;
  return ok;
}
bool Copy8(const uint8_t* s, int st, uint8_t* out, size_t n) {
  bool ok = true;
  for (size_t i = 0; i < 4 * n; i += 4) ok = copy8_px(s + i, st, out + i) && ok;
  return ok;
}
bool Opaque8(const uint8_t* s, size_t n) {
  for (size_t i = 0; i < n; ++i)
    if (s[4 * i + 3] != 255) return false;
  return true;
}
void ToFloat8(const uint8_t* s, float* out, size_t n, int) {
  for (size_t i = 0; i < 4 * n; ++i) out[i] = float(s[i]) / 255.0f;
}
void Flush() {}
#else

using DF = hn::ScalableTag<float>;
using DU16 = hn::ScalableTag<uint16_t>;
using DI16 = hn::RebindToSigned<DU16>;
using DU8H = hn::Rebind<uint8_t, DU16>;  // half as many bytes as DU16 has lanes
using DU8F = hn::Repartition<uint8_t, DU16>;

// Lanes holding alpha: every 4th (RGBA interleaved).
template <class D>
HWY_INLINE hn::Mask<D> AlphaLanes(D d) {
  const hn::RebindToUnsigned<D> du;
  const auto three = hn::Set(du, 3);
  return hn::RebindMask(d, hn::Eq(hn::And(hn::Iota(du, 0), three), three));
}

// Each pixel's alpha in all four of its lanes (a pixel is one 128-bit block).
HWY_INLINE hn::Vec<DF> AlphaF(hn::Vec<DF> v) { return hn::Broadcast<3>(v); }

HWY_INLINE hn::Vec<DF> PremF(hn::Vec<DF> v, hn::Mask<DF> is_alpha) {
  return hn::IfThenElse(is_alpha, v, hn::Mul(v, AlphaF(v)));
}

// True when `out` can take aligned streaming stores at all (float* from the
// allocator is 16-byte aligned; a whole vector's alignment is reached by
// peeling pixels).
template <class T>
HWY_INLINE bool CanStream(const T* out) {
  return (reinterpret_cast<uintptr_t>(out) & 15) == 0;
}
template <class T>
HWY_INLINE bool Aligned(const T* p, size_t lanes) {
  return (reinterpret_cast<uintptr_t>(p) & (lanes * sizeof(T) - 1)) == 0;
}
// A vector of results to out: float, with streaming stores or not; 8 bits,
// from 16-bit lanes (never streamed).
HWY_INLINE void Put(hn::Vec<DF> v, float* p, int stream) {
  if (stream) {
    hn::Stream(v, DF(), p);
  } else {
    hn::StoreU(v, DF(), p);
  }
}
HWY_INLINE void Put(hn::Vec<DU16> v, uint8_t* p, int) {
  // Every lane is <= 255: the signed demotion is exact.
  hn::StoreU(hn::DemoteTo(DU8H(), hn::BitCast(DI16(), v)), DU8H(), p);
}

// The loop every kernel shares, over `total` elements of out, N a vector:
// with stream (when out can take aligned streaming stores), scalar steps
// (step(i): kStep elements, a pixel or one value) until out + i is at a whole
// vector; then whole vectors (vec(i, stream): elements [i, i + N)); then scalar
// steps to the end.
template <size_t kStep, class T, class VecFn, class StepFn>
HWY_INLINE void Loop(T* out, size_t total, size_t N, int stream, const VecFn& vec,
                     const StepFn& step) {
  size_t i = 0;
  if (stream && !CanStream(out)) stream = 0;
  if (stream)
    for (; i < total && !Aligned(out + i, N); i += kStep) step(i);
  for (; i + N <= total; i += N) vec(i, stream);
  for (; i < total; i += kStep) step(i);
}

// Loop over n RGBA pixels of out, for the kernels that say whether every
// result is opaque: vec(i) is the vector of results for elements [i, i + N),
// stored with Put; px(i) writes the pixel at element i and says whether its
// alpha is full. True when every result's alpha is `full`.
template <class D, class T, class VecFn, class PxFn>
HWY_INLINE bool PixelLoop(D d, T* out, size_t n, int stream, hn::Vec<D> full, const VecFn& vec,
                          const PxFn& px) {
  const auto colour = hn::Not(AlphaLanes(d));
  auto opaque = hn::Eq(full, full);
  bool ok = true;
  Loop<4>(
      out, 4 * n, hn::Lanes(d), stream,
      [&](size_t i, int stream) HWY_ATTR {
        const auto r = vec(i);
        opaque = hn::And(opaque, hn::Or(hn::Eq(r, full), colour));
        Put(r, out + i, stream);
      },
      [&](size_t i) HWY_ATTR { ok = px(i) && ok; });
  return ok && hn::AllTrue(d, opaque);
}

// out = prem(f) over prem(b) for n pixels; true when every result alpha is 1.
// out may be f or b (in place). stream: write with non-temporal stores.
bool OverF(const float* f, int fs, const float* b, int bs, float* out, size_t n, int stream) {
  const DF d;
  const auto is_alpha = AlphaLanes(d);
  const auto one = hn::Set(d, 1.0f);
  return PixelLoop(
      d, out, n, stream, one,
      [&](size_t i) HWY_ATTR {
        auto fv = hn::LoadU(d, f + i);
        auto bv = hn::LoadU(d, b + i);
        if (fs) fv = PremF(fv, is_alpha);
        if (bs) bv = PremF(bv, is_alpha);
        const auto transparency = hn::Sub(one, AlphaF(fv));  // 1 - af
        return hn::Add(fv, hn::Mul(transparency, bv));       // Cf + (1 - af) Cb, no FMA
      },
      [&](size_t i) HWY_ATTR { return over_px(f + i, fs, b + i, bs, out + i); });
}

// out = prem(s); true when every alpha is 1.
bool CopyF(const float* s, int st, float* out, size_t n, int stream) {
  const DF d;
  const auto is_alpha = AlphaLanes(d);
  return PixelLoop(
      d, out, n, stream, hn::Set(d, 1.0f),
      [&](size_t i) HWY_ATTR {
        auto v = hn::LoadU(d, s + i);
        if (st) v = PremF(v, is_alpha);
        return v;
      },
      [&](size_t i) HWY_ATTR { return copy_px(s + i, st, out + i); });
}

bool OpaqueF(const float* s, size_t n) {
  const DF d;
  const size_t N = hn::Lanes(d), total = 4 * n;
  const auto colour = hn::Not(AlphaLanes(d));
  const auto one = hn::Set(d, 1.0f);
  auto opaque = hn::Eq(one, one);
  size_t i = 0;
  for (; i + N <= total; i += N)
    opaque = hn::And(opaque, hn::Or(hn::Eq(hn::LoadU(d, s + i), one), colour));
  for (; i < total; i += 4)
    if (s[i + 3] != 1.0f) return false;
  return hn::AllTrue(d, opaque);
}

// ---- 8 bits, in 16-bit lanes (4 per pixel).

HWY_INLINE hn::Vec<DU16> Load8(const uint8_t* p) {
  return hn::PromoteTo(DU16(), hn::LoadU(DU8H(), p));
}
// Each pixel's alpha (lane 3 of its 4) in all four lanes: a byte shuffle
// within 128-bit blocks (2 pixels per block).
HWY_INLINE hn::Vec<DU16> Alpha8(hn::Vec<DU16> v) {
  alignas(16) static constexpr uint8_t kPattern[16] = {6,  7,  6,  7,  6,  7,  6,  7,
                                                       14, 15, 14, 15, 14, 15, 14, 15};
  const auto idx = hn::BitCast(DU16(), hn::LoadDup128(DU8F(), kPattern));
  return hn::TableLookupBytes(v, idx);
}
// round(x a / 255) exactly: t = x a + 128 (<= 65153), (t + (t >> 8)) >> 8 (<= 65407 before the
// shift).
HWY_INLINE hn::Vec<DU16> Mul255(hn::Vec<DU16> x, hn::Vec<DU16> a) {
  const auto t = hn::Add(hn::Mul(x, a), hn::Set(DU16(), 128));
  return hn::ShiftRight<8>(hn::Add(t, hn::ShiftRight<8>(t)));
}
HWY_INLINE hn::Vec<DU16> Prem8(hn::Vec<DU16> v, hn::Mask<DU16> is_alpha) {
  return hn::IfThenElse(is_alpha, v, Mul255(v, Alpha8(v)));
}

bool Over8(const uint8_t* f, int fs, const uint8_t* b, int bs, uint8_t* out, size_t n) {
  const DU16 d;
  const auto is_alpha = AlphaLanes(d);
  const auto full = hn::Set(d, 255);
  return PixelLoop(
      d, out, n, 0, full,
      [&](size_t i) HWY_ATTR {
        auto fv = Load8(f + i);
        auto bv = Load8(b + i);
        if (fs) fv = Prem8(fv, is_alpha);
        if (bs) bv = Prem8(bv, is_alpha);
        const auto transparency = hn::Sub(full, Alpha8(fv));          // 255 - af
        return hn::Min(hn::Add(fv, Mul255(bv, transparency)), full);  // saturating
      },
      [&](size_t i) HWY_ATTR { return over8_px(f + i, fs, b + i, bs, out + i); });
}

bool Copy8(const uint8_t* s, int st, uint8_t* out, size_t n) {
  const DU16 d;
  const auto is_alpha = AlphaLanes(d);
  return PixelLoop(
      d, out, n, 0, hn::Set(d, 255),
      [&](size_t i) HWY_ATTR {
        auto v = Load8(s + i);
        if (st) v = Prem8(v, is_alpha);
        return v;
      },
      [&](size_t i) HWY_ATTR { return copy8_px(s + i, st, out + i); });
}

bool Opaque8(const uint8_t* s, size_t n) {
  for (size_t i = 0; i < n; ++i)
    if (s[4 * i + 3] != 255) return false;
  return true;
}

// out = q / 255 (a true division: the correctly rounded float, as the reference).
void ToFloat8(const uint8_t* s, float* out, size_t n, int stream) {
  const DF d;
  const hn::RebindToSigned<DF> di;
  const hn::Rebind<uint8_t, DF> d8;
  const auto k255 = hn::Set(d, 255.0f);
  Loop<1>(
      out, 4 * n, hn::Lanes(d), stream,
      [&](size_t i, int stream) HWY_ATTR {
        Put(hn::Div(hn::ConvertTo(d, hn::PromoteTo(di, hn::LoadU(d8, s + i))), k255), out + i,
            stream);
      },
      [&](size_t i) HWY_ATTR { out[i] = float(s[i]) / 255.0f; });
}

// Streaming stores are weakly ordered: fence before the band counts as done.
void Flush() { hwy::FlushStream(); }
#endif  // HWY_TARGET == HWY_SCALAR

// ---- one range of pixels [p0, p1) through every layer, chunk by chunk.

// Composites the accumulator `acc` (already premultiplied) with the next layer
// in the plan's order: under it front to back, over it back to front.
HWY_INLINE bool CombineF(const Plan& P, const float* acc, int acc_st, const float* layer,
                         int layer_st, float* dst, size_t n, int stream) {
  return P.ftb ? OverF(acc, acc_st, layer, layer_st, dst, n, stream)
               : OverF(layer, layer_st, acc, acc_st, dst, n, stream);
}
HWY_INLINE bool Combine8(const Plan& P, const uint8_t* acc, int acc_st, const uint8_t* layer,
                         int layer_st, uint8_t* dst, size_t n) {
  return P.ftb ? Over8(acc, acc_st, layer, layer_st, dst, n)
               : Over8(layer, layer_st, acc, acc_st, dst, n);
}

void ChunkF(const Plan& P, size_t p0, size_t n, float* out) {
  const size_t L = P.f.size();
  const float* const* f = P.f.data();
  const uint8_t* st = P.straight.data();
  if (L == 1) {
    CopyF(f[0] + 4 * p0, st[0], out, n, 1);
    return;
  }
  HWY_ALIGN float acc[kChunk * 4];
  bool done[kChunk / kBlock] = {};
  const size_t blocks = (n + kBlock - 1) / kBlock;
  size_t open = blocks;
  // First pass: the first two layers of the sequence (straight to the output
  // when there are only two).
  for (size_t k = 0; k < blocks; ++k) {
    const size_t b0 = k * kBlock, bn = std::min(kBlock, n - b0);
    const float* s0 = f[0] + 4 * (p0 + b0);
    const float* s1 = f[1] + 4 * (p0 + b0);
    float* dst = L == 2 ? out + 4 * b0 : acc + 4 * b0;
    if (P.early_stop &&
        OpaqueF(s0, bn)) {  // the front layer covers the block: the next is not read
      CopyF(s0, st[0], dst, bn, L == 2);
      done[k] = true;
    } else {
      done[k] = CombineF(P, s0, st[0], s1, st[1], dst, bn, L == 2) && P.early_stop;
    }
    open -= done[k];
  }
  if (L == 2) return;
  // Middle layers, in the accumulator (in cache); covered blocks are skipped.
  for (size_t l = 2; l + 1 < L && open > 0; ++l) {
    for (size_t k = 0; k < blocks; ++k) {
      if (done[k]) continue;
      const size_t b0 = k * kBlock, bn = std::min(kBlock, n - b0);
      done[k] = CombineF(P, acc + 4 * b0, 0, f[l] + 4 * (p0 + b0), st[l], acc + 4 * b0, bn, 0) &&
                P.early_stop;
      open -= done[k];
    }
  }
  // Last layer, written to the output once (streaming).
  for (size_t k = 0; k < blocks; ++k) {
    const size_t b0 = k * kBlock, bn = std::min(kBlock, n - b0);
    if (done[k]) {
      CopyF(acc + 4 * b0, 0, out + 4 * b0, bn, 1);
    } else {
      CombineF(P, acc + 4 * b0, 0, f[L - 1] + 4 * (p0 + b0), st[L - 1], out + 4 * b0, bn, 1);
    }
  }
}

void Chunk8(const Plan& P, size_t p0, size_t n, float* out) {
  const size_t L = P.q.size();
  const uint8_t* const* q = P.q.data();
  const uint8_t* st = P.straight.data();
  HWY_ALIGN uint8_t acc[kChunk * 4];
  bool done[kChunk / kBlock] = {};
  const size_t blocks = (n + kBlock - 1) / kBlock;
  size_t open = blocks;
  for (size_t k = 0; k < blocks; ++k) {
    const size_t b0 = k * kBlock, bn = std::min(kBlock, n - b0);
    const uint8_t* s0 = q[0] + 4 * (p0 + b0);
    if (L == 1 || (P.early_stop && Opaque8(s0, bn))) {
      done[k] = Copy8(s0, st[0], acc + 4 * b0, bn) && P.early_stop;
    } else {
      done[k] =
          Combine8(P, s0, st[0], q[1] + 4 * (p0 + b0), st[1], acc + 4 * b0, bn) && P.early_stop;
    }
    open -= done[k];
  }
  for (size_t l = 2; l < L && open > 0; ++l) {
    for (size_t k = 0; k < blocks; ++k) {
      if (done[k]) continue;
      const size_t b0 = k * kBlock, bn = std::min(kBlock, n - b0);
      done[k] = Combine8(P, acc + 4 * b0, 0, q[l] + 4 * (p0 + b0), st[l], acc + 4 * b0, bn) &&
                P.early_stop;
      open -= done[k];
    }
  }
  ToFloat8(acc, out, n, 1);
}

void CompositeRange(const Plan* P, size_t p0, size_t p1, float* out) {
  const bool eight = !P->q.empty();
  for (size_t c = p0; c < p1; c += kChunk) {
    const size_t n = std::min(kChunk, p1 - c);
    if (eight) {
      Chunk8(*P, c, n, out + 4 * c);
    } else {
      ChunkF(*P, c, n, out + 4 * c);
    }
  }
  Flush();
}

// For tests: the Highway target a dispatch picks.
const char* CompositeTargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace lockstep::opt::composite_kernels
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <algorithm>

namespace lockstep::opt::composite_kernels {
HWY_EXPORT(CompositeRange);
HWY_EXPORT(CompositeTargetName);
}  // namespace lockstep::opt::composite_kernels

namespace lockstep::opt::simd {

namespace ck = composite_kernels;

const char* composite_target_name() { return HWY_DYNAMIC_DISPATCH(ck::CompositeTargetName)(); }

void composite_into(const LayerStack& stack, const FrameOptions& opts, float* out,
                    FrameStats* stats) {
  check_stack(stack);
  const int w = stack.width(), h = stack.height();
  ck::Plan plan;
  plan.ftb = stack.order == Order::front_to_back;
  plan.early_stop = plan.ftb && stack.early_stop;
  const size_t L = stack.layers.size();
  for (size_t s = 0; s < L; ++s) {
    const Layer& l = stack.layers[plan.ftb ? s : L - 1 - s];
    if (stack.storage == Storage::unorm8) {
      plan.q.push_back(l.rgba8.data());
    } else {
      plan.f.push_back(l.image.rgba.data());
    }
    plan.straight.push_back(l.alpha == Alpha::straight);
  }
  // Bands of about 64K pixels (1 MB of float RGBA per layer): a few hundred
  // tasks at 4096^2 for TBB to balance, each many chunks long.
  const int band = std::max(1, std::min(h, int((size_t(1) << 16) / size_t(w))));
  parallel_tiles(w, h, w, band, opts.threads, opts.progress, [&](int, int y0, int, int y1) {
    HWY_DYNAMIC_DISPATCH(ck::CompositeRange)
    (&plan, size_t(y0) * size_t(w), size_t(y1) * size_t(w), out);
  });
  if (stats) stats->items = uint64_t(w) * uint64_t(h);
}

Image composite(const LayerStack& stack, const FrameOptions& opts, FrameStats* stats) {
  check_stack(stack);
  // Image's constructor zero-fills (one extra write pass of the output, and the
  // first touch of its pages); composite_into() lets a caller reuse a buffer.
  Image out = Image::uninitialized(stack.width(), stack.height());  // every pixel is written below
  composite_into(stack, opts, out.rgba.data(), stats);
  return out;
}

}  // namespace lockstep::opt::simd
#endif  // HWY_ONCE
