// lockstep props: pixel-by-pixel checks of two images, for the families whose
// output is an image (texture, radiosity).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include "core/image.h"
#include "props/verdict.h"

namespace lockstep::props {

// "(r g b a)" to 9 digits.
inline std::string pixel_text(const float* p) {
  char b[160];
  std::snprintf(b, sizeof b, "(%.9g %.9g %.9g %.9g)", p[0], p[1], p[2], p[3]);
  return b;
}

// Per pixel, the largest channel difference of a and b; over bound an
// unexplained outcome labelled label, described by describe(x, y, err).
inline Verdict compare_pixels(const Image& a, const Image& b, double bound, const char* label,
                       const std::function<std::string(int, int, double)>& describe) {
  Verdict v;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      double err = 0;
      for (int k = 0; k < 4; ++k) err = std::max(err, double(std::abs(a.pixel(x, y)[k] - b.pixel(x, y)[k])));
      if (!(err == err)) err = INFINITY;
      Outcome o;
      o.err = err;
      o.measured = true;
      if (err > bound) {
        o.kind = Outcome::unexplained;
        o.label = label;
        o.detail = describe(x, y, err);
      }
      v.rays.push_back(std::move(o));
    }
  return v;
}

}  // namespace lockstep::props
