// lockstep optimized: volume ray casting in float SIMD ray packets (see
// optimized/volume_raycast_simd.h; the contract: core/volume_render.h).
//
// A packet is N neighbouring pixels of a row (N = 8 float lanes on AVX2, 16 on
// AVX-512; Highway compiles the kernels for each x86 target the build allows
// and dispatches at run time). Every ray of the view is parallel, so the packet
// steps through one shared sample index k: lane l takes sample k when k lies in
// its own [k0, k1] (core's ray_samples, in double, per pixel), at grid
// coordinates g0 + (k - kbase) dg (g0 per lane in double at the packet's first
// sample kbase, rounded to float; dg = dt dir / spacing is the same for every
// lane). Per sample, as the reference:
//   trilinear     eight gathers, the same lerps in the same order, in float;
//   classify      the transfer function exactly (piecewise linear): the segment
//                 by counting control points below the value, its ends by a
//                 table lookup in registers (a gather beyond N segments); alpha
//                 first, the colours only when some lane is not transparent;
//   correct       alpha' = 1 - exp(ratio log(1 - alpha)) (Highway's float
//                 exp/log; alpha' = alpha at ratio 1, 0 at alpha 0, 1 at 1);
//   composite     front to back, w = (1 - A) alpha', C += w c, A += w;
//   terminate     a lane stops once A >= 1 - eps (float); the packet once every
//                 lane has stopped or left the volume.
// Empty-space skipping (unless noskip): the volume's cells are grouped into
// macro cells of 8^3 cells; each gets the min and max of the samples of its
// cells and of one more sample on every side (a dilated range: any point within
// a voxel of the macro cell, so any sample whose float position strays across a
// face by roundoff, interpolates a value inside it). A macro cell is
// transparent when the transfer function's max_alpha over its range is 0. When
// every lane that takes sample k sits in a transparent macro cell, the packet
// jumps to the first sample past the nearest exit of those cells along the ray
// (never past a lane's first sample k0 that is still to come): the samples
// skipped lie on the same planes k dt and each had alpha' exactly 0, so skipping
// changes nothing but the time. The grid depends on the volume, the table on
// the transfer function: both are kept with the volume (Volume::derived, keyed
// by the samples and the transfer function's points) and built only when
// absent, on the frame's threads; the frame that builds them reports the time
// as FrameStats::build_seconds (the one-shot cost), later frames 0.
//
// The isosurface (volume_iso) marches the same packets: sample k's side of the
// iso value (value >= iso) decides; a sample whose float value lies within a
// margin of iso (a bound on the float value's error, from the volume's range
// and size) is decided again in double exactly as the reference does, so the
// first bracketing pair is the reference's. Macro cells whose dilated range is
// all below (or all at or above) iso are stepped over with their side known.
// Bisection and shading then run per hit pixel in double, the reference's code:
// the image equals the reference's.
#ifndef LOCKSTEP_VOLUME_RAYCAST_SHARED
#define LOCKSTEP_VOLUME_RAYCAST_SHARED
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/volume.h"
#include "core/volume_render.h"
#include "io/volume_settings.h"

namespace lockstep::opt::vr_kernels {

inline constexpr int kMacroShift = 3;  // macro cells of 8^3 cells
inline constexpr int kMaxLanes = 64;   // per-packet scratch arrays

// Everything a packet kernel reads (built once per frame).
struct Ctx {
  const Volume* volume = nullptr;
  const vr::View* view = nullptr;
  const float* data = nullptr;
  int64_t samples = 0;  // floats in data
  int nx = 0, ny = 0, nz = 0;
  float gmax[3] = {0, 0, 0};  // n - 1: grid coordinates are clamped to [0, n - 1]
  int imax[3] = {0, 0, 0};    // n - 2: the last cell
  double dg[3] = {0, 0, 0};   // one sample step in grid coordinates (the same for every ray)
  float inv_dg[3] = {0, 0, 0};  // 1 / dg (0 where dg is 0: that axis never exits)
  // The transfer function, as segments between control points (values clamped
  // to [x_first, x_last]): segment s runs from thresholds[s] with width w[s];
  // channel c there is base[c][s] + t delta[c][s], t = (v - x) / w.
  int points = 0;
  int segments = 0;                  // max(points - 1, 1)
  std::vector<float> inner;          // the control values strictly inside (points 1 .. P-2): the segment is their count below v
  float x_first = 0, x_last = 0;
  std::vector<float> seg_x, seg_w, base[4], delta[4];  // padded to kMaxLanes entries past `segments`
  float ratio = 1;
  bool correct = false;  // ratio != 1
  float limit = 1;       // 1 - eps
  bool terminate = false;
  // Macro cells.
  bool skip = false;
  int mi = 0, mj = 0, mk = 0;
  const int32_t* cell_state = nullptr;  // raycast: 1 transparent; iso: 0 all below, 1 all above, 2 mixed
  // Iso.
  float iso = 0;
  double iso_d = 0;
  float margin = 0;
};

}  // namespace lockstep::opt::vr_kernels
#endif  // LOCKSTEP_VOLUME_RAYCAST_SHARED

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "optimized/volume_raycast.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/contrib/math/math-inl.h"
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace lockstep::opt::vr_kernels {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<DF>;
using VF = hn::Vec<DF>;
using VI = hn::Vec<DI>;

// The packet's rays: per lane its sample range and its grid position at kbase.
struct Rays {
  HWY_ALIGN float g0[3][kMaxLanes];
  HWY_ALIGN int32_t k0[kMaxLanes], k1[kMaxLanes];
  double o[3][kMaxLanes];  // ray origins (iso: the double re-decisions)
  long kbase = 0, kend = -1;
  bool any = false;
};

HWY_INLINE void SetUp(const Ctx& c, int x, int x_end, int y, size_t N, Rays& r) {
  const vr::View& view = *c.view;
  const Volume& v = *c.volume;
  long kmin = 0, kmax = -1;
  bool any = false;
  Vec3 origins[kMaxLanes];
  for (size_t l = 0; l < N; ++l) {
    long k0 = 1, k1 = 0;
    Vec3 o{0, 0, 0};
    if (x + int(l) < x_end) {
      o = vr::ray_origin(view, x + int(l), y);
      vr::ray_samples(view, o, k0, k1);
    }
    origins[l] = o;
    r.o[0][l] = o.x, r.o[1][l] = o.y, r.o[2][l] = o.z;
    r.k0[l] = int32_t(k0);
    r.k1[l] = int32_t(k1);
    if (k0 <= k1) {
      kmin = any ? std::min(kmin, k0) : k0;
      kmax = any ? std::max(kmax, k1) : k1;
      any = true;
    }
  }
  r.any = any;
  r.kbase = kmin;
  r.kend = kmax;
  if (!any) return;
  for (size_t l = 0; l < N; ++l) {
    const Vec3 p = origins[l] + (double(kmin) * view.dt) * view.dir;
    r.g0[0][l] = float((p.x - v.origin.x) / v.spacing.x);
    r.g0[1][l] = float((p.y - v.origin.y) / v.spacing.y);
    r.g0[2][l] = float((p.z - v.origin.z) / v.spacing.z);
  }
}

// Sample k of the packet: grid coordinates clamped, cells, fractions.
struct Sample {
  VF g[3];
  VI i[3];
  VF f[3];
};

// Sample kq (one per lane) of the packet: grid coordinates g0 + (kq - kbase)
// dg, clamped; cells; fractions.
HWY_INLINE void Locate(const Ctx& c, const Rays& r, VI kq, Sample& s) {
  const DF df;
  const DI di;
  const VF steps = hn::ConvertTo(df, hn::Sub(kq, hn::Set(di, int32_t(r.kbase))));
  for (int a = 0; a < 3; ++a) {
    VF g = hn::Add(hn::Load(df, r.g0[a]), hn::Mul(steps, hn::Set(df, float(c.dg[a]))));
    g = hn::Min(hn::Max(g, hn::Zero(df)), hn::Set(df, c.gmax[a]));
    const VI i = hn::Min(hn::ConvertTo(di, g), hn::Set(di, c.imax[a]));
    s.g[a] = g;
    s.i[a] = i;
    s.f[a] = hn::Sub(g, hn::ConvertTo(df, i));
  }
}

HWY_INLINE VI MacroIndex(const Ctx& c, const Sample& s) {
  const DI di;
  const VI mx = hn::ShiftRight<kMacroShift>(s.i[0]), my = hn::ShiftRight<kMacroShift>(s.i[1]),
           mz = hn::ShiftRight<kMacroShift>(s.i[2]);
  return hn::Add(mx, hn::Mul(hn::Add(my, hn::Mul(mz, hn::Set(di, c.mj))), hn::Set(di, c.mi)));
}

// Samples (in units of k) from sample k to the exit of each lane's macro cell,
// the nearest face along the ray (floored); large where the ray runs parallel.
HWY_INLINE VI StepsInCell(const Ctx& c, const Sample& s) {
  const DF df;
  const DI di;
  VF e = hn::Set(df, 1e6f);
  for (int a = 0; a < 3; ++a) {
    if (c.dg[a] == 0) continue;
    const VI m = hn::ShiftRight<kMacroShift>(s.i[a]);
    const VI bound = c.dg[a] > 0 ? hn::ShiftLeft<kMacroShift>(hn::Add(m, hn::Set(di, 1))) : hn::ShiftLeft<kMacroShift>(m);
    const VF ea = hn::Mul(hn::Sub(hn::ConvertTo(df, bound), s.g[a]), hn::Set(df, c.inv_dg[a]));
    e = hn::Min(e, ea);
  }
  e = hn::Min(hn::Max(e, hn::Zero(df)), hn::Set(df, 1e6f));
  return hn::ConvertTo(di, e);
}

HWY_INLINE VF Lerp(VF a, VF b, VF t) { return hn::Add(a, hn::Mul(t, hn::Sub(b, a))); }

// Samples (i, j, k) and (i + 1, j, k) of every lane, as one 64-bit gather of
// the two neighbouring floats (half the loads of two 32-bit gathers), split
// into the first and the second of each pair.
HWY_INLINE void GatherPairs(const Ctx& c, VI index, VF& a, VF& b) {
  const DF df;
  const hn::Half<DI> dih;
  const hn::Repartition<int64_t, DF> d64;
  const auto lo = hn::ShiftLeft<2>(hn::PromoteTo(d64, hn::LowerHalf(dih, index)));
  const auto hi = hn::ShiftLeft<2>(hn::PromoteTo(d64, hn::UpperHalf(dih, index)));
  const int64_t* base = reinterpret_cast<const int64_t*>(c.data);
  const VF plo = hn::BitCast(df, hn::GatherOffset(d64, base, lo));
  const VF phi = hn::BitCast(df, hn::GatherOffset(d64, base, hi));
  a = hn::ConcatEven(df, phi, plo);
  b = hn::ConcatOdd(df, phi, plo);
}

// The trilinear interpolant at every lane's sample. When the active lanes'
// cells all start within one vector's width of a sample row (rays whose image
// rows run along the volume's x axis: lanes half a voxel apart read the same
// few samples), each of the four rows of corners is one unaligned load and two
// lane permutations; otherwise pair gathers. The same values either way.
HWY_INLINE VF Trilinear(const Ctx& c, const Sample& s, hn::Mask<DI> active) {
  const DF df;
  const DI di;
  const int32_t sy = c.nx, sz = c.nx * c.ny;
  const VI base = hn::Add(s.i[0], hn::Mul(hn::Add(s.i[1], hn::Mul(s.i[2], hn::Set(di, c.ny))), hn::Set(di, c.nx)));
  VF v000, v100, v010, v110, v001, v101, v011, v111;
  const int32_t lanes = int32_t(hn::Lanes(df));
  const int32_t lo = hn::GetLane(hn::MinOfLanes(di, hn::IfThenElse(active, base, hn::Set(di, INT32_MAX))));
  const int32_t hi = hn::GetLane(hn::MaxOfLanes(di, hn::IfThenElse(active, base, hn::Set(di, INT32_MIN))));
  if (hi - lo + 2 <= lanes && int64_t(lo) + sz + sy + lanes <= c.samples) {
    const VI rel = hn::IfThenElseZero(active, hn::Sub(base, hn::Set(di, lo)));
    const auto ia = hn::IndicesFromVec(df, rel);
    const auto ib = hn::IndicesFromVec(df, hn::Add(rel, hn::Set(di, 1)));
    auto row = [&](int32_t off, VF& a, VF& b) {
      const VF r = hn::LoadU(df, c.data + lo + off);
      a = hn::TableLookupLanes(r, ia);
      b = hn::TableLookupLanes(r, ib);
    };
    row(0, v000, v100);
    row(sy, v010, v110);
    row(sz, v001, v101);
    row(sz + sy, v011, v111);
  } else {
    GatherPairs(c, base, v000, v100);
    GatherPairs(c, hn::Add(base, hn::Set(di, sy)), v010, v110);
    GatherPairs(c, hn::Add(base, hn::Set(di, sz)), v001, v101);
    GatherPairs(c, hn::Add(base, hn::Set(di, sz + sy)), v011, v111);
  }
  const VF c00 = Lerp(v000, v100, s.f[0]);
  const VF c10 = Lerp(v010, v110, s.f[0]);
  const VF c01 = Lerp(v001, v101, s.f[0]);
  const VF c11 = Lerp(v011, v111, s.f[0]);
  return Lerp(Lerp(c00, c10, s.f[1]), Lerp(c01, c11, s.f[1]), s.f[2]);
}

HWY_INLINE VF Lookup(const Ctx& c, const float* table, VI seg) {
  const DF df;
  if (size_t(c.segments) <= hn::Lanes(df)) return hn::TableLookupLanes(hn::LoadU(df, table), hn::IndicesFromVec(df, seg));
  return hn::GatherIndex(df, table, seg);
}

// Renders pixels [x, x_end) of row y (x_end - x <= kMaxLanes * many) into out (RGBA).
void CastRow(const Ctx& c, int x_begin, int x_end, int y, float* out, uint64_t* skipped) {
  const DF df;
  const DI di;
  const size_t N = hn::Lanes(df);
  Rays r;
  HWY_ALIGN float res[4][kMaxLanes];
  uint64_t skip_count = 0;
  for (int x = x_begin; x < x_end; x += int(N)) {
    SetUp(c, x, x_end, y, N, r);
    VF acc[3] = {hn::Zero(df), hn::Zero(df), hn::Zero(df)};
    VF A = hn::Zero(df);
    if (r.any) {
      const VI k0 = hn::Load(di, r.k0), k1 = hn::Load(di, r.k1);
      auto done = hn::Lt(k1, k0);  // empty lanes never take a sample
      for (long k = r.kbase; k <= r.kend;) {
        const VI vk = hn::Set(di, int32_t(k));
        const auto pending = hn::AndNot(done, hn::Lt(vk, k0));
        const auto active_i = hn::Not(hn::Or(done, hn::Or(hn::Lt(vk, k0), hn::Gt(vk, k1))));
        if (!c.skip && hn::AllFalse(di, active_i)) {
          if (hn::AllFalse(di, pending)) break;
          // Only lanes still to start: go to the first one's first sample.
          k = hn::GetLane(hn::MinOfLanes(di, hn::IfThenElse(pending, k0, hn::Set(di, INT32_MAX))));
          continue;
        }
        // Each lane's next sample: k, or its first one still to come.
        const VI kq = hn::IfThenElse(pending, k0, vk);
        Sample s;
        Locate(c, r, kq, s);
        if (c.skip) {
          const auto clear = hn::Eq(hn::GatherIndex(di, c.cell_state, MacroIndex(c, s)), hn::Set(di, 1));
          if (hn::AllFalse(di, hn::AndNot(clear, active_i))) {
            // Every lane taking sample k is in a transparent macro cell: jump to
            // the first sample past the nearest exit, not past a lane still to
            // start unless its first sample is in a transparent cell too (then
            // not past that cell's exit).
            const VI past = hn::Add(kq, hn::Add(StepsInCell(c, s), hn::Set(di, 1)));
            const VI limit = hn::IfThenElse(hn::Or(active_i, hn::And(pending, clear)), past,
                                            hn::IfThenElse(pending, k0, hn::Set(di, INT32_MAX)));
            const long next = hn::GetLane(hn::MinOfLanes(di, limit));
            if (next == INT32_MAX) break;
            skip_count += uint64_t(next - k) * hn::CountTrue(di, active_i);
            k = std::max(next, k + 1);
            continue;
          }
          if (hn::AllFalse(di, active_i)) {
            k = hn::GetLane(hn::MinOfLanes(di, hn::IfThenElse(pending, k0, hn::Set(di, INT32_MAX))));
            continue;
          }
        }
        const auto active = hn::RebindMask(df, active_i);
        const VF value = Trilinear(c, s, active_i);
        // The segment: how many inner control values lie at or below v.
        const VF v = hn::Min(hn::Max(value, hn::Set(df, c.x_first)), hn::Set(df, c.x_last));
        VI seg = hn::Zero(di);
        for (const float xin : c.inner) seg = hn::Sub(seg, hn::VecFromMask(di, hn::RebindMask(di, hn::Ge(v, hn::Set(df, xin)))));
        const VF t = hn::Div(hn::Sub(v, Lookup(c, c.seg_x.data(), seg)), Lookup(c, c.seg_w.data(), seg));
        VF alpha = hn::Add(Lookup(c, c.base[3].data(), seg), hn::Mul(t, Lookup(c, c.delta[3].data(), seg)));
        alpha = hn::Min(hn::Max(alpha, hn::Zero(df)), hn::Set(df, 1.0f));
        const auto visible = hn::And(active, hn::Gt(alpha, hn::Zero(df)));
        if (!hn::AllFalse(df, visible)) {
          VF a = alpha;
          if (c.correct) {
            const VF one = hn::Set(df, 1.0f);
            const VF keep = hn::Max(hn::Sub(one, alpha), hn::Set(df, 1e-30f));
            a = hn::Sub(one, hn::Exp(df, hn::Mul(hn::Set(df, c.ratio), hn::Log(df, keep))));
            a = hn::IfThenElse(hn::Ge(alpha, one), one, a);
            a = hn::IfThenZeroElse(hn::Eq(alpha, hn::Zero(df)), a);
          }
          const VF w = hn::IfThenElseZero(active, hn::Mul(hn::Sub(hn::Set(df, 1.0f), A), a));
          for (int ch = 0; ch < 3; ++ch) {
            const VF col = hn::Add(Lookup(c, c.base[ch].data(), seg), hn::Mul(t, Lookup(c, c.delta[ch].data(), seg)));
            acc[ch] = hn::Add(acc[ch], hn::Mul(w, col));
          }
          A = hn::Add(A, w);
          if (c.terminate) done = hn::Or(done, hn::RebindMask(di, hn::And(active, hn::Ge(A, hn::Set(df, c.limit)))));
        }
        // Lanes with samples still to come.
        if (hn::AllFalse(di, hn::AndNot(done, hn::Gt(k1, vk)))) break;
        ++k;
      }
    }
    hn::Store(acc[0], df, res[0]);
    hn::Store(acc[1], df, res[1]);
    hn::Store(acc[2], df, res[2]);
    hn::Store(A, df, res[3]);
    for (size_t l = 0; l < N && x + int(l) < x_end; ++l) {
      float* p = out + 4 * size_t(x + int(l));
      for (int ch = 0; ch < 4; ++ch) p[ch] = res[ch][l];
    }
  }
  *skipped += skip_count;
}

// The isosurface: per pixel of [x_begin, x_end) of row y the first bracketing
// sample k (the reference's pair k - 1, k), or -1.
void IsoRow(const Ctx& c, int x_begin, int x_end, int y, int32_t* hit, uint64_t* skipped) {
  const DF df;
  const DI di;
  const size_t N = hn::Lanes(df);
  const vr::View& view = *c.view;
  Rays r;
  HWY_ALIGN int32_t out[kMaxLanes], above_store[kMaxLanes];
  uint64_t skip_count = 0;
  for (int x = x_begin; x < x_end; x += int(N)) {
    SetUp(c, x, x_end, y, N, r);
    VI khit = hn::Set(di, -1);
    if (r.any) {
      const VI k0 = hn::Load(di, r.k0), k1 = hn::Load(di, r.k1);
      // A lane needs two samples for a bracket.
      auto done = hn::Lt(k1, hn::Add(k0, hn::Set(di, 1)));
      VI prev = hn::Zero(di);  // the side (1: at or above iso) of the lane's previous sample
      for (long k = r.kbase; k <= r.kend;) {
        const VI vk = hn::Set(di, int32_t(k));
        const auto pending = hn::AndNot(done, hn::Lt(vk, k0));
        const auto active = hn::Not(hn::Or(done, hn::Or(hn::Lt(vk, k0), hn::Gt(vk, k1))));
        const VI kq = hn::IfThenElse(pending, k0, vk);
        Sample s;
        Locate(c, r, kq, s);
        const VI state = hn::GatherIndex(di, c.cell_state, MacroIndex(c, s));
        const auto uniform = hn::Lt(state, hn::Set(di, 2));
        const auto first = hn::Eq(vk, k0);
        VI above;
        long next = k + 1;
        auto took = active;  // lanes whose side at kq is decided now
        if (hn::AllFalse(di, hn::AndNot(uniform, active))) {
          // Every lane taking sample k is in a macro cell entirely on one side:
          // its side is known, and stays so up to the cell's exit; a lane still
          // to start whose first sample is in such a cell takes its side there
          // (its first sample, no bracket).
          above = state;
          took = hn::Or(active, hn::And(pending, uniform));
          const VI past = hn::Add(kq, hn::Add(StepsInCell(c, s), hn::Set(di, 1)));
          const VI limit = hn::IfThenElse(took, past, hn::IfThenElse(pending, k0, hn::Set(di, INT32_MAX)));
          next = hn::GetLane(hn::MinOfLanes(di, limit));
          if (next == INT32_MAX) break;
          next = std::max(next, k + 1);
          skip_count += uint64_t(next - k - 1) * hn::CountTrue(di, active);
        } else {
          const VF value = Trilinear(c, s, active);
          above = hn::VecFromMask(di, hn::RebindMask(di, hn::Ge(value, hn::Set(df, c.iso))));
          above = hn::And(above, hn::Set(di, 1));
          // Close to iso: decide in double, the reference's way.
          const auto near = hn::And(hn::RebindMask(df, active),
                                    hn::Le(hn::Abs(hn::Sub(value, hn::Set(df, c.iso))), hn::Set(df, c.margin)));
          if (!hn::AllFalse(df, near)) {
            hn::Store(above, di, above_store);
            HWY_ALIGN int32_t nm[kMaxLanes];
            hn::Store(hn::VecFromMask(di, hn::RebindMask(di, near)), di, nm);
            for (size_t l = 0; l < N; ++l)
              if (nm[l]) {
                const Vec3 o{r.o[0][l], r.o[1][l], r.o[2][l]};
                above_store[l] = vr::trilinear(*c.volume, o + (double(k) * view.dt) * view.dir) >= c.iso_d;
              }
            above = hn::Load(di, above_store);
          }
          if (hn::AllFalse(di, active)) {
            // Only lanes still to start (none in a one-sided cell): the first one's first sample.
            next = hn::GetLane(hn::MinOfLanes(di, hn::IfThenElse(pending, k0, hn::Set(di, INT32_MAX))));
            if (next == INT32_MAX) break;
          }
        }
        // A bracket (k - 1, k): an active lane past its first sample whose side changed.
        const auto crossed = hn::AndNot(first, hn::And(active, hn::Ne(above, prev)));
        khit = hn::IfThenElse(crossed, vk, khit);
        done = hn::Or(done, crossed);
        prev = hn::IfThenElse(took, above, prev);
        if (hn::AllFalse(di, hn::AndNot(done, hn::Gt(k1, vk)))) break;
        // A jump crosses samples on the lane's side: prev stays right.
        k = next;
      }
    }
    hn::Store(khit, di, out);
    for (size_t l = 0; l < N && x + int(l) < x_end; ++l) hit[x + int(l)] = out[l];
  }
  *skipped += skip_count;
}

const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace lockstep::opt::vr_kernels
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "core/timer.h"
#include "optimized/tiling.h"
#include "optimized/volume_raycast_simd.h"

namespace lockstep::opt::vr_kernels {
HWY_EXPORT(CastRow);
HWY_EXPORT(IsoRow);
HWY_EXPORT(TargetName);
}  // namespace lockstep::opt::vr_kernels

namespace lockstep::opt::simd {

namespace {

namespace vk = vr_kernels;

// Per macro cell: the min and max of the samples of its cells and of one more
// sample on every side (core: the macro cell of a sample at cell i is i >> 3).
struct MacroGrid {
  int mi = 0, mj = 0, mk = 0;
  std::vector<float> lo, hi;
};

MacroGrid build_macro(const Volume& v, int threads) {
  MacroGrid m;
  const int s = 1 << vk::kMacroShift;
  m.mi = (v.nx - 2) / s + 1;
  m.mj = (v.ny - 2) / s + 1;
  m.mk = (v.nz - 2) / s + 1;
  auto range = [s](int n, int c, int& a, int& b) {
    a = std::max(0, c * s - 1);
    b = std::min(n - 1, c * s + s + 1);
  };
  const size_t plane = size_t(m.mj) * m.mi;
  m.lo.resize(size_t(m.mk) * plane);
  m.hi.resize(m.lo.size());
  const size_t nx = size_t(v.nx), row_stride = size_t(v.ny) * nx;
  // Per macro slab K: the element-wise min and max of the sample planes it
  // spans in z (contiguous, vectorised by the compiler; each sample read about
  // 1.4 times), then per macro row J of that over the rows it spans in y, then
  // along x.
  parallel_tiles(1, m.mk, 1, 1, threads, nullptr, [&](int, int K0, int, int K1) {
    std::vector<float> plo(row_stride), phi(row_stride), lo(nx), hi(nx);
    for (int K = K0; K < K1; ++K) {
      int ka, kb;
      range(v.nz, K, ka, kb);
      {
        const float* first = &v.data[v.index(0, 0, ka)];
        std::copy_n(first, row_stride, plo.data());
        std::copy_n(first, row_stride, phi.data());
        float* HWY_RESTRICT l = plo.data();
        float* HWY_RESTRICT h = phi.data();
        for (int k = ka + 1; k <= kb; ++k) {
          const float* HWY_RESTRICT p = &v.data[v.index(0, 0, k)];
          for (size_t q = 0; q < row_stride; ++q) {
            l[q] = std::min(l[q], p[q]);
            h[q] = std::max(h[q], p[q]);
          }
        }
      }
      for (int J = 0; J < m.mj; ++J) {
        int ja, jb;
        range(v.ny, J, ja, jb);
        std::copy_n(&plo[size_t(ja) * nx], nx, lo.data());
        std::copy_n(&phi[size_t(ja) * nx], nx, hi.data());
        float* HWY_RESTRICT l = lo.data();
        float* HWY_RESTRICT h = hi.data();
        for (int j = ja + 1; j <= jb; ++j) {
          const float* HWY_RESTRICT rl = &plo[size_t(j) * nx];
          const float* HWY_RESTRICT rh = &phi[size_t(j) * nx];
          for (size_t i = 0; i < nx; ++i) {
            l[i] = std::min(l[i], rl[i]);
            h[i] = std::max(h[i], rh[i]);
          }
        }
        for (int I = 0; I < m.mi; ++I) {
          int a, b;
          range(v.nx, I, a, b);
          float cl = l[a], ch = h[a];
          for (int i = a + 1; i <= b; ++i) {
            cl = std::min(cl, l[i]);
            ch = std::max(ch, h[i]);
          }
          const size_t q = size_t(K) * plane + size_t(J) * m.mi + size_t(I);
          m.lo[q] = cl;
          m.hi[q] = ch;
        }
      }
    }
  });
  return m;
}

// The volume's macro cells, built on its first frame and kept with it.
std::shared_ptr<const MacroGrid> macro_of(const Volume& v, int threads, bool* made) {
  return v.derived->get<MacroGrid>("simd.macro", v.data.data(), v.data.size(),
                                   [&] { return build_macro(v, threads); }, made);
}

// A transfer function as a key: its control points, exactly (hex floats).
std::string tf_key(const TransferFunction& tf) {
  std::string k;
  char buf[160];
  for (const ControlPoint& p : tf.points) {
    std::snprintf(buf, sizeof buf, "%a %a %a %a %a;", p.value, double(p.r), double(p.g), double(p.b), double(p.a));
    k += buf;
  }
  return k;
}

// The part of the context every mode shares: the volume, the view, the steps.
vk::Ctx context(const Volume& v, const vr::View& view) {
  vk::Ctx c;
  c.volume = &v;
  c.view = &view;
  c.data = v.data.data();
  c.samples = int64_t(v.data.size());
  c.nx = v.nx, c.ny = v.ny, c.nz = v.nz;
  const int n[3] = {v.nx, v.ny, v.nz};
  const double sp[3] = {v.spacing.x, v.spacing.y, v.spacing.z};
  for (int a = 0; a < 3; ++a) {
    c.gmax[a] = float(n[a] - 1);
    c.imax[a] = n[a] - 2;
    c.dg[a] = view.dt * view.dir[a] / sp[a];
    c.inv_dg[a] = c.dg[a] == 0 ? 0.0f : float(1.0 / c.dg[a]);
  }
  return c;
}

void set_transfer(vk::Ctx& c, const TransferFunction& tf) {
  const auto& p = tf.points;
  c.points = int(p.size());
  c.segments = std::max(c.points - 1, 1);
  c.x_first = float(p.front().value);
  c.x_last = float(p.back().value);
  c.inner.clear();
  for (int q = 1; q + 1 < c.points; ++q) c.inner.push_back(float(p[size_t(q)].value));
  const size_t len = size_t(c.segments) + vk::kMaxLanes;
  c.seg_x.assign(len, 0);
  c.seg_w.assign(len, 1);
  for (auto& b : c.base) b.assign(len, 0);
  for (auto& d : c.delta) d.assign(len, 0);
  for (int s = 0; s < c.segments; ++s) {
    const ControlPoint& a = p[size_t(s)];
    const ControlPoint& b = c.points > 1 ? p[size_t(s) + 1] : a;
    c.seg_x[size_t(s)] = float(a.value);
    c.seg_w[size_t(s)] = c.points > 1 ? float(b.value - a.value) : 1.0f;
    const float ca[4] = {a.r, a.g, a.b, a.a}, cb[4] = {b.r, b.g, b.b, b.a};
    for (int ch = 0; ch < 4; ++ch) {
      c.base[ch][size_t(s)] = ca[ch];
      c.delta[ch][size_t(s)] = float(double(cb[ch]) - ca[ch]);
    }
  }
}

}  // namespace

bool volume_cast_handles(const Volume& v) { return v.nx >= 2 && v.ny >= 2 && v.nz >= 2; }

Image volume_raycast(const Volume& v, const FrameOptions& options, FrameStats* stats) {
  const vr::Settings s = vr::settings(options.params, v.source, vr::Mode::kRaycast);
  if (!volume_cast_handles(v))
    throw std::invalid_argument("opt::simd::volume_raycast: a volume without a cell (see volume_cast_handles)");
  const vr::View view = vr::make_view(v, s, options.width, options.height);
  vk::Ctx c = context(v, view);
  set_transfer(c, s.tf);
  c.ratio = float(view.ratio);
  c.correct = view.ratio != 1;
  c.terminate = s.eps > 0;
  c.limit = float(1 - s.eps);

  // The macro cells depend on the samples only and their transparency on the
  // transfer function too: both are kept with the volume (Volume::derived) and
  // built only when absent, so a second frame of the same volume and transfer
  // function pays nothing; build_seconds is what this frame built.
  const Stopwatch build;
  std::shared_ptr<const MacroGrid> m;
  std::shared_ptr<const std::vector<int32_t>> state;
  bool made_grid = false, made_state = false;
  if (s.skip) {
    m = macro_of(v, options.threads, &made_grid);
    const auto grid = m;
    state = v.derived->get<std::vector<int32_t>>(
        "simd.transparent " + tf_key(s.tf), v.data.data(), v.data.size(),
        [&] {
          std::vector<int32_t> st(grid->lo.size());
          for (size_t q = 0; q < st.size(); ++q) st[q] = s.tf.max_alpha(grid->lo[q], grid->hi[q]) == 0 ? 1 : 0;
          return st;
        },
        &made_state);
    c.skip = true;
    c.mi = m->mi, c.mj = m->mj, c.mk = m->mk;
    c.cell_state = state->data();
  }
  const double build_seconds = made_grid || made_state ? build.seconds() : 0.0;

  Image image = Image::uninitialized(options.width, options.height);
  std::atomic<uint64_t> skipped{0};
  parallel_tiles(options.width, options.height, 64, 4, options.threads, options.progress,
                 [&](int x0, int y0, int x1, int y1) {
                   uint64_t sk = 0;
                   for (int y = y0; y < y1; ++y) HWY_DYNAMIC_DISPATCH(vk::CastRow)(c, x0, x1, y, image.pixel(0, y), &sk);
                   skipped += sk;
                 });
  if (stats) {
    stats->items = uint64_t(view.width) * uint64_t(view.height);
    stats->build_seconds = build_seconds;
    // The samples skipped (`skipped`) are not FrameStats::skipped, whose unit is the family's (pixels).
  }
  return image;
}

Image volume_iso(const Volume& v, const FrameOptions& options, FrameStats* stats) {
  const vr::Settings s = vr::settings(options.params, v.source, vr::Mode::kIso);
  if (!volume_cast_handles(v))
    throw std::invalid_argument("opt::simd::volume_iso: a volume without a cell (see volume_cast_handles)");
  const vr::View view = vr::make_view(v, s, options.width, options.height);
  const Vec3 base = vr::iso_base(s);
  vk::Ctx c = context(v, view);
  c.iso = float(s.iso);
  c.iso_d = s.iso;

  const Stopwatch build;
  bool made_grid = false;
  const std::shared_ptr<const MacroGrid> grid = macro_of(v, options.threads, &made_grid);
  const MacroGrid& m = *grid;
  std::vector<int32_t> state(m.lo.size());
  double vmin = std::numeric_limits<double>::infinity(), vmax = -vmin;
  for (size_t q = 0; q < state.size(); ++q) {
    // Trilinear values (in double) are convex combinations: within the range,
    // up to a few ulps of rounding; a relative 1e-9 keeps clear of them.
    const double lo = m.lo[q], hi = m.hi[q];
    state[q] = hi + 1e-9 * (std::abs(hi) + 1) < s.iso ? 0 : lo - 1e-9 * (std::abs(lo) + 1) >= s.iso ? 1 : 2;
    vmin = std::min(vmin, lo);
    vmax = std::max(vmax, hi);
  }
  c.skip = true;
  c.mi = m.mi, c.mj = m.mj, c.mk = m.mk;
  c.cell_state = state.data();
  // The float value's error against the reference's double one: the float grid
  // position is within a few 2^-24 of the largest coordinate (a voxel fraction
  // delta), the interpolant's slope is at most the range per voxel per axis, and
  // the lerps round within a few ulps of the largest value. 64x and 8x those.
  const double nmax = std::max({v.nx, v.ny, v.nz});
  const double delta = 64 * std::ldexp(nmax + 1, -24);
  c.margin = float(3 * delta * (vmax - vmin) + 8 * std::ldexp(std::max(std::abs(vmin), std::abs(vmax)), -24) +
                   std::ldexp(std::abs(s.iso), -20));
  // The grid is the one-shot part; the per-iso states above are this frame's work.
  const double build_seconds = made_grid ? build.seconds() : 0.0;

  Image image(options.width, options.height);
  std::atomic<uint64_t> skipped{0};
  parallel_tiles(options.width, options.height, 64, 4, options.threads, options.progress,
                 [&](int x0, int y0, int x1, int y1) {
                   std::vector<int32_t> hit(static_cast<size_t>(x1));
                   uint64_t sk = 0;
                   for (int y = y0; y < y1; ++y) {
                     HWY_DYNAMIC_DISPATCH(vk::IsoRow)(c, x0, x1, y, hit.data(), &sk);
                     for (int x = x0; x < x1; ++x) {
                       if (hit[size_t(x)] < 0) continue;
                       // The reference's bisection and shading (reference/volume_iso.cpp).
                       const Vec3 o = vr::ray_origin(view, x, y);
                       auto above = [&](double t) { return vr::trilinear(v, o + t * view.dir) >= s.iso; };
                       const long k = hit[size_t(x)];
                       double t_lo = double(k - 1) * view.dt, t_hi = double(k) * view.dt;
                       const bool first_above = above(t_lo);
                       for (int n = 0; n < vr::kIsoBisections; ++n) {
                         const double mid = 0.5 * (t_lo + t_hi);
                         (above(mid) == first_above ? t_lo : t_hi) = mid;
                       }
                       const Vec3 p = o + (0.5 * (t_lo + t_hi)) * view.dir;
                       image.set(x, y, vr::iso_shade(base, vr::gradient(v, p), view.dir), 1.0f);
                     }
                   }
                   skipped += sk;
                 });
  if (stats) {
    stats->items = uint64_t(view.width) * uint64_t(view.height);
    stats->build_seconds = build_seconds;
    // The samples skipped (`skipped`) are not FrameStats::skipped, whose unit is the family's (pixels).
  }
  return image;
}

}  // namespace lockstep::opt::simd
#endif  // HWY_ONCE
