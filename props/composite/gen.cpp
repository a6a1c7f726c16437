#include "props/composite/gen.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "props/gen/numbers.h"

namespace lockstep::props::composite {

namespace {

using props::gen::chance;
using props::gen::int_in;
using props::gen::int_towards;

constexpr int64_t k24 = int64_t(1) << 24;

// ---------------------------------------------------------------- values

// alpha = m 2^-24 in [lo, 1]; shrinks towards 1/2.
float alpha_grid(float lo) {
  const int64_t m_lo = std::max<int64_t>(1, int64_t(std::ceil(double(lo) * double(k24))));
  return float(double(*int_towards(m_lo, k24, k24 / 2)) / double(k24));
}

// colour in [0, 1] on the 2^-24 grid; shrinks towards 0.
float unit_grid() { return float(double(*int_in(0, k24)) / double(k24)); }

// Any positive denormal float.
float denormal() { return std::ldexp(float(*int_towards(1, (1 << 23) - 1, 1)), -149); }

float edge_alpha() {
  switch (*int_in(0, 7)) {
    case 0:
      return alpha_grid(0x1p-10f);
    case 1:
      return 0.0f;
    case 2:
      return 1.0f;
    case 3:
      return 0x1p-149f;  // one ulp from 0
    case 4:
      return std::nextafter(1.0f, 0.0f);  // one ulp from 1
    case 5:
      return denormal();
    case 6:
      return std::ldexp(1.0f + float(*int_in(0, (1 << 23) - 1)) * 0x1p-23f,
                        -int(*int_towards(1, 126, 20)));
    default:
      return std::nextafter(0x1p-126f, 0.0f);  // the largest denormal
  }
}

float edge_colour() {
  switch (*int_in(0, 6)) {
    case 0:
      return unit_grid();
    case 1:
      return 0.0f;
    case 2:
      return 1.0f;
    case 3:
      return std::nextafter(1.0f, 0.0f);
    case 4:
      return 0x1p-149f;
    case 5:
      return denormal();
    default:
      return std::ldexp(1.0f + float(*int_in(0, (1 << 23) - 1)) * 0x1p-23f,
                        int(*int_towards(0, 12, 1)));
  }
}

int level_uniform() { return int(*int_towards(0, 255, 128)); }
int level_edge() {
  switch (*int_in(0, 4)) {
    case 0:
      return level_uniform();
    case 1:
      return 0;
    case 2:
      return 1;
    case 3:
      return 254;
    default:
      return 255;
  }
}

// ---------------------------------------------------------------- stacks

StackCase frame(const char* name, int min_layers) {
  StackCase c;
  c.generator = name;
  c.width = int(*int_towards(1, 8, 1));
  c.height = int(*int_towards(1, 8, 1));
  const int n = int(*int_towards(min_layers, kMaxLayers, std::max(2, min_layers)));
  c.order = *chance(1, 2) ? Order::back_to_front : Order::front_to_back;
  c.early_stop = !*chance(1, 4);
  c.layers.resize(size_t(n));
  for (StackLayer& l : c.layers) l.alpha = *chance(1, 2) ? Alpha::straight : Alpha::premultiplied;
  return c;
}

// Fills a float layer pixel by pixel from alpha() and colour() choosers.
template <class A, class C>
void fill_float(const StackCase& c, StackLayer& l, A alpha, C colour, bool premultiply_colour) {
  l.rgba.assign(size_t(c.pixels()) * 4, 0.0f);
  for (int px = 0; px < c.pixels(); ++px) {
    float* p = &l.rgba[size_t(px) * 4];
    p[3] = alpha();
    for (int ch = 0; ch < 3; ++ch) {
      const float s = colour();
      p[ch] = premultiply_colour && l.alpha == Alpha::premultiplied ? s * p[3] : s;
    }
  }
}

template <class A, class C>
void fill8(const StackCase& c, StackLayer& l, A alpha, C colour) {
  l.rgba8.assign(size_t(c.pixels()) * 4, 0);
  for (int px = 0; px < c.pixels(); ++px) {
    uint8_t* p = &l.rgba8[size_t(px) * 4];
    p[3] = uint8_t(alpha());
    for (int ch = 0; ch < 3; ++ch) {
      int q = colour();
      if (l.alpha == Alpha::premultiplied)
        q = std::min(q, int(p[3]));  // valid premultiplied: c <= a
      p[ch] = uint8_t(q);
    }
  }
}

float hdr_colour() {
  return std::ldexp(1.0f + float(*int_in(0, (1 << 23) - 1)) * 0x1p-23f,
                    int(*int_towards(0, 12, 4)));
}

}  // namespace

rc::Gen<StackCase> general() {
  return rc::gen::exec([] {
    StackCase c = frame("general", 1);
    for (StackLayer& l : c.layers)
      fill_float(
          c, l, [] { return alpha_grid(0x1p-10f); }, [] { return unit_grid(); }, true);
    return c;
  });
}

rc::Gen<StackCase> alpha_edges() {
  return rc::gen::exec([] {
    StackCase c = frame("alpha_edges", 1);
    for (StackLayer& l : c.layers)
      fill_float(
          c, l, [] { return edge_alpha(); }, [] { return edge_colour(); }, false);
    return c;
  });
}

rc::Gen<StackCase> general8() {
  return rc::gen::exec([] {
    StackCase c = frame("general8", 1);
    c.storage = Storage::unorm8;
    for (StackLayer& l : c.layers)
      fill8(
          c, l, [] { return level_uniform(); }, [] { return level_uniform(); });
    return c;
  });
}

rc::Gen<StackCase> edges8() {
  return rc::gen::exec([] {
    StackCase c = frame("edges8", 1);
    c.storage = Storage::unorm8;
    for (StackLayer& l : c.layers)
      fill8(
          c, l, [] { return level_edge(); }, [] { return level_edge(); });
    return c;
  });
}

rc::Gen<StackCase> opaque_early() {
  return rc::gen::exec([] {
    StackCase c = frame("opaque_early", 2);
    c.order = Order::front_to_back;
    c.early_stop = !*chance(1, 4);
    const bool eight = *chance(1, 3);
    if (eight) c.storage = Storage::unorm8;
    const int n = int(c.layers.size());
    // Which layer makes the stack opaque; mode 1: layers p, p+1 round to 1 together.
    const int p = int(*int_in(0, n - 2));
    const int mode = int(*int_in(0, 1));
    for (int k = 0; k < n; ++k) {
      StackLayer& l = c.layers[size_t(k)];
      const bool behind = k > p + mode;
      if (eight) {
        fill8(
            c, l,
            [&] {
              return k == p || (mode && k == p + 1) ? (mode ? 254 + int(*int_in(0, 1)) : 255)
                                                    : level_edge();
            },
            [&] { return behind ? level_edge() : level_uniform(); });
      } else {
        fill_float(
            c, l,
            [&] {
              if (k == p) return mode ? 1.0f - 0x1p-13f : 1.0f;
              if (mode && k == p + 1) return 1.0f - 0x1p-12f;
              return *chance(1, 4) ? edge_alpha() : alpha_grid(0x1p-10f);
            },
            [&] { return behind && *chance(1, 2) ? hdr_colour() : unit_grid(); }, !behind);
      }
    }
    return c;
  });
}

rc::Gen<StackCase> nearly_opaque() {
  return rc::gen::exec([] {
    StackCase c = frame("nearly_opaque", 2);
    const bool eight = *chance(1, 3);
    if (eight) c.storage = Storage::unorm8;
    const int n = int(c.layers.size());
    const int front = int(*int_towards(1, std::min(3, n - 1), 1));
    for (int k = 0; k < n; ++k) {
      StackLayer& l = c.layers[size_t(k)];
      const bool is_front = k < front;
      if (eight) {
        fill8(
            c, l, [&] { return is_front ? 254 + int(*int_in(0, 1)) : level_edge(); },
            [&] { return is_front ? level_uniform() : level_edge(); });
      } else {
        fill_float(
            c, l,
            [&] {
              return is_front ? 1.0f - float(*int_towards(0, 64, 1)) * 0x1p-24f
                              : alpha_grid(0x1p-10f);
            },
            [&] { return is_front ? unit_grid() : hdr_colour(); }, is_front);
      }
    }
    return c;
  });
}

std::vector<NamedGen> generators() {
  return {
      {"general", "float, alpha in [2^-10, 1], colours in [0, 1]", general()},
      {"alpha_edges", "float, alpha 0 / 1 / ulp from 0 and 1 / denormal; colours denormal and > 1",
       alpha_edges()},
      {"general8", "unorm8, uniform levels", general8()},
      {"edges8", "unorm8, levels 0, 1, 254, 255", edges8()},
      {"opaque_early", "an exactly opaque layer, or two that round to alpha 1; HDR behind",
       opaque_early()},
      {"nearly_opaque", "front layers with alpha >= 1 - 64 ulp; HDR behind", nearly_opaque()},
  };
}

rc::Gen<StackCase> one_of(const std::vector<std::string_view>& names) {
  std::vector<rc::Gen<StackCase>> gens;
  for (const NamedGen& g : generators())
    if (std::find(names.begin(), names.end(), g.name) != names.end()) gens.push_back(g.gen);
  if (gens.empty()) throw std::invalid_argument("composite::one_of: no such generator");
  return rc::gen::exec([gens] { return *gens[size_t(*int_in(0, int64_t(gens.size()) - 1))]; });
}

}  // namespace lockstep::props::composite
