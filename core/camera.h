// lockstep core: the pinhole camera of an NFF viewpoint.
//
// Pixel convention (stated once, used everywhere): NFF's angle is the field of
// view between the *centres* of the edge pixels, not their outer edges. So for
// an image of W x H pixels the pixel pitch on the image plane at distance 1 is
//     s = 2 tan(angle/2) / (min(W, H) - 1)
// and pixel (i, j) (column i from the left, row j from the top) has its centre at
//     x = (i - (W-1)/2) s,   y = ((H-1)/2 - j) s.
// For the square images NFF describes, the edge pixel centres sit at +-tan(angle/2).
#pragma once

#include <cmath>

#include "core/math.h"
#include "core/scene.h"

namespace lockstep {

struct Camera {
  Vec3 eye;
  Vec3 right, up, forward;  // orthonormal, right-handed: right = forward x up
  double pitch = 0;         // s above
  double hither = 0;
  int width = 0, height = 0;

  // Camera for view rendered at width x height. The view must have been
  // validated (from != at, up not parallel to the view direction, 0 < angle < 180).
  static Camera from_view(const View& v, int width, int height) {
    Camera c;
    c.eye = v.from;
    c.forward = normalize(v.at - v.from);
    c.right = normalize(cross(c.forward, v.up));
    c.up = cross(c.right, c.forward);
    const double half = std::tan(v.angle * 0.5 * M_PI / 180.0);
    const int n = width < height ? width : height;
    c.pitch = 2.0 * half / double(n > 1 ? n - 1 : 1);
    c.hither = v.hither;
    c.width = width;
    c.height = height;
    return c;
  }

  // Offsets of pixel (i, j)'s centre on the image plane at distance 1.
  double sx(int i) const { return (double(i) - 0.5 * (width - 1)) * pitch; }
  double sy(int j) const { return (0.5 * (height - 1) - double(j)) * pitch; }

  // Camera-space direction (x right, y up, z forward) of pixel (i, j), not normalised.
  Vec3 camera_dir(int i, int j) const { return {sx(i), sy(j), 1.0}; }

  // World-space primary ray through the centre of pixel (i, j): unit direction,
  // tmin at the hither plane (hither is a distance along the view axis).
  Ray primary(int i, int j) const {
    const Vec3 d = forward + sx(i) * right + sy(j) * up;
    const double len = length(d);
    return Ray{eye, d / len, hither * len, kInfinity};
  }
};

}  // namespace lockstep
