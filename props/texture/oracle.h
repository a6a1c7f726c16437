// lockstep props/texture: the exact oracle of texture filtering.
//
// What it computes, exactly: the pixel's box filter of the texel-constant
// texture, i.e. the average over the pixel square [x, x+1] x [y, y+1] (in
// pixel space, every point weighted alike) of the colour of the texel the
// point sees. It is NOT the plain average of the texels over the pixel's
// footprint in texture space (what area sampling, the reference's `area`
// filter, computes): under perspective the map from texture to pixels
// stretches the footprint's near end, so the two weight the texels
// differently; they are equal when the map is affine (a quad parallel to the
// image plane).
//
// How: each texel square cut to the footprint (the pixel square's exact
// preimage, a convex quadrilateral in texel coordinates) is mapped back to
// pixel space by the projective map, where its area is the texel's weight.
// In double: the weights sum to 1 within 1e-12 on the cases here (checked per
// pixel: weight_sum), against float outputs (2^-24 relative).
//
// Only interior pixels are judged: all four corners of the pixel see the
// quad (edge pixels mix in the background, which the rows decide by the
// pixel's centre: coverage, not filtering).
#pragma once

#include <array>

#include "core/texture.h"

namespace lockstep::props::texture {

struct BoxValue {
  bool interior = false;
  std::array<double, 4> rgba{};      // the box-filtered value
  double weight_sum = 0;             // 1 up to rounding
  std::array<double, 4> lo{}, hi{};  // the range of the texels with weight > 0
  double depth_ratio = 1;            // the largest over the smallest depth on the footprint's corners
  long texels = 0;                   // how many texels have weight > 0
};

BoxValue pixel_box_filter(const TextureScene& scene, const TexelMap& map, int x, int y);

}  // namespace lockstep::props::texture
