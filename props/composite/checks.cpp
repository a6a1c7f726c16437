#include "props/composite/checks.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "registry/registry.h"
#include "props/composite/oracle.h"
#include "reference/composite.h"

namespace lockstep::props::composite {

std::vector<CompositeSubject> subjects_of(const Family& f) {
  // float_ulps: per over (checks.h: derived 1.5 for premultiplied over, 3 for the
  // reference's straight formula), stated in the row; levels8: the family's
  // agreement tolerance (1/255 + 1e-6: one level; measured 0: every
  // implementation rounds x a / 255 exactly, the same way).
  const int levels8 = int(std::floor(f.tol.abs * 255));
  std::vector<CompositeSubject> out;
  for (size_t i = 0; i < f.impls.size(); ++i) {
    const FamilyImpl& im = f.impls[i];
    auto fn = [im](const LayerStack& st, const FrameOptions& o, FrameStats* s) {
      const int w = st.width(), h = st.height();
      return im.run_as<Image>(make_input<LayerStack>(st, "props/composite", w, h), o, s);
    };
    out.push_back({std::string(im.name), fn, im.accuracy, i == 0 ? 0 : levels8, i == 0});
  }
  return out;
}

const std::vector<CompositeSubject>& composite_subjects() {
  static const std::vector<CompositeSubject> s = [] {
    const Family* f = registry().find("composite");
    if (!f) throw std::runtime_error("the registry has no family 'composite'");
    return subjects_of(*f);
  }();
  return s;
}

namespace {

constexpr LD kFltMin = LD(0x1p-126);

// ---------------------------------------------------------------- running

FrameOptions options(const StackCase& c) {
  FrameOptions o;
  o.width = c.width;
  o.height = c.height;
  o.threads = 1;
  return o;
}

Image run(const CompositeSubject& s, const StackCase& c) {
  FrameStats stats;
  Image img = s.fn(c.to_stack(), options(c), &stats);
  if (img.width != c.width || img.height != c.height || img.rgba.size() != size_t(c.pixels()) * 4)
    throw std::runtime_error(s.name + ": output size differs from the stack's");
  return img;
}

const float* px_of(const Image& img, int px) { return img.rgba.data() + size_t(px) * 4; }

// The 8-bit level q of an output value q / 255; -1 when it is not exactly one.
int level_of(float v) {
  if (!std::isfinite(v)) return -1;
  const long q = std::lround(double(v) * 255.0);
  if (q < 0 || q > 255 || float(q) / 255.0f != v) return -1;
  return int(q);
}

// Output channel in the case's units (values, or levels; NaN when not a level).
LD unit_value(const StackCase& c, float v) {
  if (!c.is8()) return LD(v);
  const int q = level_of(v);
  return q < 0 ? LD(NAN) : LD(q);
}

double eps_of(const StackCase& c) {
  const double n = double(c.layers.size());
  return c.is8() ? 0.5 * (n - 1) : 2 * n * kU;
}

// ---------------------------------------------------------------- text for details

std::string ld(LD x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.21Lg", x);
  return buf;
}
std::string ld4(const LD4& v) {
  return "(" + ld(v[0]) + ", " + ld(v[1]) + ", " + ld(v[2]) + ", " + ld(v[3]) + ")";
}
std::string g(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g", x);
  return buf;
}

std::string input_text(const StackCase& c, int px) {
  std::ostringstream o;
  o << "pixel " << px << " (" << px % c.width << "," << px / c.width << ") of " << c.width << "x"
    << c.height << ", " << name_of(c.order) << ", " << name_of(c.storage) << ", early_stop "
    << c.early_stop << "; layers front first:";
  for (size_t k = 0; k < c.layers.size(); ++k) {
    const StackLayer& l = c.layers[k];
    o << "\n    " << k << " " << name_of(l.alpha) << " "
      << (c.is8() ? lev4(&l.rgba8[size_t(px) * 4]) : hex4(&l.rgba[size_t(px) * 4]));
  }
  return o.str();
}

std::string out_text(const StackCase& c, const float* o) {
  if (!c.is8()) return hex4(o);
  std::string s = "levels (";
  for (int ch = 0; ch < 4; ++ch) s += (ch ? ", " : "") + std::to_string(level_of(o[ch]));
  return s + ") = " + hex4(o);
}

// ---------------------------------------------------------------- judging one pixel

struct PixelErr {
  double err = 0;  // largest channel error: ulps (float) or levels (8 bits)
  bool within = true;
  bool finite = true;
  std::string per_channel;
};

// Output o against exact values in the case's units; float: ulps of max(|exact|, floor, 2^-126)
// within bound_f; 8 bits: levels within bound8(ch) + extra8.
PixelErr judge(const StackCase& c, const float* o, const LD4& exact, const LD4& floor,
               double bound_f, int px, const StackCase* bound_case = nullptr, double extra8 = 0) {
  PixelErr r;
  for (int ch = 0; ch < 4; ++ch) {
    double e, b;
    if (!std::isfinite(o[ch])) r.finite = false;
    if (c.is8()) {
      const LD q = unit_value(c, o[ch]);
      e = std::isnan(q) ? INFINITY : double(std::fabs(q - exact[ch]));
      b = bound8(bound_case ? *bound_case : c, px, ch) + extra8 + 1e-9;
    } else {
      e = err_ulps(o[ch], exact[ch], floor[ch]);
      b = bound_f;
    }
    r.err = std::max(r.err, e);
    if (!(e <= b)) r.within = false;
    r.per_channel += (ch ? ", " : "") + g(e) + (c.is8() ? "" : "") + "/" + g(b);
  }
  r.per_channel =
      std::string(c.is8() ? "levels" : "ulps") + " (err/bound per channel) " + r.per_channel;
  return r;
}

Outcome make(Outcome::Kind k, std::string label, double err, std::string detail) {
  Outcome o;
  o.kind = k;
  o.label = std::move(label);
  o.err = err;
  o.measured = true;
  o.detail = std::move(detail);
  return o;
}

const CompositeSubject& reference_subject() { return composite_subjects().front(); }

// The reference's straight-accumulator loss at this pixel (oracle.h), "" for other subjects.
std::string ref_loss(const CompositeSubject& s, const StackCase& c, int px) {
  return s.is_reference ? reference_straight_loss(c, px) : "";
}

bool finite4(const float* o) {
  return std::isfinite(o[0]) && std::isfinite(o[1]) && std::isfinite(o[2]) && std::isfinite(o[3]);
}

// Case with every layer reinterpreted as straight alpha (the values are kept).
StackCase all_straight(const StackCase& c) {
  StackCase s = c;
  for (StackLayer& l : s.layers) l.alpha = Alpha::straight;
  return s;
}

// Layers [lo, hi] of c as a case of their own.
StackCase sub(const StackCase& c, size_t lo, size_t hi) {
  StackCase s = c;
  s.layers.assign(c.layers.begin() + long(lo), c.layers.begin() + long(hi) + 1);
  return s;
}

// An output image as a premultiplied layer of a case like c (8 bits: its levels).
StackLayer as_layer(const StackCase& c, const Image& img) {
  StackLayer l;
  l.alpha = Alpha::premultiplied;
  if (c.is8()) {
    for (float v : img.rgba) l.rgba8.push_back(uint8_t(std::max(0, level_of(v))));
  } else {
    l.rgba.assign(img.rgba.begin(), img.rgba.end());
  }
  return l;
}

std::string bucket(int a) {
  if (a == 0) return "a0";
  if (a < 16) return "a1-15";
  if (a < 64) return "a16-63";
  if (a < 128) return "a64-127";
  if (a < 255) return "a128-254";
  return "a255";
}

}  // namespace

// ---------------------------------------------------------------- the 8-bit bound

double bound8(const StackCase& c, int px, int ch) {
  const size_t n = c.layers.size();
  // Exact inputs in levels: alpha a_k, premultiplied colour c_k (straight: c a / 255, exact).
  std::vector<double> a(n), col(n), d(n);
  for (size_t k = 0; k < n; ++k) {
    const uint8_t* p = &c.layers[k].rgba8[size_t(px) * 4];
    const bool straight = c.layers[k].alpha == Alpha::straight;
    a[k] = p[3];
    col[k] = ch == 3 ? p[3] : (straight ? double(p[ch]) * p[3] / 255.0 : p[ch]);
    d[k] = straight && ch < 3 ? 0.5 : 0.0;
  }
  double bound = 0, T = 1;
  if (c.order == Order::back_to_front) {
    for (size_t k = 0; k < n; ++k) {
      bound += T * ((k + 1 < n ? 0.5 : 0.0) + d[k]);
      T *= 1 - a[k] / 255;
    }
    return bound;
  }
  double e = 0;  // bound on the accumulated alpha's error before layer k
  for (size_t k = 0; k < n; ++k) {
    if (k > 0) bound += 0.5 + e * col[k] / 255;
    bound += T * d[k];
    if (k > 0) e = e * (1 - a[k] / 255) + 0.5;
    T *= 1 - a[k] / 255;
  }
  return ch == 3 ? e : bound;
}

// ---------------------------------------------------------------- accuracy

Verdict check_accuracy(const CompositeSubject& s, const StackCase& c) {
  Verdict v;
  const Image out = run(s, c);
  for (int px = 0; px < c.pixels(); ++px) {
    const PixelTruth t = truth(c, px, eps_of(c));
    const float* o = px_of(out, px);
    const PixelErr e =
        judge(c, o, t.value, floor_for(t, c.order), float_bound(s, c.layers.size()), px);
    const bool good = e.within && e.finite;
    const std::string loss = good || !e.finite ? "" : ref_loss(s, c, px);
    v.rays.push_back(
        make(good ? Outcome::ok : (loss.empty() ? Outcome::unexplained : Outcome::explained),
             good ? "ok"
                  : (!loss.empty() ? loss
                     : e.finite    ? "accuracy"
                                   : "nan"),
             e.err,
             "accuracy of " + s.name + ": " + input_text(c, px) + "\n  got    " + out_text(c, o) +
                 "\n  oracle " + ld4(t.value) + "\n  " + e.per_channel));
  }
  return v;
}

// ---------------------------------------------------------------- agreement with the reference

Verdict check_agreement(const CompositeSubject& s, const StackCase& c) {
  Verdict v;
  const Image out = run(s, c);
  const Image ref = ref::composite(c.to_stack(), options(c), nullptr);
  const double bound_f =
      float_bound(s, c.layers.size()) + float_bound(reference_subject(), c.layers.size());
  for (int px = 0; px < c.pixels(); ++px) {
    const PixelTruth t = truth(c, px, eps_of(c));
    const float* o = px_of(out, px);
    const float* r = px_of(ref, px);
    double err = 0;
    bool good = true;
    std::string per;
    for (int ch = 0; ch < 4; ++ch) {
      double e, b;
      if (c.is8()) {
        const int qo = level_of(o[ch]), qr = level_of(r[ch]);
        e = qo < 0 || qr < 0 ? INFINITY : std::abs(qo - qr);
        b = s.levels8;
      } else {
        const LD scale = std::max({std::fabs(t.value[ch]), floor_for(t, c.order)[ch], kFltMin});
        e = std::isfinite(o[ch]) && std::isfinite(r[ch])
                ? double(std::fabs(LD(o[ch]) - LD(r[ch])) / ulp32(scale))
                : INFINITY;
        b = bound_f;
      }
      err = std::max(err, e);
      if (!(e <= b)) good = false;
      per += (ch ? ", " : "") + g(e) + "/" + g(b);
    }
    const std::string loss = good || !finite4(o) || !finite4(r)
                                 ? ""
                                 : std::string(c.is8() ? "" : reference_straight_loss(c, px));
    v.rays.push_back(make(
        good ? Outcome::ok : (loss.empty() ? Outcome::unexplained : Outcome::explained),
        good ? "ok" : (loss.empty() ? "agreement" : "reference_" + loss), err,
        "agreement of " + s.name + " with the reference: " + input_text(c, px) + "\n  got       " +
            out_text(c, o) + "\n  reference " + out_text(c, r) + "\n  oracle    " + ld4(t.value) +
            "\n  " + (c.is8() ? "levels" : "ulps") + " (diff/bound per channel) " + per));
  }
  return v;
}

// ---------------------------------------------------------------- straight vs premultiplied

Verdict check_straight_vs_premultiplied(const CompositeSubject& s, const StackCase& c) {
  Verdict v;
  const StackCase S = all_straight(c);
  StackCase P = S;
  for (StackLayer& l : P.layers) {
    l.alpha = Alpha::premultiplied;
    for (int px = 0; px < c.pixels(); ++px) {
      if (c.is8()) {
        uint8_t* q = &l.rgba8[size_t(px) * 4];
        const Rgba8 m = ref::premultiply8({q[0], q[1], q[2], q[3]});
        q[0] = m.r, q[1] = m.g, q[2] = m.b, q[3] = m.a;
      } else {
        float* f = &l.rgba[size_t(px) * 4];
        const Rgba m = ref::premultiply({f[0], f[1], f[2], f[3]});
        f[0] = m.r, f[1] = m.g, f[2] = m.b, f[3] = m.a;
      }
    }
  }
  const Image outS = run(s, S), outP = run(s, P);
  const double b = float_bound(s, c.layers.size());
  for (int px = 0; px < c.pixels(); ++px) {
    const PixelTruth t = truth(S, px, eps_of(S));
    const LD4& floor = floor_for(t, S.order);
    const float* oS = px_of(outS, px);
    const float* oP = px_of(outP, px);
    // Premultiplied results: each within its accuracy bound (P: +1 ulp for its premultiply).
    const PixelErr eS = judge(S, oS, t.value, floor, b, px);
    const PixelErr eP = judge(S, oP, t.value, floor, b + 0.5, px, &S);
    std::string detail = "straight vs premultiplied, " + s.name + ": " + input_text(S, px) +
                         "\n  straight stack       " + out_text(S, oS) +
                         "\n  premultiplied stack  " + out_text(S, oP) + "\n  oracle " +
                         ld4(t.value) + "\n  straight: " + eS.per_channel +
                         "\n  premultiplied: " + eP.per_channel;
    if (!(eS.within && eP.within && eS.finite && eP.finite)) {
      v.rays.push_back(make(Outcome::unexplained, eS.finite && eP.finite ? "accuracy" : "nan",
                            std::max(eS.err, eP.err), detail));
      continue;
    }
    // After conversion to straight, wherever alpha > 0.
    // (8 bits: ok outcomes carry the output alpha's bucket, so that the loss rate per bucket shows)
    Outcome::Kind kind = Outcome::ok;
    std::string label = c.is8() && level_of(oS[3]) > 0 ? bucket(level_of(oS[3])) : "ok";
    double worst = 0;
    for (int which = 0; which < 2; ++which) {
      const float* o = which ? oP : oS;
      const double bw = which ? b + 0.5 : b;
      if (c.is8()) {
        const int qa = level_of(o[3]);
        const Rgba8 st = ref::unpremultiply8({uint8_t(level_of(o[0])), uint8_t(level_of(o[1])),
                                              uint8_t(level_of(o[2])), uint8_t(qa)});
        const uint8_t sc[3] = {st.r, st.g, st.b};
        const double Ba = bound8(S, px, 3);
        for (int ch = 0; ch < 3 && t.value[3] > 0; ++ch) {
          if (qa == 0) {  // the exact alpha rounded to 0: the colour is gone
            if (t.value[3] <= Ba && kind == Outcome::ok)
              kind = Outcome::explained, label = "alpha_rounds_to_0";
            if (t.value[3] > Ba) kind = Outcome::unexplained, label = "alpha_lost";
            continue;
          }
          const double sstar = double(t.straight[ch]);
          const double err = std::fabs(sc[ch] - sstar);
          // The straight error: 255 (dC - s* da / 255) / a_out, rounded (+1/2). At a_out = 255
          // it is the composite's own rounding; beyond that, the 255/a_out amplification
          // is the premultiplied representation's loss.
          const double bound = 255 * (bound8(S, px, ch) + sstar * Ba / 255) / qa + 0.5 + 1e-9;
          const double at255 = std::max(1.0, bound8(S, px, ch) + sstar * Ba / 255 + 0.5 + 1e-9);
          detail += "\n  " + std::string(which ? "premultiplied" : "straight") + " ch" +
                    std::to_string(ch) + ": unpremultiply8 " + std::to_string(sc[ch]) +
                    " vs exact " + ld(t.straight[ch]) + " (loss " + g(err) + ", bound " + g(bound) +
                    " at a=" + std::to_string(qa) + ")";
          worst = std::max(worst, err);
          if (err <= at255) continue;
          if (err <= bound) {
            if (kind == Outcome::ok)
              kind = Outcome::explained, label = "premul8_loss_" + bucket(qa);
          } else {
            kind = Outcome::unexplained, label = "straight_after_conversion";
          }
        }
      } else {
        const LD a = o[3];
        for (int ch = 0; ch < 3 && t.value[3] > 0 && a > 0; ++ch) {
          const LD sg = LD(o[ch]) / a, sstar = t.straight[ch];
          const LD dC = bw * ulp32(std::max({std::fabs(t.value[ch]), floor[ch], kFltMin}));
          const LD da = bw * ulp32(std::max({t.value[3], floor[3], kFltMin}));
          const LD bound = (dC + std::fabs(sstar) * da) / a * 1.0001L;
          const LD err = std::fabs(sg - sstar);
          const double ulps = double(err / ulp32(std::max(std::fabs(sstar), kFltMin)));
          worst = std::max(worst, ulps);
          detail += "\n  " + std::string(which ? "premultiplied" : "straight") + " ch" +
                    std::to_string(ch) + ": straight " + ld(sg) + " vs exact " + ld(sstar) + " (" +
                    g(ulps) + " ulps, bound " + ld(bound) + ")";
          if (ulps <= 4 * (bw + 1)) continue;
          if (err <= bound) {
            if (kind == Outcome::ok) {
              kind = Outcome::explained;
              label = std::max(t.value[3], t.value[ch]) < kFltMin * 0x1p24L ? "subnormal_alpha"
                      : floor[ch] > std::fabs(t.value[ch])                  ? "hidden_term_floor"
                                                                            : "small_alpha";
            }
          } else {
            kind = Outcome::unexplained, label = "straight_after_conversion";
          }
        }
      }
    }
    Outcome oc = make(kind, label, std::max(eS.err, eP.err), detail);
    v.rays.push_back(oc);
    (void)worst;
  }
  return v;
}

// ---------------------------------------------------------------- front-to-back == back-to-front

Verdict check_ftb_equals_btf(const CompositeSubject& s, const StackCase& c) {
  Verdict v;
  const StackCase F = c.with_order(Order::front_to_back), B = c.with_order(Order::back_to_front);
  const Image oF = run(s, F), oB = run(s, B);
  for (int px = 0; px < c.pixels(); ++px) {
    const PixelTruth t = truth(c, px, eps_of(c), true);
    const float* f = px_of(oF, px);
    const float* b = px_of(oB, px);
    const PixelErr eF = judge(F, f, t.value, t.floor, float_bound(s, c.layers.size()), px);
    const PixelErr eB = judge(B, b, t.value, t.floor_w, float_bound(s, c.layers.size()), px);
    double diff = 0;
    bool good = t.exact_agree && eF.within && eB.within && eF.finite && eB.finite;
    std::string per;
    for (int ch = 0; ch < 4; ++ch) {
      double d, bound;
      if (c.is8()) {
        d = std::fabs(double(unit_value(c, f[ch]) - unit_value(c, b[ch])));
        bound = bound8(F, px, ch) + bound8(B, px, ch) + 1e-9;
      } else {
        d = double(std::fabs(LD(f[ch]) - LD(b[ch])) /
                   ulp32(std::max({std::fabs(t.value[ch]), t.floor[ch], kFltMin})));
        bound = 2 * float_bound(s, c.layers.size());
      }
      if (!(d <= bound)) good = false;
      diff = std::max(diff, d);
      per += (ch ? ", " : "") + g(d) + "/" + g(bound);
    }
    std::string loss;
    if (!good && t.exact_agree && finite4(f) && finite4(b)) {
      loss = ref_loss(s, F, px);
      if (loss.empty()) loss = ref_loss(s, B, px);
    }
    v.rays.push_back(make(
        good ? Outcome::ok : (loss.empty() ? Outcome::unexplained : Outcome::explained),
        good                         ? "ok"
        : !loss.empty()              ? loss
        : !finite4(f) || !finite4(b) ? std::string("nan")
                                     : (t.exact_agree ? "ftb_vs_btf" : "oracle_not_associative"),
        diff,
        "ftb vs btf, " + s.name + ": " + input_text(c, px) + "\n  ftb    " + out_text(c, f) +
            "\n  btf    " + out_text(c, b) + "\n  oracle " + ld4(t.value) +
            (t.exact_agree ? " (ftb == btf exactly)" : " (ORACLE: ftb != btf)") +
            "\n  ftb: " + eF.per_channel + "\n  btf: " + eB.per_channel +
            "\n  |ftb - btf| (diff/bound per channel) " + per));
  }
  return v;
}

// ---------------------------------------------------------------- associativity

Verdict check_associativity(const CompositeSubject& s, const StackCase& c) {
  Verdict v;
  const size_t n = c.layers.size();
  // Every two-way grouping: (0..j) as one premultiplied layer over the rest, and
  // the rest as one layer under 0..j; each composited by the subject itself.
  struct Grouped {
    std::string what;
    StackCase outer;
    StackCase inner;
    Image out;
  };
  std::vector<Grouped> groups;
  for (size_t j = 0; j + 1 < n; ++j) {
    const StackCase front = sub(c, 0, j), back = sub(c, j + 1, n - 1);
    StackCase left = back;
    left.layers.insert(left.layers.begin(), as_layer(c, run(s, front)));
    StackCase right = front;
    right.layers.push_back(as_layer(c, run(s, back)));
    groups.push_back({"(0.." + std::to_string(j) + ") over rest", left, front, run(s, left)});
    groups.push_back({"0.." + std::to_string(j) + " over (rest)", right, back, run(s, right)});
  }
  for (int px = 0; px < c.pixels(); ++px) {
    const PixelTruth t = truth(c, px, eps_of(c), true);
    bool good = t.exact_agree;
    double err = 0;
    std::string label = t.exact_agree ? "ok" : "oracle_not_associative";
    std::string detail =
        "associativity, " + s.name + ": " + input_text(c, px) + "\n  oracle " + ld4(t.value) +
        (t.exact_agree ? " (every grouping equal exactly)" : " (ORACLE: groupings differ)");
    for (const Grouped& gr : groups) {
      const float* o = px_of(gr.out, px);
      PixelErr e;
      if (c.is8()) {
        // inner's error passes through the outer stack with weight <= 1: the two bounds add.
        double worst = 0;
        bool within = true;
        for (int ch = 0; ch < 4; ++ch) {
          const LD q = unit_value(c, o[ch]);
          const double d = std::isnan(q) ? INFINITY : double(std::fabs(q - t.value[ch]));
          // the inner result's alpha error also scales the colour behind it (<= 255 levels)
          const double b = bound8(gr.inner, px, ch) + (ch < 3 ? bound8(gr.inner, px, 3) : 0) +
                           bound8(gr.outer, px, ch) + 1e-9;
          worst = std::max(worst, d);
          if (!(d <= b)) within = false;
          e.per_channel += (ch ? ", " : "") + g(d) + "/" + g(b);
        }
        e.err = worst;
        e.within = within;
      } else {
        e = judge(c, o, t.value, t.floor, 3 * float_bound(s, c.layers.size()), px);
      }
      err = std::max(err, e.err);
      detail += "\n  " + gr.what + ": " + out_text(c, o) + "  " + e.per_channel;
      if (!e.within || !e.finite) {
        std::string loss;
        if (e.finite) {
          loss = ref_loss(s, c, px);
          if (loss.empty()) loss = ref_loss(s, gr.inner, px);
          if (loss.empty()) loss = ref_loss(s, gr.outer, px);
        }
        if (loss.empty())
          good = false, label = e.finite ? "grouping" : "nan";
        else if (good && label == "ok")
          label = loss;
      }
    }
    // The textbook kernel itself, on consecutive triples (float values; 8-bit cases as q / 255).
    if (s.is_reference) {
      for (size_t k = 0; k + 2 < n; ++k) {
        float L[3][4];
        for (int m = 0; m < 3; ++m) {
          for (int ch = 0; ch < 4; ++ch) L[m][ch] = c.value(int(k) + m, px, ch);
          if (c.layers[k + size_t(m)].alpha == Alpha::straight) {
            const Rgba p = ref::premultiply({L[m][0], L[m][1], L[m][2], L[m][3]});
            L[m][0] = p.r, L[m][1] = p.g, L[m][2] = p.b;
          }
        }
        auto rgba = [](const float* f) { return Rgba{f[0], f[1], f[2], f[3]}; };
        const Rgba l =
            ref::over_premultiplied(ref::over_premultiplied(rgba(L[0]), rgba(L[1])), rgba(L[2]));
        const Rgba r =
            ref::over_premultiplied(rgba(L[0]), ref::over_premultiplied(rgba(L[1]), rgba(L[2])));
        LD4 exact;
        const bool same = exact_associative(L[0], L[1], L[2], &exact);
        const float lv[4] = {l.r, l.g, l.b, l.a}, rv[4] = {r.r, r.g, r.b, r.a};
        for (int ch = 0; ch < 4; ++ch) {
          const LD largest = std::max({LD(L[0][ch]), LD(L[1][ch]), LD(L[2][ch])});
          const double el = err_ulps(lv[ch], exact[ch], largest),
                       er = err_ulps(rv[ch], exact[ch], largest);
          const LD scale = std::max({std::fabs(exact[ch]), largest, kFltMin});
          const double d = double(std::fabs(LD(lv[ch]) - LD(rv[ch])) / ulp32(scale));
          if (!same || !(el <= kAssocUlps / 2) || !(er <= kAssocUlps / 2) || !(d <= kAssocUlps)) {
            good = false;
            label = same ? "kernel_associativity" : "oracle_not_associative";
            detail += "\n  kernel layers " + std::to_string(k) + ".." + std::to_string(k + 2) +
                      " ch" + std::to_string(ch) + ": (ab)c " + hexf(lv[ch]) + " a(bc) " +
                      hexf(rv[ch]) + " exact " + ld(exact[ch]) + " errs " + g(el) + ", " + g(er) +
                      " diff " + g(d) + " ulps";
          }
        }
      }
    }
    v.rays.push_back(
        make(good ? (label == "ok" ? Outcome::ok : Outcome::explained) : Outcome::unexplained,
             label, err, detail));
  }
  return v;
}

// ---------------------------------------------------------------- early termination

Verdict check_early_stop(const CompositeSubject& s, const StackCase& c) {
  Verdict v;
  const Image on = run(s, c.with_early_stop(true)), off = run(s, c.with_early_stop(false));
  const double eps = eps_of(c);
  for (int px = 0; px < c.pixels(); ++px) {
    const PixelTruth t = truth(c, px, eps);
    const float* o = px_of(on, px);
    const float* f = px_of(off, px);
    std::string detail = "early stop, " + s.name + ": " + input_text(c, px) +
                         "\n  early_stop on  " + out_text(c, o) + "\n  early_stop off " +
                         out_text(c, f) + "\n  oracle " + ld4(t.value) + "\n  visible (layers 0.." +
                         std::to_string(t.stop) + ", exact alpha " + ld(t.alpha_stop) + ") " +
                         ld4(t.visible) + "\n  hidden " + ld4(t.hidden) + " (could add at most " +
                         ld4(t.hidden_max) + ")";
    bool same = true;
    for (int ch = 0; ch < 4; ++ch)
      same = same && std::bit_cast<uint32_t>(o[ch]) == std::bit_cast<uint32_t>(f[ch]);
    if (!same) {
      v.rays.push_back(make(Outcome::unexplained, "early_stop_changed", INFINITY, detail));
      continue;
    }
    // The stated bound on H: H <= eps * (sum of the hidden layers' colours), when the stop is
    // before the end.
    bool h_ok = true;
    if (t.stop + 1 < int(c.layers.size())) {
      for (int ch = 0; ch < 4; ++ch) {
        LD sum = 0;
        for (size_t k = size_t(t.stop) + 1; k < c.layers.size(); ++k) {
          const bool st = c.layers[k].alpha == Alpha::straight && ch < 3;
          const LD val = c.is8() ? LD(c.layers[k].rgba8[size_t(px) * 4 + size_t(ch)])
                                 : LD(c.value(int(k), px, ch));
          const LD alpha = c.is8() ? LD(c.layers[k].rgba8[size_t(px) * 4 + 3]) / 255
                                   : LD(c.value(int(k), px, 3));
          sum += st ? val * alpha : val;
        }
        const LD one = c.is8() ? 255 : 1;
        const LD T = (one - t.alpha_stop) / one;
        // (long double slack: alpha_stop was rounded once to 64 bits, so 1 - alpha_stop carries
        // 2^-64 absolute)
        if (!(t.hidden[ch] <= T * sum * (1 + 1e-9L) + 1e-40L) ||
            !(T <= LD(eps) / one * (1 + 1e-9L)))
          h_ok = false;
      }
    }
    double err = 0;
    Outcome::Kind kind = h_ok ? Outcome::ok : Outcome::unexplained;
    std::string label = h_ok ? "ok" : "hidden_over_stated_bound";
    for (int ch = 0; ch < 4; ++ch) {
      const LD got = unit_value(c, o[ch]);
      const LD dev = std::fabs(got - t.value[ch]);
      LD tight, loose;
      if (c.is8()) {
        tight = bound8(c, px, ch) + 1e-9;
        loose = tight + t.hidden_max[ch];
        err = std::max(err, double(dev));
      } else {
        const LD u =
            ulp32(std::max({std::fabs(t.visible[ch]), floor_visible_for(t, c.order)[ch], kFltMin}));
        tight = float_bound(s, c.layers.size()) * u;
        loose = tight + t.hidden_max[ch];
        // reported in ulps of the whole stack's scale, as accuracy (comparable across checks)
        err = std::max(err, double(dev / ulp32(std::max({std::fabs(t.value[ch]),
                                                         floor_for(t, c.order)[ch], kFltMin}))));
      }
      detail += "\n  ch" + std::to_string(ch) + ": |out - full| " + ld(dev) + ", bound " +
                ld(tight) + " (+ hidden could add " + ld(t.hidden_max[ch]) + ")";
      if (!(dev <= loose)) {
        const std::string loss = std::isfinite(got) ? ref_loss(s, c, px) : "";
        if (!loss.empty()) {
          if (kind == Outcome::ok) kind = Outcome::explained, label = loss;
          continue;
        }
        kind = Outcome::unexplained, label = std::isfinite(got) ? "early_stop_error" : "nan";
      } else if (!(dev <= tight) && kind == Outcome::ok) {
        kind = Outcome::explained, label = "hidden_layers";
      }
    }
    v.rays.push_back(make(kind, label, err, detail));
  }
  return v;
}

// ---------------------------------------------------------------- straight alpha 0

Verdict check_straight_clear(const CompositeSubject& s, const StackCase& c) {
  Verdict v;
  // The case as it is, and a variant: every layer straight, every odd pixel's
  // alpha 0 in every layer (its colours kept: they must not show).
  StackCase Zm = all_straight(c);
  for (StackLayer& l : Zm.layers)
    for (int px = 1; px < c.pixels(); px += 2) {
      if (c.is8())
        l.rgba8[size_t(px) * 4 + 3] = 0;
      else
        l.rgba[size_t(px) * 4 + 3] = 0.0f;
    }
  const StackCase& Z = Zm;
  for (const StackCase* cs : {&c, &Z}) {
    const Image out = run(s, *cs);
    for (int px = 0; px < c.pixels(); ++px) {
      const PixelTruth t = truth(*cs, px, eps_of(*cs));
      const float* o = px_of(out, px);
      const bool all_straight =
          std::all_of(cs->layers.begin(), cs->layers.end(),
                      [](const StackLayer& l) { return l.alpha == Alpha::straight; });
      bool any_zero = false;
      for (size_t k = 0; k < cs->layers.size(); ++k)
        any_zero = any_zero ||
                   (cs->layers[k].alpha == Alpha::straight && cs->value(int(k), px, 3) == 0.0f);
      std::string detail = std::string("straight alpha 0, ") + s.name +
                           (cs == &Z ? " (alpha-0 variant)" : "") + ": " + input_text(*cs, px) +
                           "\n  got    " + out_text(*cs, o) + "\n  oracle " + ld4(t.value);
      const bool finite =
          std::isfinite(o[0]) && std::isfinite(o[1]) && std::isfinite(o[2]) && std::isfinite(o[3]);
      Outcome::Kind kind = Outcome::ok;
      std::string label = any_zero ? "alpha0_layer" : "ok";
      double err = 0;
      if (!finite) {
        kind = Outcome::unexplained, label = "nan";
      } else if (all_straight && t.all_alpha_zero) {
        label = "all_alpha0";
        if (!(o[0] == 0 && o[1] == 0 && o[2] == 0 && o[3] == 0))
          kind = Outcome::unexplained, label = "not_clear";
      } else if (any_zero) {
        const PixelErr e =
            judge(*cs, o, t.value, floor_for(t, cs->order), float_bound(s, cs->layers.size()), px);
        err = e.err;
        detail += "\n  " + e.per_channel;
        if (!e.within) {
          const std::string loss = ref_loss(s, *cs, px);
          if (loss.empty())
            kind = Outcome::unexplained, label = "alpha0_layer_shows";
          else
            kind = Outcome::explained, label = loss;
        }
      }
      // The textbook kernels: kStraightClear where there is no coverage, never NaN.
      if (s.is_reference && any_zero) {
        auto same = [](Rgba a, Rgba b) {
          return std::bit_cast<uint32_t>(a.r) == std::bit_cast<uint32_t>(b.r) &&
                 std::bit_cast<uint32_t>(a.g) == std::bit_cast<uint32_t>(b.g) &&
                 std::bit_cast<uint32_t>(a.b) == std::bit_cast<uint32_t>(b.b) &&
                 std::bit_cast<uint32_t>(a.a) == std::bit_cast<uint32_t>(b.a);
        };
        for (size_t k = 0; k < cs->layers.size(); ++k) {
          const Rgba L{cs->value(int(k), px, 0), cs->value(int(k), px, 1), cs->value(int(k), px, 2),
                       cs->value(int(k), px, 3)};
          if (L.a == 0 && !same(ref::unpremultiply(L), ref::kStraightClear))
            kind = Outcome::unexplained, label = "unpremultiply_not_clear";
          if (cs->is8()) {
            const uint8_t* q = &cs->layers[k].rgba8[size_t(px) * 4];
            const Rgba8 u = ref::unpremultiply8({q[0], q[1], q[2], 0});
            if (u.r || u.g || u.b || u.a)
              kind = Outcome::unexplained, label = "unpremultiply8_not_clear";
          }
          if (k + 1 < cs->layers.size()) {
            const Rgba B{cs->value(int(k) + 1, px, 0), cs->value(int(k) + 1, px, 1),
                         cs->value(int(k) + 1, px, 2), cs->value(int(k) + 1, px, 3)};
            const Rgba r = ref::over_straight(L, B);
            if (std::isnan(r.r) || std::isnan(r.g) || std::isnan(r.b) || std::isnan(r.a))
              kind = Outcome::unexplained, label = "over_straight_nan";
            if (L.a == 0 && B.a == 0 && !same(r, ref::kStraightClear))
              kind = Outcome::unexplained, label = "over_straight_not_clear";
          }
        }
      }
      v.rays.push_back(make(kind, label, err, detail));
    }
  }
  return v;
}

// ---------------------------------------------------------------- the 8-bit round trip

Verdict check_round_trip8(const CompositeSubject& s, const StackCase& c) {
  Verdict v;
  if (!c.is8()) {
    for (int px = 0; px < c.pixels(); ++px)
      v.rays.push_back(make(Outcome::skipped, "float_case", 0, ""));
    return v;
  }
  for (size_t k = 0; k < c.layers.size(); ++k) {
    // Layer k alone, straight: the subject premultiplies it (its 8-bit premultiply).
    StackCase one = sub(c, k, k);
    one.layers[0].alpha = Alpha::straight;
    const Image out = run(s, one);
    for (int px = 0; px < c.pixels(); ++px) {
      const uint8_t* q = &one.layers[0].rgba8[size_t(px) * 4];
      const int a = q[3];
      const float* o = px_of(out, px);
      int p[4];
      for (int ch = 0; ch < 4; ++ch) p[ch] = level_of(o[ch]);
      const Rgba8 back =
          ref::unpremultiply8({uint8_t(std::max(0, p[0])), uint8_t(std::max(0, p[1])),
                               uint8_t(std::max(0, p[2])), uint8_t(std::max(0, p[3]))});
      const uint8_t cb[3] = {back.r, back.g, back.b};
      for (int ch = 0; ch < 3; ++ch) {
        const int cin = q[ch], bound = round_trip8_bound(a);
        const int expect_p = nearest_mul255(cin, a);
        const int loss = std::abs(int(cb[ch]) - cin);
        std::string detail = "8-bit round trip, " + s.name + ": layer " + std::to_string(k) + " " +
                             input_text(one, px) + "\n  straight (c, a) = (" + std::to_string(cin) +
                             ", " + std::to_string(a) + ") ch" + std::to_string(ch) +
                             ": premultiplied level " + std::to_string(p[ch]) + " (exact " +
                             ld(exact_mul255(cin, a)) + ", nearest " + std::to_string(expect_p) +
                             "), unpremultiply8 -> " + std::to_string(cb[ch]) + " (loss " +
                             std::to_string(loss) +
                             ", bound floor(1/2 + 127.5/a) = " + std::to_string(bound) + ")";
        Outcome::Kind kind = Outcome::ok;
        std::string label = bucket(a);
        if (p[ch] < 0 || p[3] != a) {
          kind = Outcome::unexplained, label = "premultiplied_alpha_or_level";
        } else if (p[ch] != expect_p) {
          kind = Outcome::unexplained, label = "premultiply8_rounding";
        } else if (a > 0 && !is_nearest_unpremultiply8(p[ch], a, cb[ch])) {
          kind = Outcome::unexplained, label = "unpremultiply8_rounding";
        } else if (a == 0) {
          if (cb[ch] != 0)
            kind = Outcome::unexplained, label = "alpha0_not_stated_colour";
          else if (cin != 0)
            kind = Outcome::explained, label = "alpha0_no_colour";
        } else if (loss > bound) {
          kind = Outcome::unexplained, label = "round_trip_over_bound";
        } else if (loss > 0) {
          // A real loss: the recovered colour premultiplies to the same level.
          if (nearest_mul255(cb[ch], a) == p[ch])
            kind = Outcome::explained, label = "premul8_loss_" + bucket(a);
          else
            kind = Outcome::unexplained, label = "round_trip_not_a_loss";
        }
        v.rays.push_back(make(kind, label, a == 0 ? 0 : loss, detail));
      }
    }
  }
  return v;
}

// ---------------------------------------------------------------- the list

std::vector<NamedCheck> composite_checks() {
  const std::vector<std::string_view> all = {"general", "alpha_edges",  "general8",
                                             "edges8",  "opaque_early", "nearly_opaque"};
  return {
      {"Accuracy", &check_accuracy, all, false},
      {"Agreement", &check_agreement, all, true},
      {"StraightVsPremultiplied",
       &check_straight_vs_premultiplied,
       {"general", "alpha_edges", "general8", "edges8"},
       false},
      {"FtbEqualsBtf", &check_ftb_equals_btf, all, false},
      {"Associativity", &check_associativity, all, false},
      {"EarlyStop",
       &check_early_stop,
       {"opaque_early", "nearly_opaque", "alpha_edges", "edges8"},
       false},
      {"StraightClear", &check_straight_clear, {"alpha_edges", "edges8", "general"}, false},
      {"RoundTrip8", &check_round_trip8, {"general8", "edges8"}, false},
  };
}

}  // namespace lockstep::props::composite
