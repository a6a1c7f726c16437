// lockstep reference: alpha compositing (Porter & Duff 1984, "Compositing
// Digital Images"; Smith 1995, "Image Compositing Fundamentals").
//
// Contract of the compositing family (every implementation, reference,
// opt::simd and opt::oiio, has composite() with exactly this signature):
//
//   composite(stack, opts, stats) -> the stack's layers composited with `over`,
//   front first, into one image of the stack's size (opts.width/height are
//   ignored), PREMULTIPLIED RGBA float. With Storage::unorm8 the arithmetic is
//   8-bit and the result is q / 255 exactly for each 8-bit value q.
//   Order::front_to_back accumulates under the front layers and, with
//   stack.early_stop, stops at a pixel (the reference) or a block of pixels
//   (simd) once its alpha is exactly 1; back_to_front lays layers over the
//   result from the back.
//
//   Straight-alpha layers are composited with the straight formula by the
//   reference and converted to premultiplied first by the others.
//   stats->items = output pixels.
#pragma once

#include <cstdint>

#include "core/family.h"
#include "io/layers.h"

namespace lockstep {

struct Rgba {
  float r = 0, g = 0, b = 0, a = 0;
};
struct Rgba8 {
  uint8_t r = 0, g = 0, b = 0, a = 0;
};

namespace ref {

// The colour a straight-alpha pixel has when its alpha is 0: black (0, 0, 0).
// (A fully transparent pixel has no colour; black is what unpremultiply of
// (0,0,0,0) gives in OpenImageIO too.)
inline constexpr Rgba kStraightClear = {0, 0, 0, 0};

// Straight alpha: alpha = af + ab (1 - af); C = (Cf af + Cb ab (1 - af)) / alpha.
Rgba over_straight(Rgba front, Rgba back);
// Premultiplied: C = Cf + (1 - af) Cb (every channel, alpha included).
Rgba over_premultiplied(Rgba front, Rgba back);
Rgba premultiply(Rgba straight);
Rgba unpremultiply(Rgba premultiplied);  // alpha = 0 -> kStraightClear

// 8 bits: x * a / 255 rounded to nearest, exactly (not a shift by 8).
uint8_t mul255(uint8_t x, uint8_t a);
Rgba8 over_premultiplied8(Rgba8 front, Rgba8 back);
Rgba8 premultiply8(Rgba8 straight);
Rgba8 unpremultiply8(Rgba8 premultiplied);  // round(C * 255 / a); a = 0 -> (0,0,0,0)

Image composite(const LayerStack& stack, const FrameOptions& opts, FrameStats* stats);

}  // namespace ref
}  // namespace lockstep
