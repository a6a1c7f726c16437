// lockstep reference: splatting, as the lecture notes give it.
//
// Westover, "Footprint Evaluation for Volume Rendering", SIGGRAPH 1990;
// Zwicker et al., "EWA Volume Splatting", IEEE Visualization 2001 (the
// footprint of a Gaussian kernel under projection). Object order instead of
// image order: every voxel throws its contribution at the image.
//   1. classify each voxel by the transfer function (colour c, opacity alpha
//      for a reference step dt0); alpha = 0 voxels contribute nothing;
//   2. the voxel stands for a Gaussian blob of extinction: a voxel of volume V
//      whose opacity per dt0 is alpha has extinction sigma = -ln(1 - alpha)/dt0
//      per unit length, spread as sigma V G(x), G a 3-D Gaussian of unit
//      integral with standard deviation kSigma times the spacing on each axis;
//   3. under a parallel projection the blob's footprint on the image is the
//      2-D Gaussian g with the projected covariance (P Sigma P^T): the optical
//      depth it adds at a pixel is tau = sigma V g(pixel - projected centre),
//      its opacity 1 - exp(-tau);
//   4. voxels are taken in depth order, front first, and each footprint is
//      composited *under* the image with premultiplied `over`, as the ray
//      caster composites its samples; a pixel that reached 1 - eps takes no more.
// Summed over a lattice, the footprints of a uniform region add up to the
// extinction per unit length the ray caster integrates, so the two methods
// converge to the same image; they differ where the reconstruction differs
// (the Gaussian blurs where trilinear interpolation does not, blobs overlap
// in depth where ray samples are ordered exactly) and at the box's faces
// (footprints reach past them). props/volume states by how much.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/volume_render.h"
#include "io/volume_settings.h"
#include "reference/volume_render.h"

namespace lockstep::ref {

namespace {

// The blob's standard deviation in spacings: with 0.6 a uniform lattice of
// blobs is flat to about 0.2% (the ripple of a sampled Gaussian), yet blurs
// little more than trilinear interpolation does.
constexpr double kSigma = vr::kSplatSigma;
// Footprints are cut off at 3 standard deviations (1.1% of the peak's extent... e^-4.5).
constexpr double kCutoff = vr::kSplatCutoff;

struct Splat {
  double depth;
  size_t index;
};

}  // namespace

Image volume_splat(const Volume& volume, const FrameOptions& options, FrameStats* stats) {
  const vr::Settings s = vr::settings(options.params, volume.source, vr::Mode::kSplat);
  const vr::View view = vr::make_view(volume, s, options.width, options.height);
  const double pixel = length(view.du);
  const Vec3 right = view.du / pixel, up = -view.dv / pixel;
  const double dt0 = std::min({volume.spacing.x, volume.spacing.y, volume.spacing.z});
  const double voxel_volume = volume.spacing.x * volume.spacing.y * volume.spacing.z;

  // 3. The footprint's covariance: the 3-D blob's, projected on (right, up).
  const Vec3 var{std::pow(kSigma * volume.spacing.x, 2), std::pow(kSigma * volume.spacing.y, 2),
                 std::pow(kSigma * volume.spacing.z, 2)};
  const double sxx = dot(mul(right, right), var), syy = dot(mul(up, up), var), sxy = dot(mul(right, up), var);
  const double det = sxx * syy - sxy * sxy;
  const double ixx = syy / det, iyy = sxx / det, ixy = -sxy / det;  // the inverse
  const double norm = 1.0 / (2 * std::numbers::pi * std::sqrt(det));
  const int reach_x = int(std::ceil(kCutoff * std::sqrt(sxx) / pixel));
  const int reach_y = int(std::ceil(kCutoff * std::sqrt(syy) / pixel));

  // 1. Classification; 4. depth order.
  std::vector<Splat> order;
  for (int k = 0; k < volume.nz; ++k)
    for (int j = 0; j < volume.ny; ++j)
      for (int i = 0; i < volume.nx; ++i) {
        double rgba[4];
        s.tf.eval(volume.at(i, j, k), rgba);
        if (rgba[3] > 0) order.push_back({dot(volume.position(i, j, k), view.dir), volume.index(i, j, k)});
      }
  std::stable_sort(order.begin(), order.end(), [](const Splat& a, const Splat& b) { return a.depth < b.depth; });

  // Accumulated in double, written as float at the end.
  std::vector<double> acc(size_t(view.width) * size_t(view.height) * 4, 0.0);
  // 4. Voxels of equal depth (a view along an axis puts whole slices
  // on one plane) form a sheet (Westover's sheet buffer): their optical depths
  // add up per pixel first, then the sheet goes under the image at once, so
  // the result does not depend on the order within the sheet (a mirrored
  // volume from the mirrored camera gives the mirrored image).
  std::vector<double> sheet(acc.size(), 0.0);  // per pixel: tau, tau r, tau g, tau b
  std::vector<size_t> touched;
  // "Equal" up to rounding: depths are dot products, and the mirrored volume's
  // are the same numbers summed in another order.
  const double tie = 1e-9 * length(view.hi - view.lo);
  double sheet_depth = 0;
  auto flush = [&] {
    for (const size_t px : touched) {
      double* t = &sheet[px * 4];
      double* p = &acc[px * 4];
      const double alpha = -std::expm1(-t[0]);
      // Under what is already in front; the colour is the sheet's
      // extinction-weighted mean.
      const double w = (1 - p[3]) * alpha;
      for (int ch = 0; ch < 3; ++ch) p[ch] += w * t[ch + 1] / t[0];
      p[3] += w;
      t[0] = t[1] = t[2] = t[3] = 0;
    }
    touched.clear();
  };
  for (size_t n = 0; n < order.size(); ++n) {
    const Splat& sp = order[n];
    if (n == 0 || sp.depth - sheet_depth > tie) {
      flush();
      sheet_depth = sp.depth;
    }
    const size_t i = sp.index % size_t(volume.nx), j = sp.index / size_t(volume.nx) % size_t(volume.ny),
                 k = sp.index / (size_t(volume.nx) * size_t(volume.ny));
    double rgba[4];
    s.tf.eval(volume.data[sp.index], rgba);
    // 2. Extinction; alpha = 1 is as opaque as a double can say.
    const double sigma = -std::log1p(-std::min(rgba[3], 1 - 1e-12)) / dt0;
    // Where the centre lands, in pixel coordinates (pixel x's centre at x).
    const Vec3 rel = volume.position(int(i), int(j), int(k)) - view.corner;
    const double cx = dot(rel, right) / pixel - 0.5, cy = -dot(rel, up) / pixel - 0.5;
    const int x0 = std::max(0, int(std::floor(cx)) - reach_x), x1 = std::min(view.width - 1, int(std::ceil(cx)) + reach_x);
    const int y0 = std::max(0, int(std::floor(cy)) - reach_y), y1 = std::min(view.height - 1, int(std::ceil(cy)) + reach_y);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const size_t px = size_t(y) * size_t(view.width) + size_t(x);
        if (s.eps > 0 && acc[px * 4 + 3] >= 1 - s.eps) continue;
        // The offset from the centre in world units along right and up.
        const double dx = (x - cx) * pixel, dy = (cy - y) * pixel;
        const double q = ixx * dx * dx + 2 * ixy * dx * dy + iyy * dy * dy;
        if (q > kCutoff * kCutoff) continue;
        // 3. The optical depth the footprint adds here.
        const double tau = sigma * voxel_volume * norm * std::exp(-0.5 * q);
        if (!(tau > 0)) continue;  // underflow: nothing to add (and no 0/0 in the flush)
        double* t = &sheet[px * 4];
        if (t[0] == 0) touched.push_back(px);
        t[0] += tau;
        for (int ch = 0; ch < 3; ++ch) t[ch + 1] += tau * rgba[ch];
      }
    if (options.progress && (n + 1) % 65536 == 0) options.progress(double(n + 1) / double(order.size()));
  }
  flush();
  Image image = Image::uninitialized(options.width, options.height);
  for (size_t n = 0; n < acc.size(); ++n) image.rgba[n] = float(acc[n]);
  if (stats) stats->items = uint64_t(view.width) * uint64_t(view.height);
  return image;
}

}  // namespace lockstep::ref
