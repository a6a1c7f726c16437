// lockstep spd: mount, a fractal mountain (Eric Haines' SPD mount.c:
// Carpenter's midpoint subdivision extended to square grids), 2*4^size
// triangles, with a pyramid of four glass spheres in front; one light.
//
// The heights come from the SPD's own hash and Gaussian generator: the file
// matches the SPD's only if both are reproduced exactly, faults included (the
// SPD keeps the original hash, which repeats, so that images stay comparable
// with the 1987 IEEE CG&A article).
#include <cmath>

#include "spd/scenes.h"

namespace lockstep::spd {

namespace {

constexpr double kFractalDimension = 2.2;  // between 2 and 3: the variance of z
constexpr long kMountainNo = 21;           // another number, another mountain
constexpr double kCorner = -1.0, kWidth = 2.0;

// mount.c's hash_rand (the "old, buggy" one). The shifts are those of the
// SPD's unsigned long; sizes are limited to 7 so that none is negative.
long hash_rand(long a, long b, int c) {
  const unsigned long ua = static_cast<unsigned long>(a), ub = static_cast<unsigned long>(b);
  return long(((ua << (23 - c)) + (ub << (15 - c)) + (ua << (7 - c))) & 0xffff);
}

struct Mountain {
  Writer& w;
  int size;
  double roughness;
  double fnum_pts;

  double rand(long x, long y) const { return gauss_rand(kMountainNo + hash_rand(x, y, size)); }

  // mount.c grow_mountain: a square of `width` grid steps at (llx, lly) with
  // its four corner heights, split into four until one step wide.
  void grow(int width, int llx, int lly, double ll, double lr, double ur, double ul) const {
    if (width == 1) {
      const double lx = kCorner + double(llx) * kWidth / fnum_pts;
      const double rx = kCorner + double(llx + 1) * kWidth / fnum_pts;
      const double ly = kCorner + double(lly) * kWidth / fnum_pts;
      const double uy = kCorner + double(lly + 1) * kWidth / fnum_pts;
      const Vec3 corner[4] = {{lx, ly, ll}, {rx, ly, lr}, {rx, uy, ur}, {lx, uy, ul}};
      w.polygon({corner[0], corner[1], corner[2]});
      w.polygon({corner[2], corner[3], corner[0]});
      return;
    }
    const int half = width >> 1;
    const double rise = (double(half) * kWidth / fnum_pts) * roughness;
    const double lower = (ll + lr) / 2.0 + rise * rand(llx + half, lly);
    const double right = (lr + ur) / 2.0 + rise * rand(llx + width, lly + half);
    const double upper = (ur + ul) / 2.0 + rise * rand(llx + half, lly + width);
    const double left = (ul + ll) / 2.0 + rise * rand(llx, lly + half);
    const double middle =
        (ll + lr + ur + ul) / 4.0 + 1.4142136 * rise * rand(llx + half, lly + half);
    grow(half, llx, lly, ll, lower, middle, left);
    grow(half, llx + half, lly, lower, lr, right, middle);
    grow(half, llx + half, lly + half, middle, right, ur, upper);
    grow(half, llx, lly + half, left, middle, upper, ul);
  }
};

// A pyramid of four spheres resting on each other (mount.c create_spheres).
void crystal_spheres(Writer& w, const Vec4& center) {
  Vec3 axis = {1.0, 1.0, 0.0};
  normalize(axis);
  const double angle = std::acos(-1.0 / 3.0);
  const Vec3 pt = {0.0, 0.0, center[3] * std::sqrt(3.0 / 2.0)};
  w.sphere({center[0] + pt[0], center[1] + pt[1], center[2] + pt[2], center[3]});
  const Vec3 new_pt = transform_vector(pt, axis_rotate(axis, angle));
  for (int i = 0; i < 3; i++) {
    const Vec3 p = transform_vector(new_pt, rotate(kZ, double(i) * 2.0 * kPi / 3.0));
    w.sphere({p[0] + center[0], p[1] + center[1], p[2] + center[2], center[3]});
  }
}

}  // namespace

void mount(Writer& w, int size) {
  w.background(kSkyBlue);
  w.viewpoint({-1.6, 1.6, 1.7}, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, 45.0, 0.01, 512, 512);
  w.light({-100.0, -100.0, 100.0, 1.0});
  // Crystal spheres: clear white.
  w.color({1.0, 1.0, 1.0}, 0.0, 0.1, 0.1, 0.4, 6.7, 0.9, 1.5);
  crystal_spheres(w, {-0.8, 0.8, 1.00, 0.17});
  // Mountain: grey.
  w.color({0.5, 0.45, 0.35}, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  const int num_pts = 1 << size;
  const double ratio = 2.0 / std::exp(std::log(2.0) / (kFractalDimension - 1.0));
  const Mountain m{w, size, std::sqrt(ratio * ratio - 1.0), double(num_pts)};
  m.grow(num_pts, 0, 0, 0.0, 0.0, 0.0, 0.0);
}

}  // namespace lockstep::spd
