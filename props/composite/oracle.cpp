// The compositing oracle: exact rational arithmetic (CGAL::Gmpq), results rounded
// once to long double through MPFR. The only translation unit of props/composite
// that includes CGAL.
#include "props/composite/oracle.h"

#include <CGAL/Gmpq.h>
#include <mpfr.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

namespace lockstep::props::composite {

namespace {

using Q = CGAL::Gmpq;
using Q4 = std::array<Q, 4>;

LD to_ld(const Q& q) {
  mpfr_t m;
  mpfr_init2(m, 64);
  mpfr_set_q(m, q.mpq(), MPFR_RNDN);
  const LD r = mpfr_get_ld(m, MPFR_RNDN);
  mpfr_clear(m);
  return r;
}

LD4 to_ld4(const Q4& q) { return {to_ld(q[0]), to_ld(q[1]), to_ld(q[2]), to_ld(q[3])}; }

Q4 q4(const float* v) {
  return {Q(double(v[0])), Q(double(v[1])), Q(double(v[2])), Q(double(v[3]))};
}

Q4 premultiplied(Q4 s) {
  for (int ch = 0; ch < 3; ++ch) s[ch] = s[ch] * s[3];
  return s;
}

// Premultiplied over, every channel: f + (1 - f.a) b.
Q4 over(const Q4& f, const Q4& b) {
  const Q t = Q(1) - f[3];
  return {f[0] + t * b[0], f[1] + t * b[1], f[2] + t * b[2], f[3] + t * b[3]};
}

bool equal(const Q4& a, const Q4& b) {
  return a[0] == b[0] && a[1] == b[1] && a[2] == b[2] && a[3] == b[3];
}

// Layer k of pixel px, exactly, converted to premultiplied.
Q4 layer(const StackCase& c, int k, int px) {
  const StackLayer& l = c.layers[size_t(k)];
  Q4 v;
  for (int ch = 0; ch < 4; ++ch) {
    const size_t i = size_t(px) * 4 + size_t(ch);
    v[ch] = c.is8() ? Q(int(l.rgba8[i]), 255) : Q(double(l.rgba[i]));
  }
  return l.alpha == Alpha::straight ? premultiplied(v) : v;
}

// Layers [lo, hi] composited front to back.
Q4 ftb(const std::vector<Q4>& L, size_t lo, size_t hi) {
  Q4 acc = L[lo];
  for (size_t k = lo + 1; k <= hi; ++k) acc = over(acc, L[k]);
  return acc;
}

Q4 btf(const std::vector<Q4>& L, size_t lo, size_t hi) {
  Q4 r = L[hi];
  for (size_t k = hi; k-- > lo;) r = over(L[k], r);
  return r;
}

}  // namespace

PixelTruth truth(const StackCase& c, int px, double eps, bool groupings) {
  const size_t n = c.layers.size();
  std::vector<Q4> L;
  for (size_t k = 0; k < n; ++k) L.push_back(layer(c, int(k), px));
  PixelTruth t;

  const Q4 f = ftb(L, 0, n - 1), b = btf(L, 0, n - 1);
  t.exact_agree = equal(f, b);
  for (size_t j = 0; groupings && j + 1 < n; ++j)
    t.exact_agree = t.exact_agree && equal(f, over(ftb(L, 0, j), btf(L, j + 1, n - 1)));

  const Q scale = c.is8() ? Q(255) : Q(1);
  Q4 value = f;
  for (auto& v : value) v = v * scale;
  t.value = to_ld4(value);

  // The largest term, and the first layer where the exact alpha reaches 1 - eps.
  const Q one_minus_eps = Q(1) - Q(eps) / scale;
  Q T = 1;  // exact transmittance in front of layer k
  Q4 acc = L[0];
  bool found = false;
  std::vector<Q> Tk(n);
  for (size_t k = 0; k < n; ++k) {
    Tk[k] = T;
    const bool straight = c.layers[k].alpha == Alpha::straight;
    for (int ch = 0; ch < 4; ++ch) {
      const Q term = L[k][ch] * scale;
      LD u = std::fabs(to_ld(term)), w = std::fabs(to_ld(term * T));
      if (straight && ch < 3) {
        const LD under = std::fabs(LD(c.value(int(k), px, ch))) * LD(0x1p-126) * to_ld(scale);
        u = std::max(u, under), w = std::max(w, under);
      }
      t.floor[ch] = std::max(t.floor[ch], u);
      t.floor_w[ch] = std::max(t.floor_w[ch], w);
      if (!found) {
        t.floor_visible[ch] = std::max(t.floor_visible[ch], u);
        t.floor_visible_w[ch] = std::max(t.floor_visible_w[ch], w);
      }
    }
    if (k > 0) acc = over(acc, L[k]);
    if (!found && (k + 1 == n || acc[3] >= one_minus_eps)) {
      found = true;
      t.stop = int(k);
    }
    T = T * (Q(1) - L[k][3]);
  }
  for (size_t k = size_t(t.stop) + 1; k < n; ++k) {
    const LD slack = c.is8() ? LD(k) * 0.5L / 255 : LD(2 * k) * LD(kU);
    for (int ch = 0; ch < 4; ++ch)
      t.hidden_max[ch] +=
          std::min<LD>(1, to_ld(Tk[k]) + slack) * std::fabs(to_ld(L[k][ch] * scale));
  }
  const Q4 vis = ftb(L, 0, size_t(t.stop));
  Q4 visible = vis, hidden;
  for (int ch = 0; ch < 4; ++ch) {
    visible[ch] = vis[ch] * scale;
    hidden[ch] = value[ch] - visible[ch];
  }
  t.visible = to_ld4(visible);
  t.hidden = to_ld4(hidden);
  t.alpha_stop = to_ld(visible[3]);

  t.all_alpha_zero =
      std::all_of(L.begin(), L.end(), [](const Q4& q) { return CGAL::is_zero(q[3]); });
  if (CGAL::sign(f[3]) > 0)
    for (int ch = 0; ch < 3; ++ch) t.straight[ch] = to_ld(f[ch] / f[3] * scale);
  return t;
}

const char* reference_straight_loss(const StackCase& c, int px) {
  const size_t n = c.layers.size();
  if (c.is8()) return "";  // 8 bits: premultiplied throughout
  // A stack with any premultiplied layer is composited premultiplied throughout
  // (straight layers premultiplied as read): no straight accumulator, no loss.
  for (size_t k = 0; k < n; ++k)
    if (c.layers[k].alpha == Alpha::premultiplied) return "";
  std::vector<Q4> raw(n);
  for (size_t k = 0; k < n; ++k)
    for (int ch = 0; ch < 4; ++ch) raw[k][ch] = Q(double(c.value(int(k), px, ch)));
  const bool ftb_order = c.order == Order::front_to_back;
  const size_t first = ftb_order ? 0 : n - 1;
  Q4 acc = raw[first];
  Alpha rep = c.layers[first].alpha;
  const char* loss = "";
  const Q big(double(3.4028234663852886e38)), tiny(0x1p-102);
  for (size_t s = 1; s < n; ++s) {
    const size_t k = ftb_order ? s : n - 1 - s;
    if (ftb_order && c.early_stop && acc[3] == Q(1)) break;
    const Alpha want = c.layers[k].alpha;
    if (rep != want) {
      if (want == Alpha::straight) {  // premultiplied -> straight
        const bool colour =
            !CGAL::is_zero(acc[0]) || !CGAL::is_zero(acc[1]) || !CGAL::is_zero(acc[2]);
        if (CGAL::is_zero(acc[3])) {
          if (colour && !*loss) loss = "additive_at_alpha0";
          acc = {0, 0, 0, 0};
        } else {
          for (int ch = 0; ch < 3; ++ch) {
            acc[ch] = acc[ch] / acc[3];
            if (CGAL::abs(acc[ch]) > big && !*loss) loss = "straight_overflow";
          }
          if (colour && acc[3] < tiny && !*loss) loss = "subnormal_alpha";
        }
      } else {
        acc = premultiplied(acc);
      }
      rep = want;
    }
    const Q4 f = ftb_order ? acc : raw[k], b = ftb_order ? raw[k] : acc;
    if (rep == Alpha::premultiplied) {
      acc = over(f, b);
    } else {  // the straight formula; alpha 0 -> (0, 0, 0, 0)
      const Q4 p = over(premultiplied(f), premultiplied(b));
      if (CGAL::is_zero(p[3]))
        acc = {0, 0, 0, 0};
      else
        acc = {p[0] / p[3], p[1] / p[3], p[2] / p[3], p[3]};
    }
  }
  return loss;
}

LD4 exact_over_premultiplied(const float* f, const float* b) { return to_ld4(over(q4(f), q4(b))); }

LD4 exact_over_straight(const float* f, const float* b) {
  const Q4 p = over(premultiplied(q4(f)), premultiplied(q4(b)));
  if (CGAL::is_zero(p[3])) return {0, 0, 0, 0};
  return {to_ld(p[0] / p[3]), to_ld(p[1] / p[3]), to_ld(p[2] / p[3]), to_ld(p[3])};
}

LD4 exact_premultiply(const float* s) { return to_ld4(premultiplied(q4(s))); }

bool exact_associative(const float* a, const float* b, const float* c, LD4* value) {
  const Q4 A = q4(a), B = q4(b), C = q4(c);
  const Q4 l = over(over(A, B), C), r = over(A, over(B, C));
  if (value) *value = to_ld4(l);
  return equal(l, r);
}

LD exact_mul255(int x, int a) { return to_ld(Q(x * a, 255)); }

int nearest_mul255(int x, int a) { return (2 * x * a + 255) / 510; }

bool is_nearest_unpremultiply8(int p, int a, int got) {
  // |got - p 255/a| <= 1/2  <=>  |2 a got - 510 p| <= a
  return std::abs(2 * a * got - 510 * p) <= a;
}

int round_trip8_bound(int a) {
  if (a <= 0) return 255;
  // floor(1/2 + 127.5/a) = floor((a + 255) / (2a))
  return (a + 255) / (2 * a);
}

LD ulp32(LD x) {
  x = std::fabs(x);
  if (!(x >= LD(0x1p-126))) return LD(0x1p-149);
  if (std::isinf(x)) return LD(INFINITY);
  int e = 0;
  std::frexp(x, &e);  // x = m 2^e, m in [0.5, 1): x in [2^(e-1), 2^e)
  return std::ldexp(LD(1), e - 1 - 23);
}

double err_ulps(float got, LD exact, LD floor) {
  if (!std::isfinite(got)) return INFINITY;
  const LD scale = std::max({std::fabs(exact), std::fabs(floor), LD(0x1p-126)});
  return double(std::fabs(LD(got) - exact) / ulp32(scale));
}

}  // namespace lockstep::props::composite
