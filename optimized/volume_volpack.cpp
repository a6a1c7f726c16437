// lockstep optimized: the volume family's production peer, VolPack's
// shear-warp (Lacroute and Levoy, SIGGRAPH 1994), through its C API.
//
// What VolPack is given (the reference's contract, core/volume_render.h, as
// closely as its API allows):
//   voxels   one 16-bit field per voxel: the sample value quantized over the
//            volume's [min, max]. Integer-valued volumes spanning at most 65536
//            values (the 12-bit CT head, the 8-bit MRI) are stored exactly
//            (q = v - min); others in 65536 levels (analytic fields: a step of
//            1.5e-5 of their range).
//   opacity  the classifier table, per quantized value: the transfer
//            function's alpha at that value. VolPack stores each voxel's
//            opacity in 8 bits (truncating: table entries are biased by half a
//            step so that it rounds) and corrects it per slice for the
//            ray's length through the slice in *voxel-index* units,
//            1 - (1 - a)^sqrt(1 + shear_i^2 + shear_j^2). The reference
//            corrects per dt / dt0 with dt0 the smallest spacing in *world*
//            units; in a parallel view the two lengths differ by one factor,
//            r = 1 / (h |(dir_x / s_x, dir_y / s_y, dir_z / s_z)|) (h the
//            smallest spacing s), so the table holds 1 - (1 - alpha)^r: exact
//            up to the 8-bit quantization (r = 1 for cubic voxels; for the CT
//            head's 1x1x2 mm voxels it depends on the view, so the
//            classification is made per view).
//   colour   a lookup shader with one material whose colour field is the same
//            16-bit value: color_table[q] = 255 x the transfer function's rgb
//            at q. No lights, no vpShadeTable: the voxel's colour is the TF's.
//   view     the reference's parallel view: one affine map from voxel index to
//            VolPack's clip coordinates (model matrix; view and projection the
//            identity) such that VolPack's output pixel (x, H-1-y), whose
//            centre its warp puts at integer image coordinates, is our pixel
//            (x, y) with its centre at corner + (x+1/2) du + (y+1/2) dv. VolPack
//            scales the volume so that its longest side (in voxels) spans 1
//            (its "prematrix"); the model matrix undoes that.
//   eps      VP_MAX_RAY_OPACITY = 1 - eps (its early ray termination); eps = 0: 1.
//
// Where it differs, by method (measured in registry/volume_rows.cpp):
//   - classification before interpolation: VolPack classifies and shades each
//     voxel, then resamples the (opacity-weighted) colours and opacities
//     bilinearly within each slice; the reference interpolates the value
//     trilinearly and classifies the sample. At sharp transfer-function edges
//     (bone) the two differ most;
//   - one sample per slice along the principal axis, not every dt along the ray;
//   - the intermediate image at voxel resolution is warped (bilinear) to the
//     output: detail finer than a voxel is blurred;
//   - 8-bit opacities per voxel (after the correction above) and an 8-bit
//     RGBA result, truncated by its warp: we return (b + 1/2) / 255 for a byte
//     b > 0 (the middle of the interval b stands for), 0 for 0 (the background
//     stays transparent) and 1 for 255. The colour is premultiplied (VolPack
//     composites opacity-weighted colours; its alpha is the pixel's opacity).
//
// VolPack has no threads: threaded = false. Volumes are limited to
// VP_MAX_VOLUME_DIM (1024) samples per side.
#include "optimized/volume_volpack.h"

#ifdef LOCKSTEP_HAVE_VOLPACK

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

#include "core/error.h"
#include "core/timer.h"
#include "core/volume_render.h"
#include "io/volume_settings.h"
#include "optimized/peer_module.h"

namespace lockstep::opt::volpack {

namespace {

// The volume's values as 16-bit indices, and what each index stands for.
struct Quantized {
  std::vector<uint16_t> q;  // one per voxel, i fastest (VolPack's x stride 2 bytes)
  int qmax = 0;             // largest index
  double lo = 0, step = 1;  // index k stands for lo + k step
};

Quantized quantize(const Volume& v) {
  Quantized out;
  const auto [mn, mx] = std::minmax_element(v.data.begin(), v.data.end());
  const double lo = *mn, hi = *mx;
  bool integral = hi - lo <= 65535;
  for (size_t i = 0; integral && i < v.data.size(); ++i) integral = v.data[i] == std::floor(v.data[i]);
  out.lo = lo;
  out.q.resize(v.data.size());
  if (integral) {
    out.step = 1;
    out.qmax = int(hi - lo);
    for (size_t i = 0; i < v.data.size(); ++i) out.q[i] = uint16_t(double(v.data[i]) - lo);
  } else {
    out.qmax = 65535;
    out.step = (hi - lo) / 65535;
    const double scale = 65535 / (hi - lo);
    for (size_t i = 0; i < v.data.size(); ++i)
      out.q[i] = uint16_t(std::clamp(std::lround((double(v.data[i]) - lo) * scale), 0L, 65535L));
  }
  return out;
}

// The tables VolPack reads during classification and rendering (it never frees
// or copies them): declared before the context, so they outlive it.
struct Tables {
  std::vector<float> opacity;  // qmax + 1
  std::vector<float> colour;   // (qmax + 1) x 3, 0..255
};

Tables make_tables(const vr::Settings& s, const Quantized& qz, double r) {
  Tables t;
  const size_t n = size_t(qz.qmax) + 1;
  t.opacity.resize(n);
  t.colour.resize(3 * n);
  for (size_t k = 0; k < n; ++k) {
    double rgba[4];
    s.tf.eval(qz.lo + double(k) * qz.step, rgba);
    // The opacity VolPack should see per index-space unit (see the top), rounded
    // to its 8 bits: it truncates opacity x 255, so aim at the middle of the step.
    const double a = vr::correct_opacity(rgba[3], r);
    const double level = std::round(a * 255);
    t.opacity[k] = level <= 0 ? 0.0f : float(std::min((level + 0.5) / 255, 1.0));
    for (int c = 0; c < 3; ++c) t.colour[3 * k + c] = float(255 * rgba[c]);
  }
  return t;
}

// VolPack's own prematrix (vp_view.c): voxel index -> its object space, the
// longest side spanning 1, centred at n/2. Its inverse goes into the model matrix.
void inverse_prematrix(const Volume& v, double m[4][4]) {
  const double maxdim = std::max({v.nx, v.ny, v.nz});
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m[i][j] = i == j ? 1 : 0;
  m[0][0] = m[1][1] = m[2][2] = maxdim;
  m[0][3] = 0.5 * v.nx;
  m[1][3] = 0.5 * v.ny;
  m[2][3] = 0.5 * v.nz;
}

}  // namespace

bool available() { return !peer::find_module("volpack").empty(); }

// Recorded beside the module when it was built (cmake/peer_version.cpp), so
// that --version does not load VolPack.
std::string version() {
  const std::string v = peer::recorded_version("volpack");
  return v.empty() ? "version not recorded (" + peer::module_file("volpack") + " has no .version beside it)" : v;
}

Image render_path(const Volume& volume, const FrameOptions& options, Path path, Times* times) {
  const vr::Settings s = vr::settings(options.params, volume.source, vr::Mode::kRaycast);
  const vr::View view = vr::make_view(volume, s, options.width, options.height);
  const int W = options.width, H = options.height;
  const auto* api = static_cast<const ModuleApi*>(peer::open_api("volpack", kAbi));
  if (std::max({volume.nx, volume.ny, volume.nz}) > api->max_volume_dim)
    throw InputError(volume.source, 0,
                     "volpack: VolPack takes at most " + std::to_string(api->max_volume_dim) + " samples per side, got " +
                         std::to_string(volume.nx) + "x" + std::to_string(volume.ny) + "x" + std::to_string(volume.nz));
  if (volume.nx < 2 || volume.ny < 2 || volume.nz < 2)
    throw InputError(volume.source, 0, "volpack: the volume needs at least 2 samples per side");

  // The opacity exponent that turns VolPack's per-slice correction into the reference's.
  const double h = std::min({volume.spacing.x, volume.spacing.y, volume.spacing.z});
  const Vec3 d_index{view.dir.x / volume.spacing.x, view.dir.y / volume.spacing.y, view.dir.z / volume.spacing.z};
  const double r = 1 / (h * length(d_index));

  Stopwatch clock;
  const Quantized qz = quantize(volume);
  Tables tables = make_tables(s, qz, r);
  const double prepare_seconds = clock.seconds();
  std::vector<unsigned char> pixels(size_t(W) * size_t(H) * 4);

  // The view: voxel index -> VolPack clip coordinates. x_c = 2 (u - 1/2) / W - 1,
  // y_c = 2 (H - v - 1/2) / H - 1 with (u, v) our continuous pixel coordinates
  // (centres at half-integers, v down); z_c = -(depth - centre) / R towards the eye.
  const Vec3 centre = 0.5 * (view.lo + view.hi);
  const double R = 1.01 * std::max(0.5 * length(view.hi - view.lo), 1e-12);
  const double du2 = dot(view.du, view.du), dv2 = dot(view.dv, view.dv);
  double A[4][4] = {};
  const Vec3 sp = volume.spacing;
  // Row of an affine map world -> coordinate, w . p + w0, composed with index -> world.
  auto row = [&](int i, const Vec3& w, double w0) {
    A[i][0] = w.x * sp.x;
    A[i][1] = w.y * sp.y;
    A[i][2] = w.z * sp.z;
    A[i][3] = dot(w, volume.origin) + w0;
  };
  // u = (p - corner) . du / |du|^2
  const Vec3 wx = (2.0 / W / du2) * view.du;
  row(0, wx, -dot(wx, view.corner) - 1.0 / W - 1);
  const Vec3 wy = (-2.0 / H / dv2) * view.dv;
  row(1, wy, -dot(wy, view.corner) + 1 - 1.0 / H);
  const Vec3 wz = (-1 / R) * view.dir;
  row(2, wz, -dot(wz, centre));
  A[3][3] = 1;
  double P[4][4], M[4][4];
  inverse_prematrix(volume, P);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      M[i][j] = 0;
      for (int k = 0; k < 4; ++k) M[i][j] += A[i][k] * P[k][j];
    }
  Request q;
  q.voxels = qz.q.data();
  q.nx = volume.nx, q.ny = volume.ny, q.nz = volume.nz;
  q.qmax = qz.qmax;
  q.opacity = tables.opacity.data();
  q.colour = tables.colour.data();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) q.model[i][j] = M[i][j];
  q.max_ray_opacity = s.eps > 0 ? 1 - s.eps : 1.0;
  q.width = W, q.height = H;
  q.path = path;
  double classify_seconds = 0, render_seconds = 0;
  api->render(q, pixels.data(), &classify_seconds, &render_seconds);

  // VolPack's rows run bottom-up; its bytes were truncated (see the top).
  Image image = Image::uninitialized(W, H);
  auto value = [](unsigned char b) { return b == 0 ? 0.0f : b == 255 ? 1.0f : float((b + 0.5) / 255); };
  for (int y = 0; y < H; ++y) {
    const unsigned char* src = pixels.data() + size_t(H - 1 - y) * size_t(W) * 4;
    float* dst = image.pixel(0, y);
    for (int i = 0; i < 4 * W; ++i) dst[i] = value(src[i]);
  }
  if (options.progress) options.progress(1.0);
  if (times) *times = {prepare_seconds, classify_seconds, render_seconds};
  return image;
}

Image volume_raycast(const Volume& volume, const FrameOptions& options, FrameStats* stats) {
  Times t;
  Image image = render_path(volume, options, Path::kClassified, &t);
  if (stats) {
    stats->build_seconds = t.prepare + t.classify;  // the one-shot classification, ours and VolPack's
    stats->items = uint64_t(image.width) * uint64_t(image.height);
  }
  return image;
}

}  // namespace lockstep::opt::volpack

#else  // no VolPack: the row is not registered (registry/volume_rows.cpp asks available()).

#include "core/error.h"

namespace lockstep::opt::volpack {

bool available() { return false; }
std::string version() { return {}; }
Image volume_raycast(const Volume& volume, const FrameOptions&, FrameStats*) {
  throw InputError(volume.source, 0, "volpack: this build has no VolPack (install libvolpack1-dev and re-run cmake)");
}
Image render_path(const Volume& volume, const FrameOptions& o, Path, Times*) { return volume_raycast(volume, o, nullptr); }

}  // namespace lockstep::opt::volpack

#endif
