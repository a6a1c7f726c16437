// lockstep spd: rings (Eric Haines' SPD rings.c): a pyramid of objects seen
// from its point, each six pentagonal rings of cylinders and spheres joining
// the edge midpoints of a dodecahedron (30 of each per object), before a wall
// square; three lights.
#include <array>
#include <cmath>

#include "spd/scenes.h"

namespace lockstep::spd {

namespace {

constexpr double kSpreadOut = 1.0;  // > 1: succeeding layers spread out more

// The 30 ring vertices (rings.c create_dodec): one pentagon in the XY plane,
// five more turned about X by the dodecahedron's dihedral angle, then about Z.
std::array<Vec3, 30> dodec(double minor_radius) {
  std::array<Vec3, 30> v;
  const double scale = 1.0 / (1.0 + minor_radius);  // fits a sphere of radius 1
  for (int i = 0; i < 5; ++i)
    v[size_t(i)] = {scale * std::cos(double(i) * 2.0 * kPi / 5.0),
                    scale * std::sin(double(i) * 2.0 * kPi / 5.0), 0.0};
  const double x_rotation = 2.0 * std::acos(std::cos(kPi / 3.0) / std::sin(kPi / 5.0));
  const Matrix xm = rotate(kX, x_rotation);
  for (int p = 1; p < 6; ++p) {
    const Matrix zm = rotate(kZ, kPi * (2.0 * double(p - 1) + 1.0) / 5.0);
    for (int i = 0; i < 5; ++i)
      v[size_t(5 * p + i)] = transform_point(transform_point(v[size_t(i)], xm), zm);
  }
  return v;
}

}  // namespace

void rings(Writer& w, int size) {
  const double radius = 0.07412;  // cylinder and sphere radius
  const double spread = 1 / std::sin(kPi / 8.0);
  double y_diff, xz_diff;
  if (kSpreadOut <= spread) {
    y_diff = spread / kSpreadOut;
    xz_diff = 1.0;
  } else {
    y_diff = 1.0;
    xz_diff = kSpreadOut / spread;
  }
  w.background(kSkyBlue);  // never seen
  const Vec3 from = {-1.0, -spread, 0.5};
  w.viewpoint(from, {from[0], from[1] + 1.0, from[2]}, {0.0, 0.0, 1.0}, 45.0, 1.0, 512, 512);
  w.light({3.0, -spread, 3.0, 1.0});
  w.light({-4.0, -spread, 1.0, 1.0});
  w.light({2.0, -spread, -4.0, 1.0});
  // The wall: white, just spanning the 45 degree view plus 1%.
  w.color({1.0, 1.0, 1.0}, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  Vec3 wv;
  wv[1] = y_diff * (size + 1);
  wv[0] = wv[2] = 1.01 * (wv[1] - from[1]) * std::tan(kPi / 8.0);
  w.polygon({{wv[0] + from[0], wv[1], wv[2] + from[2]},
             {-wv[0] + from[0], wv[1], wv[2] + from[2]},
             {-wv[0] + from[0], wv[1], -wv[2] + from[2]},
             {wv[0] + from[0], wv[1], -wv[2] + from[2]}});
  // Ring colours: RGB and their complements.
  const Vec3 colors[6] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0},
                          {0.0, 1.0, 1.0}, {1.0, 0.0, 1.0}, {1.0, 1.0, 0.0}};
  const std::array<Vec3, 30> d = dodec(radius);
  Vec3 offset;
  for (int depth = 0; depth < size; ++depth) {
    offset[1] = y_diff * double(depth + 1);
    for (int oz = 0; oz <= depth; ++oz) {
      offset[2] = xz_diff * double(2 * oz - depth);
      for (int ox = 0; ox <= depth; ++ox) {
        offset[0] = xz_diff * double(2 * ox - depth);
        for (int e = 0; e < 30; ++e) {
          int prev = e - 1;
          if (e % 5 == 0) {
            prev = e + 4;  // a new ring begins
            w.color(colors[e / 5], 0.0, 0.5, 0.2, 0.3, 37.0, 0.0, 0.0);
          }
          const Vec3 b = add(d[size_t(e)], offset), a = add(d[size_t(prev)], offset);
          const Vec4 base = {b[0], b[1], b[2], radius}, apex = {a[0], a[1], a[2], radius};
          w.cylcone(base, apex);
          w.sphere(base);
        }
      }
    }
  }
}

}  // namespace lockstep::spd
