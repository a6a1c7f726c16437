// lockstep optimized: the Highway helpers the z-buffer kernels share
// (zbuffer_raster_kernels.cpp, zbuffer_setup_kernels.cpp), compiled per target.
//
// Included after hwy/highway.h in each kernel file's foreach_target.h pass, so
// once per target: the include guard toggles with HWY_TARGET_TOGGLE (Highway's
// -inl.h convention, as hwy/examples/skeleton-inl.h). Inline, so that the
// kernels that use them lose nothing to the file boundaries.

// clang-format off
#if defined(LOCKSTEP_OPTIMIZED_ZBUFFER_SIMD_KERNELS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef LOCKSTEP_OPTIMIZED_ZBUFFER_SIMD_KERNELS_INL_H_
#undef LOCKSTEP_OPTIMIZED_ZBUFFER_SIMD_KERNELS_INL_H_
#else
#define LOCKSTEP_OPTIMIZED_ZBUFFER_SIMD_KERNELS_INL_H_
#endif
// clang-format on

#include <cstddef>
#include <cstdint>

#include "hwy/highway.h"

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

}  // namespace HWY_NAMESPACE
}  // namespace lockstep::opt::zsimd
HWY_AFTER_NAMESPACE();

#endif  // LOCKSTEP_OPTIMIZED_ZBUFFER_SIMD_KERNELS_INL_H_
