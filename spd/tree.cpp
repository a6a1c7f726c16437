// lockstep spd: tree (Eric Haines' SPD tree.c, after Aono & Kunii, IEEE CG&A
// May 1984): a binary tree of cone branches with spheres at the joints,
// 2^(size+1)-1 of each, on a field square; seven lights.
#include <array>

#include "spd/scenes.h"

namespace lockstep::spd {

namespace {

constexpr double kBranchAngle[2] = {40.0, 25.0};
constexpr double kContraction[2] = {0.65, 0.70};
constexpr double kDiameter = 0.67;
constexpr double kDivergence = 140.0;
constexpr double kWidthHeightRatio = 0.15;

// A branch from 0 to +Z in cur's frame, then its two children (tree.c grow_tree).
void grow(Writer& w, const std::array<Matrix, 2>& rst, const Matrix& cur, double scale, int depth) {
  const Vec3 b = transform_point({0.0, 0.0, 0.0}, cur), a = transform_point({0.0, 0.0, 1.0}, cur);
  const Vec4 base = {b[0], b[1], b[2], scale * kWidthHeightRatio};
  const Vec4 apex = {a[0], a[1], a[2], base[3] * kDiameter};
  w.cylcone(base, apex);
  w.sphere(apex);
  if (depth <= 0) return;
  for (int i = 0; i < 2; ++i)
    grow(w, rst, multiply(rst[size_t(i)], cur), scale * kDiameter, depth - 1);
}

}  // namespace

void tree(Writer& w, int size) {
  w.background(kSkyBlue);
  w.viewpoint({4.5, 0.4, 2.0}, {0.0, 0.0, 1.5}, {0.0, 0.0, 1.0}, 45.0, 1.0, 512, 512);
  for (const Vec4& l :
       {Vec4{-5.0, 5.0, 50.0, 1.0}, Vec4{30.0, -30.0, 30.0, 1.0}, Vec4{-40.0, -30.0, 20.0, 1.0},
        Vec4{10.0, 30.0, 40.0, 1.0}, Vec4{-30.0, 40.0, 10.0, 1.0}, Vec4{50.0, 25.0, 20.0, 1.0},
        Vec4{-10.0, -60.0, 30.0, 1.0}})
    w.light(l);
  // Field: green.
  w.color({0.2, 0.7, 0.2}, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  w.polygon({{50.0, 50.0, 0.0}, {-50.0, 50.0, 0.0}, {-50.0, -50.0, 0.0}, {50.0, -50.0, 0.0}});
  // Tree: brown.
  w.color({0.55, 0.4, 0.2}, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  // Each child's frame relative to its parent: turned about X by the
  // branching angle, about Z by the divergence, shrunk, moved to the tip.
  std::array<Matrix, 2> rst;
  for (int i = 0; i < 2; ++i) {
    const double divergence = i == 0 ? 90.0 : kDivergence + 90.0;
    const Matrix r =
        multiply(rotate(kX, kBranchAngle[i] * kPi / 180.0), rotate(kZ, divergence * kPi / 180.0));
    Matrix st = identity();
    st[0][0] = st[1][1] = st[2][2] = kContraction[i];
    st[3][2] = 1.0;
    rst[size_t(i)] = multiply(r, st);
  }
  grow(w, rst, identity(), 1.0, size);
}

}  // namespace lockstep::spd
