// lockstep props/composite: one generated compositing case, and its bit-exact text form.
//
// A StackCase is a small layer stack (1..8 layers of W x H pixels, W*H <= 64,
// FRONT FIRST, as in io/layers.h) with everything the compositing contract
// reads: each layer's Alpha, the Order, the Storage and early_stop. Float
// stacks carry the float values; unorm8 stacks carry the 8-bit levels (the float
// image of such a layer is q / 255, which the implementations ignore).
//
// The text form writes every float as a C99 hexfloat (%a) and every level as an
// integer, so a counterexample file replays bit for bit:
//
//   stack v1
//   generator alpha_edges
//   size 2 1                          W H
//   order ftb                         ftb | btf
//   storage float                     float | unorm8
//   early_stop 1
//   layer straight                    one block per layer, front first
//   0x1p-1 0x0p+0 0x1.8p+1 0x1p+0     one pixel per line: r g b a (unorm8: 4 integers)
//   ...
//   end
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "io/layers.h"

namespace lockstep::props::composite {

inline constexpr int kMaxLayers = 8;
inline constexpr int kMaxPixels = 64;

struct StackLayer {
  Alpha alpha = Alpha::premultiplied;
  std::vector<float> rgba;     // Storage::f32: W*H*4 values
  std::vector<uint8_t> rgba8;  // Storage::unorm8: W*H*4 levels, in this layer's representation
};

struct StackCase {
  std::string generator;
  int width = 1, height = 1;
  Order order = Order::front_to_back;
  Storage storage = Storage::f32;
  bool early_stop = true;
  std::vector<StackLayer> layers;  // front first

  int pixels() const { return width * height; }
  bool is8() const { return storage == Storage::unorm8; }
  // Channel ch of pixel px of layer k as a float (unorm8: level / 255, rounded to float).
  float value(int k, int px, int ch) const;
  // Builds the LayerStack the implementations take (unorm8: rgba8 = the levels,
  // image = level / 255 in float).
  LayerStack to_stack() const;
  // A copy with another order / storage flag / early_stop.
  StackCase with_order(Order o) const;
  StackCase with_early_stop(bool e) const;
  // Throws std::invalid_argument when sizes disagree or a layer count is out of range.
  void validate() const;
};

// Hexfloat of a float ("0x1.8p+1"; "inf", "-inf", "nan").
std::string hexf(float x);
// "(r, g, b, a)" as hexfloats / levels.
std::string hex4(const float* v);
std::string lev4(const uint8_t* v);

void write_case(std::ostream& out, const StackCase& c);
// Throws std::runtime_error naming `name` and the line on a malformed text.
StackCase read_case(std::istream& in, const std::string& name);

// For RapidCheck's counterexample printing: the whole case in the text form.
void showValue(const StackCase& c, std::ostream& os);

}  // namespace lockstep::props::composite
