// Alpha compositing: the `over` operator, textbook version.
//
// Sources:
//  * T. Porter and T. Duff, "Compositing Digital Images", SIGGRAPH 1984: the
//    premultiplied ("associated") representation and A over B = A + (1 - aA) B.
//  * A. R. Smith, "Image Compositing Fundamentals", Microsoft Tech Memo 4, 1995:
//    the straight-alpha form of over and why premultiplied is the one to use.
//  * J. Blinn, "Compositing, Part 1: Theory", IEEE CG&A 1994: exact 8-bit
//    multiplication x * a / 255 with rounding (no "shift by 8" shortcut).
//
// Scalar, one pixel at a time, single-threaded, deterministic. Each step of the
// formulas is on its own line so it can be checked against the paper. The
// project compiles with -ffp-contract=off: every product is rounded on its own,
// never fused into an FMA, so this is exactly what the source says.
#include "reference/composite.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace lockstep::ref {

// ---------------------------------------------------------------- float

Rgba over_straight(Rgba front, Rgba back) {
  // Smith 1995: the back's coverage shows only where the front's does not.
  const float back_share = back.a * (1.0f - front.a);
  const float alpha = front.a + back_share;
  // Nothing covers the pixel: it has no colour, and dividing by 0 would make
  // NaN. Say what it is instead (kStraightClear).
  if (alpha == 0.0f) return kStraightClear;
  // Each colour weighted by how much of the pixel it covers, then divided by
  // the total coverage to get back to a straight (unweighted) colour.
  Rgba out;
  out.r = (front.r * front.a + back.r * back_share) / alpha;
  out.g = (front.g * front.a + back.g * back_share) / alpha;
  out.b = (front.b * front.a + back.b * back_share) / alpha;
  out.a = alpha;
  return out;
}

Rgba over_premultiplied(Rgba front, Rgba back) {
  // Porter & Duff 1984: with colours already weighted by coverage, over is the
  // same linear blend on all four channels: C = Cf + (1 - af) Cb.
  const float transparency = 1.0f - front.a;  // how much of the back shows through
  Rgba out;
  out.r = front.r + transparency * back.r;
  out.g = front.g + transparency * back.g;
  out.b = front.b + transparency * back.b;
  out.a = front.a + transparency * back.a;
  return out;
}

Rgba premultiply(Rgba s) { return {s.r * s.a, s.g * s.a, s.b * s.a, s.a}; }

Rgba unpremultiply(Rgba p) {
  if (p.a == 0.0f) return kStraightClear;  // no coverage: no colour (never 0/0)
  return {p.r / p.a, p.g / p.a, p.b / p.a, p.a};
}

// ---------------------------------------------------------------- 8 bits

uint8_t mul255(uint8_t x, uint8_t a) {
  // round(x * a / 255) exactly (Blinn 1994). With t = x a + 128, t / 255 is
  // approximated by (t + t / 256) / 256, which is exact for every t < 65536
  // that can arise here (tests/composite_smoke.cpp checks all 65536 pairs).
  const uint32_t t = uint32_t(x) * uint32_t(a) + 128u;
  return uint8_t((t + (t >> 8)) >> 8);
}

Rgba8 over_premultiplied8(Rgba8 front, Rgba8 back) {
  // C = Cf + (1 - af) Cb with 1 = 255. For valid premultiplied input (C <= a)
  // the sum is at most af + (255 - af) = 255; a colour brighter than its alpha
  // (possible in an EXR quantised to 8 bits) saturates instead of wrapping.
  const uint8_t transparency = uint8_t(255 - front.a);
  auto channel = [&](uint8_t f, uint8_t b) {
    const uint32_t sum = uint32_t(f) + uint32_t(mul255(b, transparency));
    return uint8_t(std::min(sum, 255u));
  };
  return {channel(front.r, back.r), channel(front.g, back.g), channel(front.b, back.b),
          channel(front.a, back.a)};
}

Rgba8 premultiply8(Rgba8 s) { return {mul255(s.r, s.a), mul255(s.g, s.a), mul255(s.b, s.a), s.a}; }

Rgba8 unpremultiply8(Rgba8 p) {
  if (p.a == 0) return {0, 0, 0, 0};
  // round(C * 255 / a), clamped: C > a has no straight meaning, say 255.
  auto channel = [&](uint8_t c) {
    const uint32_t q = (uint32_t(c) * 255u + p.a / 2u) / p.a;
    return uint8_t(std::min(q, 255u));
  };
  return {channel(p.r), channel(p.g), channel(p.b), p.a};
}

// ---------------------------------------------------------------- the stack

namespace {

Rgba load(const Layer& l, size_t i) {
  const float* p = &l.image.rgba[i * 4];
  return {p[0], p[1], p[2], p[3]};
}
Rgba8 load8(const Layer& l, size_t i) {
  const uint8_t* p = &l.rgba8[i * 4];
  return {p[0], p[1], p[2], p[3]};
}

// Which formula a stack is composited with. A stack of straight layers only is
// composited with the straight formula throughout (so the reference really
// exercises it) and premultiplied once at the end. A stack that mixes the two
// is composited premultiplied: its straight layers are premultiplied as they
// are read. Converting a premultiplied accumulator back to straight instead
// would divide by its alpha, and a bright colour over a tiny alpha then
// overflows (2^-21 / 2^-149 = inf) or, at alpha = 0, loses an additive colour
// that straight alpha cannot hold (props/composite found both).
Alpha working_representation(const LayerStack& stack) {
  for (const Layer& l : stack.layers)
    if (l.alpha == Alpha::premultiplied) return Alpha::premultiplied;
  return Alpha::straight;
}

// Layer k's pixel i in the working representation.
Rgba load_as(const LayerStack& stack, size_t k, size_t i, Alpha rep) {
  const Rgba v = load(stack.layers[k], i);
  return rep == Alpha::premultiplied && stack.layers[k].alpha == Alpha::straight ? premultiply(v) : v;
}

Rgba over_in(Alpha rep, Rgba front, Rgba back) {
  return rep == Alpha::straight ? over_straight(front, back) : over_premultiplied(front, back);
}

// One float pixel: layers front first in `stack.layers`.
Rgba composite_pixel(const LayerStack& stack, size_t i, Alpha rep) {
  const size_t n = stack.layers.size();
  Rgba acc;
  if (stack.order == Order::front_to_back) {
    // Front to back: the accumulator is in front; each new layer goes UNDER it.
    acc = load_as(stack, 0, i, rep);
    for (size_t k = 1; k < n; ++k) {
      // Once the pixel is fully covered nothing behind can show: stop (exactly
      // 1 only, so that the result is the same as without stopping).
      if (stack.early_stop && acc.a == 1.0f) break;
      acc = over_in(rep, acc, load_as(stack, k, i, rep));
    }
  } else {
    // Back to front (the painter's order): each layer goes OVER the result so far.
    acc = load_as(stack, n - 1, i, rep);
    for (size_t k = n - 1; k-- > 0;) acc = over_in(rep, load_as(stack, k, i, rep), acc);
  }
  // The contract's output representation.
  return rep == Alpha::straight ? premultiply(acc) : acc;
}

// One 8-bit pixel. 8-bit compositors work premultiplied: straight layers are
// premultiplied once (premultiply8), then every over is the premultiplied one.
Rgba8 composite_pixel8(const LayerStack& stack, size_t i) {
  const auto& layers = stack.layers;
  const size_t n = layers.size();
  auto premultiplied = [&](size_t k) {
    const Rgba8 v = load8(layers[k], i);
    return layers[k].alpha == Alpha::straight ? premultiply8(v) : v;
  };
  if (stack.order == Order::front_to_back) {
    Rgba8 acc = premultiplied(0);
    for (size_t k = 1; k < n; ++k) {
      if (stack.early_stop && acc.a == 255) break;  // fully covered: nothing behind shows
      acc = over_premultiplied8(acc, premultiplied(k));
    }
    return acc;
  }
  Rgba8 acc = premultiplied(n - 1);
  for (size_t k = n - 1; k-- > 0;) acc = over_premultiplied8(premultiplied(k), acc);
  return acc;
}

}  // namespace

Image composite(const LayerStack& stack, const FrameOptions& opts, FrameStats* stats) {
  check_stack(stack);  // empty stacks and mismatched sizes are InputErrors, not crashes
  const int w = stack.width(), h = stack.height();
  Image out(w, h);
  const size_t count = size_t(w) * size_t(h);
  const Alpha rep = working_representation(stack);
  for (size_t i = 0; i < count; ++i) {
    float* d = &out.rgba[i * 4];
    if (stack.storage == Storage::unorm8) {
      const Rgba8 q = composite_pixel8(stack, i);
      // The 8-bit value q stands for q / 255 (divided, not multiplied by 1/255,
      // so that it is the correctly rounded float).
      d[0] = float(q.r) / 255.0f;
      d[1] = float(q.g) / 255.0f;
      d[2] = float(q.b) / 255.0f;
      d[3] = float(q.a) / 255.0f;
    } else {
      const Rgba v = composite_pixel(stack, i, rep);
      d[0] = v.r;
      d[1] = v.g;
      d[2] = v.b;
      d[3] = v.a;
    }
    if (opts.progress && (i + 1) % (size_t(1) << 20) == 0)
      opts.progress(double(i + 1) / double(count));
  }
  if (opts.progress) opts.progress(1.0);
  if (stats) stats->items = count;
  return out;
}

}  // namespace lockstep::ref
