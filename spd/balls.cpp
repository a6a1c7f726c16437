// lockstep spd: balls, the "sphereflake" (Eric Haines' SPD balls.c).
//
// A sphere with nine spheres of a third its radius around it, each of them
// with nine more, size levels deep (sum of 9^k spheres), over a floor square;
// three lights.
#include <array>

#include "spd/scenes.h"

namespace lockstep::spd {

namespace {

// The nine directions in which a sphere spawns its children, as unit
// vectors from +Z (balls.c create_objset): three trios around Z.
std::array<Vec4, 9> make_objset() {
  const double dist = 1.0 / std::sqrt(2.0);
  std::array<Vec4, 3> trio = {Vec4{dist, dist, 0.0, 0.0}, Vec4{dist, 0.0, -dist, 0.0},
                              Vec4{0.0, dist, -dist, 0.0}};
  Vec3 axis = {1.0, -1.0, 0.0};
  normalize(axis);
  Matrix mx = axis_rotate(axis, std::asin(2.0 / std::sqrt(6.0)));
  for (Vec4& t : trio) t = transform_coord(t, mx);
  std::array<Vec4, 9> set;
  for (int s = 0; s < 3; ++s) {
    mx = rotate(kZ, s * 2.0 * kPi / 3.0);
    for (int v = 0; v < 3; ++v) set[size_t(s * 3 + v)] = transform_coord(trio[size_t(v)], mx);
  }
  return set;
}

// A sphere, then its children (balls.c output_object). direction: the unit
// vector from the parent, W the child/parent radius ratio.
void flake(Writer& w, const std::array<Vec4, 9>& objset, int depth, const Vec4& center,
           const Vec4& direction) {
  w.sphere(center);
  if (depth <= 0) return;
  --depth;
  Matrix mx;
  // A child's direction may be a hair short of unit length: hence the 0.9999.
  if (direction[2] >= 0.9999) {
    mx = identity();
  } else if (direction[2] <= -0.9999) {
    mx = rotate(kY, kPi);
  } else {
    const Vec3 z_axis = {0.0, 0.0, 1.0};
    Vec3 axis = cross(z_axis, xyz(direction));
    normalize(axis);
    mx = axis_rotate(axis, std::acos(dot(z_axis, xyz(direction))));
  }
  const double scale = center[3] * (1.0 + direction[3]);
  for (const Vec4& o : objset) {
    Vec4 child = transform_coord(o, mx);
    child[0] = child[0] * scale + center[0];
    child[1] = child[1] * scale + center[1];
    child[2] = child[2] * scale + center[2];
    child[3] = center[3] * direction[3];
    Vec4 dir = {(child[0] - center[0]) / scale, (child[1] - center[1]) / scale,
                (child[2] - center[2]) / scale, direction[3]};
    flake(w, objset, depth, child, dir);
  }
}

}  // namespace

void balls(Writer& w, int size) {
  const double radius = 1.0;
  w.background(kSkyBlue);
  w.viewpoint({2.1, 1.3, 1.7}, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, 45.0, 0.01, 512, 512);
  w.light({4.0, 3.0, 2.0, 1.0});
  w.light({1.0, -4.0, 4.0, 1.0});
  w.light({-3.0, 1.0, 5.0, 1.0});
  // Floor: beige.
  w.color({1.0, 0.75, 0.33}, 0.2, 0.8, 0.0, 0.0, 0.0, 0.0, 1.0);
  const Vec3 b = {12.0 * radius, 12.0 * radius, -radius / 2.0};
  w.polygon({{b[0], b[1], b[2]}, {-b[0], b[1], b[2]}, {-b[0], -b[1], b[2]}, {b[0], -b[1], b[2]}});
  // Spheres: mirrored.
  w.color({1.0, 0.9, 0.7}, 0.0, 0.5, 0.5, 0.5, 37.0, 0.0, 1.0);
  flake(w, make_objset(), size, {0.0, 0.0, 0.0, radius / 2.0}, {0.0, 0.0, 1.0, 1.0 / 3.0});
}

}  // namespace lockstep::spd
