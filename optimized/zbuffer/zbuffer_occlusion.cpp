// lockstep optimized: the simd z-buffer set-up's occlusion map, built
// (optimized/zbuffer/zbuffer_occlusion.h: what it is, why the test is safe, and its
// queries): each sphere's inner ball as an occluder of the cells it covers
// whole, then each cell's bound turned into the depth beyond which it hides.
#include "optimized/zbuffer/zbuffer_occlusion.h"

namespace lockstep::opt::zsimd {

// The sphere (eye-space centre ce, radius r, inside out when inverted,
// mesh's inner distance h per unit radius) as an occluder.
void OcclusionMap::add(const Vec3& ce, double r, bool inverted, double h) {
  int i0, i1, j0, j1;
  if (!sphere_box(ce, r, i0, i1, j0, j1)) return;
  const double rho = r * h * (1 - 1e-9) - 2 * cam_.pitch * (ce.z + r);
  if (!(rho > 0)) return;
  const double z_occ = ce.z + r;
  // Cells wholly inside [i0, i1 + 1) x [j0, j1 + 1); their corners on the grid of cells.
  const int a0 = (i0 + kCell - 1) / kCell, a1 = (i1 + 1) / kCell;  // cells [a0, a1)
  const int b0 = (j0 + kCell - 1) / kCell, b1 = (j1 + 1) / kCell;
  if (a0 >= a1 || b0 >= b1) return;
  const int na = a1 - a0 + 1;
  entry_.resize(size_t(na) * size_t(b1 - b0 + 1));
  // The rays through the corners (a, b) of cells, a row at a time.
  const double centre[3] = {ce.x, ce.y, ce.z};
  for (int b = b0; b <= b1; ++b)
    ball_entries(centre, rho * rho, inverted, z_occ, cam_.pitch, 0.5 * width_,
                 (0.5 * height_ - b * kCell) * cam_.pitch, kCell, a0, na,
                 entry_.data() + size_t(b - b0) * size_t(na));
  for (int b = b0; b < b1; ++b)
    for (int a = a0; a < a1; ++a) {
      const size_t k = size_t(b - b0) * size_t(na) + size_t(a - a0);
      // (+inf where a corner is outside: the cell is not covered.)
      const double bound =
          std::max({entry_[k], entry_[k + 1], entry_[k + size_t(na)], entry_[k + size_t(na) + 1]});
      if (bound < kInfinity) {
        double& z = z_[size_t(b) * size_t(nx_) + size_t(a)];
        z = std::min(z, std::min(bound, z_occ));
      }
    }
}

// After the last add: each cell's bound becomes the depth beyond which its
// occluders hide (hidden_beyond, monotonic: the largest over cells decides),
// and each coarse cell's the largest of its cells'.
void OcclusionMap::finish() {
  double* coarse = z_.data() + coarse_at();
  for (size_t k = 0; k < coarse_at(); ++k) z_[k] = hidden_beyond(z_[k]);
  for (int b = 0; b < cny_; ++b)
    for (int a = 0; a < cnx_; ++a) {
      double m = -kInfinity;
      for (int y = 2 * b; y < std::min(2 * b + 2, ny_); ++y)
        for (int x = 2 * a; x < std::min(2 * a + 2, nx_); ++x)
          m = std::max(m, z_[size_t(y) * size_t(nx_) + size_t(x)]);
      coarse[size_t(b) * size_t(cnx_) + size_t(a)] = m;
    }
}

// The eye depth beyond which something is hidden by an occluder at z_occ:
// 1e-5 further relatively, and 1e-5 further in window depth
// (1/n - 1/z) / (1/n - 1/f), i.e. 1/z < 1/z_occ - 1e-5 (1/n - 1/f); +inf for
// no occluder.
double OcclusionMap::hidden_beyond(double z_occ) const {
  if (!(z_occ < kInfinity)) return kInfinity;
  const double inv = 1 / z_occ - 1e-5 * range_;
  return inv > 0 ? std::max(z_occ * (1 + 1e-5), 1 / inv) : kInfinity;
}

}  // namespace lockstep::opt::zsimd
