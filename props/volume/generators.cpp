// lockstep props/volume: the case generator (see generators.h).
#include "props/volume/generators.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "io/volume_io.h"
#include "props/gen/numbers.h"

namespace lockstep::props::volume {

namespace {

double range_lo(const Volume& v) { return *std::min_element(v.data.begin(), v.data.end()); }
double range_hi(const Volume& v) { return *std::max_element(v.data.begin(), v.data.end()); }

rc::Gen<Volume> gen_volume(bool blobs_only) {
  return rc::gen::exec([blobs_only] {
    Volume v;
    const int64_t kind = blobs_only ? 0 : *gen::int_in(0, 2);  // 0 smooth blobs, 1 analytic, 2 rough
    if (kind == 1) {
      FieldSpec f = field_defaults(FieldKind(*gen::int_in(0, 3)));
      f.n = int(*gen::int_in(4, 40));
      v = sample_field(f, "<generated>");
    } else {
      v.nx = int(*gen::int_in(4, 40));
      v.ny = int(*gen::int_in(4, 40));
      v.nz = int(*gen::int_in(4, 40));
      v.data.resize(size_t(v.nx) * size_t(v.ny) * size_t(v.nz));
      if (kind == 2) {
        for (float& x : v.data) x = float(*gen::int_in(0, 100)) / 100;
      } else {
        const int blobs = int(*gen::int_in(1, 5));
        struct Blob {
          double x, y, z, r, a;
        };
        std::vector<Blob> b;
        for (int q = 0; q < blobs; ++q)
          b.push_back({*gen::uniform(0, 1), *gen::uniform(0, 1), *gen::uniform(0, 1), *gen::uniform(0.05, 0.4),
                       *gen::uniform(0.2, 1)});
        for (int k = 0; k < v.nz; ++k)
          for (int j = 0; j < v.ny; ++j)
            for (int i = 0; i < v.nx; ++i) {
              const double x = double(i) / (v.nx - 1), y = double(j) / (v.ny - 1), z = double(k) / (v.nz - 1);
              double f = 0;
              for (const Blob& q : b)
                f += q.a * std::exp(-((x - q.x) * (x - q.x) + (y - q.y) * (y - q.y) + (z - q.z) * (z - q.z)) / (q.r * q.r));
              v.at(i, j, k) = float(f);
            }
      }
    }
    // Anisotropic spacing (ratios up to 4) at any scale, anywhere.
    const double scale = *gen::log_uniform(0.01, 100);
    v.spacing = {scale * *gen::log_uniform(0.5, 2), scale * *gen::log_uniform(0.5, 2), scale * *gen::log_uniform(0.5, 2)};
    v.origin = {scale * *gen::uniform(-50, 50), scale * *gen::uniform(-50, 50), scale * *gen::uniform(-50, 50)};
    v.source = "<generated>";
    return v;
  });
}

// 2 to 8 control points over [lo, hi] widened by a fifth; transparent: every
// alpha 0; clear_low: the first two points transparent, the second at least a
// twentieth into the range (low values clear, as ct-bone's air: empty space).
rc::Gen<std::vector<ControlPoint>> gen_tf(double lo, double hi, bool transparent, bool clear_low) {
  return rc::gen::exec([lo, hi, transparent, clear_low] {
    const int n = int(*gen::int_in(2, 8));
    const double r = std::max(hi - lo, 1e-3);
    std::vector<double> xs;
    for (int q = 0; q < n; ++q) xs.push_back(lo - 0.2 * r + 1.4 * r * double(*gen::int_in(0, 1000)) / 1000);
    if (clear_low) {
      xs[0] = lo - 0.2 * r;
      xs[1] = lo + r * double(*gen::int_in(50, 600)) / 1000;
      for (size_t q = 2; q < xs.size(); ++q) xs[q] = xs[1] + (hi + 0.2 * r - xs[1]) * double(*gen::int_in(1, 1000)) / 1000;
    }
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
    std::vector<ControlPoint> tf;
    // Points below the cut are transparent (a threshold, as ct-bone), the
    // others a quarter of the time.
    const size_t cut = clear_low ? 2 : size_t(*gen::int_in(0, int64_t(xs.size())));
    for (double x : xs) {
      ControlPoint p;
      p.value = x;
      p.r = float(*gen::int_in(0, 255)) / 255;
      p.g = float(*gen::int_in(0, 255)) / 255;
      p.b = float(*gen::int_in(0, 255)) / 255;
      p.a = transparent || tf.size() < cut || *gen::chance(1, 4) ? 0.0f : float(*gen::int_in(0, 1000)) / 1000;
      tf.push_back(p);
    }
    return tf;
  });
}

}  // namespace

// empty: smooth fields (blobs) and a transfer function clear at low values,
// so that much of the volume is empty space to skip.
rc::Gen<VrCase> gen_case(bool transparent, bool empty) {
  return rc::gen::exec([transparent, empty] {
    VrCase c;
    c.volume = *gen_volume(empty);
    const double lo = range_lo(c.volume), hi = range_hi(c.volume);
    c.tf = *gen_tf(lo, hi, transparent, empty || *gen::chance(1, 2));
    c.width = int(*gen::int_in(4, 32));
    c.height = int(*gen::int_in(4, 32));
    c.az = *gen::uniform(-180, 180);
    c.el = *gen::chance(1, 20) ? (*gen::chance(1, 2) ? 90.0 : -90.0) : *gen::uniform(-89, 89);
    c.roll = *gen::chance(1, 4) ? 0.0 : *gen::uniform(-180, 180);
    // A quarter of the views with image rows along the volume's x axis (simd's
    // row loads instead of gathers: neighbouring rays read the same rows).
    if (*gen::chance(1, 4)) {
      c.az = *gen::chance(1, 2) ? 90.0 : -90.0;
      c.roll = *gen::chance(1, 2) ? 0.0 : 180.0;
    }
    static constexpr double kSteps[] = {0.25, 0.5, 0.75, 1, 1.3, 2};
    c.step = kSteps[*gen::int_in(0, 5)];
    static constexpr double kEps[] = {1.0 / 256, 1.0 / 256, 0.02, 0.1, 0};
    c.eps = kEps[*gen::int_in(0, 4)];
    c.iso = lo + (hi - lo) * double(*gen::int_in(1, 99)) / 100;
    return c;
  });
}

}  // namespace lockstep::props::volume
