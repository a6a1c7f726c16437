// lockstep optimized: the simd z-buffer set-up's hidden spheres (the image
// only): the occlusion map (its queries here, inline: the sphere step asks one
// per triangle; its building in zbuffer_occlusion.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/raster.h"
#include "optimized/zbuffer/zbuffer_simd_kernels.h"

namespace lockstep::opt::zsimd {

// (The z-buffer's image only.) A sphere whose every sample is already covered
// by a nearer sphere's mesh can never pass the depth test, whatever the order:
// it is not tessellated at all, and of the other spheres, no triangle whose
// samples are all so covered is kept. The image is the same: only triangles
// that would lose every depth test are left out.
//
// The occluders. A sphere's tessellation (unit_sphere) is a convex polyhedron
// inscribed in it, so it contains the ball of radius r h (h: the smallest
// distance from the unit sphere's centre to a face plane). A sample whose ray
// meets that ball crosses the mesh: the mesh is closed and the fill rule
// watertight, so a kept triangle covers it: the front face where the ray
// enters, before it reaches the ball, or the inside-out sphere's far face, at
// eye depth at most z + r (every point of the mesh is in the sphere). The ball
// is shrunk by 2 px of its farthest depth first, for the snapping (the drawn
// surface is the mesh with its vertices moved by 1/512 px) and for the slivers
// seen edge-on at the silhouette, and only spheres wholly past the hither plane
// count (no clipping). Per cell of 4 x 4 pixels the map keeps the nearest bound
// of the spheres whose shrunk ball covers the whole cell (its four corners'
// rays: the ball's image is convex): the largest of the four corner rays' entry
// depths into the ball (the entry depth is quasi-convex over the screen: the
// points whose ray enters by depth Z are the image of ball and half-space
// z <= Z, a convex set, so its maximum over a cell is at a corner), z + r for
// an inside-out sphere.
//
// The test. Something at eye depth >= z_min with all its samples in a box of
// cells is hidden when every cell's bound z_occ is nearer by a margin that
// outlasts the depth formats' rounding: window depth (1/n - 1/z) / (1/n - 1/f)
// 1e-5 apart (float and 24-bit codes: ~170 steps near 1) and z 1e-5 apart
// relatively (reversed n / z in float). The map keeps, per cell, the depth
// beyond which that holds, so the test is a maximum and one comparison. A
// triangle's depth is at least its nearest vertex's (up to the plane's few
// ulps); a sphere's at least z - r. Boxes over many cells read coarse cells of
// 8 x 8 pixels instead, each the largest bound of its four (fewer to read, the
// test no less safe). (8 x 8 cells alone hid 68k of balls-3's triangles at
// 1024^2, 4 x 4 ones hide 76k; the corner rays a vector at a time, ball_entries,
// keep the finer map's cost below what it saves.)
class OcclusionMap {
 public:
  static constexpr int kCell = kOcclusionCell;

  OcclusionMap(const Camera& cam, int width, int height, double near_z, double far_z)
      : cam_(cam),
        width_(width),
        height_(height),
        nx_((width + kCell - 1) / kCell),
        ny_((height + kCell - 1) / kCell),
        cnx_((nx_ + 1) / 2),
        cny_((ny_ + 1) / 2),
        near_(near_z),
        inv_near_(1 / near_z),
        range_(1 / near_z - 1 / far_z),
        // (One more: triangle_step reads cells in pairs, the last one's
        // neighbour too, and ignores it.)
        z_(size_t(nx_) * size_t(ny_) + size_t(cnx_) * size_t(cny_) + 1, kInfinity) {}

  // The pixels [i0, i1] x [j0, j1] (clipped to the frame) that may hold a
  // sample of a mesh inscribed in the ball (eye-space centre ce, radius r):
  // the ball's image, found from its tangent planes through the eye, and a
  // pixel more. False when the ball is not wholly past the hither plane.
  bool sphere_box(const Vec3& ce, double r, int& i0, int& i1, int& j0, int& j1) const {
    if (!(ce.z - r > near_)) return false;
    double x_lo, x_hi, y_lo, y_hi;  // tangents x / z and y / z
    tangents(ce.x, ce.z, r, x_lo, x_hi);
    tangents(ce.y, ce.z, r, y_lo, y_hi);
    const double sx0 = 0.5 * width_ + x_lo / cam_.pitch, sx1 = 0.5 * width_ + x_hi / cam_.pitch;
    const double sy0 = 0.5 * height_ - y_hi / cam_.pitch, sy1 = 0.5 * height_ - y_lo / cam_.pitch;
    i0 = clamp_to(std::floor(sx0) - 1, width_);
    i1 = clamp_to(std::floor(sx1) + 1, width_);
    j0 = clamp_to(std::floor(sy0) - 1, height_);
    j1 = clamp_to(std::floor(sy1) + 1, height_);
    return std::isfinite(sx0 + sx1 + sy0 + sy1);
  }

  // The sphere (eye-space centre ce, radius r, inside out when inverted,
  // mesh's inner distance h per unit radius) as an occluder.
  void add(const Vec3& ce, double r, bool inverted, double h);

  // Whether everything at eye depth >= z_min with its samples in pixels
  // [i0, i1] x [j0, j1] loses to the occluders.
  // (The coarse cells: fewer to look at, each at least its cells' bounds.)
  bool hidden(int i0, int i1, int j0, int j1, double z_min) const {
    if (i0 > i1 || j0 > j1) return false;
    double beyond = -kInfinity;
    const double* coarse = z_.data() + coarse_at();
    for (int b = j0 / (2 * kCell); b <= j1 / (2 * kCell); ++b)
      for (int a = i0 / (2 * kCell); a <= i1 / (2 * kCell); ++a)
        beyond = std::max(beyond, coarse[size_t(b) * size_t(cnx_) + size_t(a)]);
    return z_min > beyond;
  }

  // The map for triangle_step.
  OcclusionCells cells() const { return {z_.data(), nx_, int(coarse_at()), cnx_}; }

  // After the last add: each cell's bound becomes the depth beyond which its
  // occluders hide (hidden_beyond, monotonic: the largest over cells decides),
  // and each coarse cell's the largest of its cells'.
  void finish();

 private:
  // x / z of the two planes through the eye (and the other axis) tangent to the
  // ball: (x - t z)^2 = r^2 (1 + t^2).
  static void tangents(double x, double z, double r, double& lo, double& hi) {
    const double a = z * z - r * r, root = r * std::sqrt(std::max(0.0, x * x + a));
    lo = (x * z - root) / a, hi = (x * z + root) / a;
  }
  static int clamp_to(double v, int n) { return int(std::clamp(v, 0.0, double(n - 1))); }
  size_t coarse_at() const { return size_t(nx_) * size_t(ny_); }
  // The eye depth beyond which something is hidden by an occluder at z_occ:
  // 1e-5 further relatively, and 1e-5 further in window depth
  // (1/n - 1/z) / (1/n - 1/f), i.e. 1/z < 1/z_occ - 1e-5 (1/n - 1/f); +inf for
  // no occluder.
  double hidden_beyond(double z_occ) const;

  const Camera& cam_;
  int width_, height_, nx_, ny_, cnx_, cny_;  // cells of kCell px a row and column; coarse ones
  double near_, inv_near_, range_;
  // Per cell: the nearest bound of a sphere covering it whole, +inf for none;
  // after finish, hidden_beyond of it.
  std::vector<double> z_;
  std::vector<double> entry_;  // add's corners' entry depths
};

}  // namespace lockstep::opt::zsimd
