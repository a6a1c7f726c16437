#include "props/composite/mutants.h"

#include <cmath>

namespace lockstep::props::composite {

namespace {

enum class Bug { none, off_by_one_ulp, shift8, early_stop_eps, alpha0_nan, btf_reversed };

uint32_t mul255(uint32_t x, uint32_t a, Bug bug) {
  if (bug == Bug::shift8) return (x * a + 128) >> 8;  // the classic shortcut: / 256, not / 255
  const uint32_t t = x * a + 128;
  return (t + (t >> 8)) >> 8;
}

template <Bug bug>
Image composite(const LayerStack& st, const FrameOptions&, FrameStats* stats) {
  check_stack(st);
  const int w = st.width(), h = st.height();
  const size_t n = st.layers.size(), count = size_t(w) * size_t(h);
  Image out(w, h);
  const bool ftb = st.order == Order::front_to_back;
  for (size_t i = 0; i < count; ++i) {
    if (st.storage == Storage::unorm8) {
      auto load = [&](size_t k, uint32_t* p) {
        const uint8_t* q = &st.layers[k].rgba8[i * 4];
        const bool s = st.layers[k].alpha == Alpha::straight;
        for (int c = 0; c < 4; ++c) p[c] = s && c < 3 ? mul255(q[c], q[3], bug) : q[c];
      };
      auto over = [&](const uint32_t* f, const uint32_t* b, uint32_t* o) {
        const uint32_t t = 255 - f[3];
        for (int c = 0; c < 4; ++c) o[c] = std::min(255u, f[c] + mul255(b[c], t, bug));
      };
      uint32_t acc[4], l[4], r[4];
      if (ftb) {
        load(0, acc);
        for (size_t k = 1; k < n; ++k) {
          if (st.early_stop && acc[3] >= (bug == Bug::early_stop_eps ? 252u : 255u)) break;
          load(k, l);
          over(acc, l, r);
          std::copy(r, r + 4, acc);
        }
      } else {
        load(n - 1, acc);
        for (size_t k = n - 1; k-- > 0;) {
          load(k, l);
          if (bug == Bug::btf_reversed)
            over(acc, l, r);
          else
            over(l, acc, r);
          std::copy(r, r + 4, acc);
        }
      }
      for (int c = 0; c < 4; ++c) out.rgba[i * 4 + size_t(c)] = float(acc[c]) / 255.0f;
      continue;
    }
    auto load = [&](size_t k, float* p) {
      const float* q = &st.layers[k].image.rgba[i * 4];
      const bool s = st.layers[k].alpha == Alpha::straight;
      for (int c = 0; c < 4; ++c) p[c] = s && c < 3 ? q[c] * q[3] : q[c];
    };
    auto over = [&](const float* f, const float* b, float* o) {
      const float t = 1.0f - f[3];
      for (int c = 0; c < 4; ++c) {
        const float p = t * b[c];
        o[c] = f[c] + p;
        if (bug == Bug::off_by_one_ulp) o[c] = std::nextafter(o[c], INFINITY);
      }
    };
    float acc[4], l[4], r[4];
    if (ftb) {
      load(0, acc);
      for (size_t k = 1; k < n; ++k) {
        if (st.early_stop && acc[3] >= (bug == Bug::early_stop_eps ? 1.0f - 0x1p-10f : 1.0f)) break;
        load(k, l);
        over(acc, l, r);
        std::copy(r, r + 4, acc);
      }
    } else {
      load(n - 1, acc);
      for (size_t k = n - 1; k-- > 0;) {
        load(k, l);
        if (bug == Bug::btf_reversed)
          over(acc, l, r);
        else
          over(l, acc, r);
        std::copy(r, r + 4, acc);
      }
    }
    if (bug == Bug::alpha0_nan)  // a round trip through straight without the alpha = 0 guard
      for (int c = 0; c < 3; ++c) acc[c] = acc[c] / acc[3] * acc[3];
    std::copy(acc, acc + 4, &out.rgba[i * 4]);
  }
  if (stats) stats->items = count;
  return out;
}

}  // namespace

std::vector<Mutant> mutants() {
  return {
      {"none",
       "the textbook premultiplied path, unbroken (must pass)",
       "",
       {"mutant_none", &composite<Bug::none>, 1.5, 1, false}},
      {"off_by_one_ulp",
       "every float over rounded up one more ulp",
       "Accuracy",
       {"mutant_off_by_one_ulp", &composite<Bug::off_by_one_ulp>, 1.5, 1, false}},
      {"shift8",
       "8-bit x a / 255 as (x a + 128) >> 8",
       "RoundTrip8",
       {"mutant_shift8", &composite<Bug::shift8>, 1.5, 1, false}},
      {"early_stop_eps",
       "front-to-back stops at alpha >= 1 - 2^-10 (252 levels), not 1",
       "EarlyStop",
       {"mutant_early_stop_eps", &composite<Bug::early_stop_eps>, 1.5, 1, false}},
      {"alpha0_nan",
       "C / a * a without the alpha = 0 guard",
       "StraightClear",
       {"mutant_alpha0_nan", &composite<Bug::alpha0_nan>, 1.5, 1, false}},
      {"btf_reversed",
       "back-to-front puts the result over the next layer (order swapped)",
       "FtbEqualsBtf",
       {"mutant_btf_reversed", &composite<Bug::btf_reversed>, 1.5, 1, false}},
  };
}

}  // namespace lockstep::props::composite
