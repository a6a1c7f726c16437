// lockstep reference: deterministic synthetic layer stacks (see synthetic_stack.h).
#include "reference/synthetic_stack.h"

#include <string>

namespace lockstep {

namespace {

// SplitMix64 (Steele, Lea, Flood 2014): a tiny, well-mixed, portable generator.
struct SplitMix64 {
  uint64_t state;
  uint64_t next() {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1) with 24 bits: exact in float.
  float unit() { return float(next() >> 40) * (1.0f / 16777216.0f); }
  float range(float lo, float hi) { return lo + (hi - lo) * unit(); }
};

// A smooth periodic wave in [0, 1]: a triangle wave through smoothstep.
float wave(float t) {
  const float f = t - float(int64_t(t) - (t < 0 ? 1 : 0));  // fract(t), t may be negative
  const float tri = f < 0.5f ? 2.0f * f : 2.0f - 2.0f * f;
  return tri * tri * (3.0f - 2.0f * tri);
}

// Two waves along random directions: smooth-ish, varied, in [0, 1].
struct Field {
  float fx[2], fy[2], phase[2];
  explicit Field(SplitMix64& rng, int width, int height) {
    const float scale = 1.0f / float(width > height ? width : height);
    for (int k = 0; k < 2; ++k) {
      fx[k] = rng.range(-4.0f, 4.0f) * scale;
      fy[k] = rng.range(-4.0f, 4.0f) * scale;
      phase[k] = rng.unit();
    }
  }
  float at(int x, int y) const {
    const float a = wave(fx[0] * float(x) + fy[0] * float(y) + phase[0]);
    const float b = wave(fx[1] * float(x) + fy[1] * float(y) + phase[1]);
    return 0.5f * (a + b);
  }
};

struct Hole {
  float cx, cy, r2;
};

}  // namespace

LayerStack synthetic_stack(int width, int height, int layers, int opaque_from, Alpha alpha,
                           Storage storage, uint64_t seed) {
  LayerStack stack;
  stack.source = "synthetic " + std::to_string(width) + "x" + std::to_string(height) + " " +
                 std::to_string(layers) + " layers, seed " + std::to_string(seed);
  if (width <= 0 || height <= 0 || layers <= 0) return stack;
  SplitMix64 rng{seed};
  for (int l = 0; l < layers; ++l) {
    Layer layer;
    layer.alpha = alpha;
    layer.source = stack.source + ", layer " + std::to_string(l);
    layer.image = Image(width, height);
    const Field colour[3] = {Field(rng, width, height), Field(rng, width, height),
                             Field(rng, width, height)};
    const Field coverage(rng, width, height);
    const bool opaque = opaque_from >= 0 && l >= opaque_from;
    Hole holes[3];
    const float radius = 0.04f * float(width < height ? width : height) + 1.0f;
    for (Hole& h : holes)
      h = {rng.range(0, float(width)), rng.range(0, float(height)), radius * radius};
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        float a = 0.02f + 0.96f * coverage.at(x, y);  // strictly inside (0, 1)
        if (opaque) {
          bool in_hole = false;
          for (const Hole& h : holes) {
            const float dx = float(x) - h.cx, dy = float(y) - h.cy;
            in_hole = in_hole || dx * dx + dy * dy < h.r2;
          }
          if (!in_hole) a = 1.0f;
        }
        float* p = layer.image.pixel(x, y);
        for (int c = 0; c < 3; ++c) {
          const float v = colour[c].at(x, y);
          p[c] = alpha == Alpha::premultiplied ? v * a : v;
        }
        p[3] = a;
      }
    }
    stack.layers.push_back(std::move(layer));
  }
  if (storage == Storage::unorm8) to_unorm8(stack);
  return stack;
}

}  // namespace lockstep
