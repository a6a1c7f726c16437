// lockstep props/volume: the volume-rendering families' properties (volume,
// volume_iso, splat; registry/volume_rows.cpp lists the parts each runs).
//
// A case is a small volume drawn by RapidCheck -- 4 to 40 samples per axis,
// random anisotropic spacing and origin; smooth fields (a few Gaussian blobs),
// rough ones (independent samples) or analytic ones (io/volume_io.h's
// sample_field: sphere, torus, gyroid, Marschner-Lobb, then stretched per axis)
// -- a transfer function of 2 to 8 control points over the field's range (the
// points below a random cut transparent, as ct-bone's, and a quarter of the
// others: so that macro cells are skipped), a view (azimuth,
// elevation, roll; a quarter with image rows along x), a step, eps, an iso value and a frame of 4 to 32 pixels a
// side. Its text form has every number as a hexfloat, so a counterexample
// replays bit for bit. The transfer function reaches the renderer as a .tf
// file written to the temporary directory (named by the hash of its text).
//
//   Agreement.<family>__<impl>   (part "agreement") the implementation's image
//       against the reference's at the same settings: every pixel's largest
//       channel difference within the family's tolerance (Family::tol.abs,
//       measured in float against double, registry/volume_rows.cpp: volume 6e-4 for a
//       measured 3.7e-4; volume_iso measured 0, the same image; splat 5e-5
//       for a measured 2.25e-5: the reference's footprints from tables, in
//       float). Failures print the case (seed, volume, settings) and each
//       pixel over: both outputs and the error. A pixel may
//       differ by up to eps where both rays stopped at the 1 - eps threshold:
//       float and double can cross it one sample apart (label
//       termination_flip, explained; both alphas at least 1 - eps - 1e-5, the
//       difference at most eps + tol; measured 1 to 4 pixels in 1.6M; splat:
//       a pixel stops taking footprints one splat apart, 13 in 3.3M).
//   SkipChangesNothing.volume__<impl>  (part "skip") noskip against skip: every
//       channel within 1e-6 (a skipped sample has alpha' exactly 0: measured 0);
//       and eps = 0 (never stop) against the case's eps > 0: every channel
//       within eps + 1e-5 (what stopping leaves out is at most (1 - A) <= eps).
//   TransparentGivesBackground.<family>__<impl>  (part "transparent") a transfer
//       function whose alphas are all 0: every pixel exactly (0, 0, 0, 0).
//   Mirror.<family>__<impl>      (part "mirror") the volume flipped along x
//       (sample i <-> nx - 1 - i, the same box), seen from azimuth 180 - az and
//       roll -roll: the image mirrored left-right, every channel within
//       kMirrorTol (the rays are the mirror images of each other up to the
//       rounding of their origins; termination flips as in Agreement). Splat
//       too: footprints of equal depth form one sheet, composited at once
//       (before: in index order, which the flip reverses; 1.3% of pixels
//       differed, up to 0.1, looking straight down the z axis).
#include <gtest/gtest.h>
#include <rapidcheck.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <unistd.h>

#include "core/error.h"
#include "core/image.h"
#include "core/transfer_function.h"
#include "core/volume.h"
#include "io/volume_io.h"
#include "props/gen/case_text.h"
#include "props/gen/numbers.h"
#include "props/property.h"

namespace lockstep::props::volume {

namespace {

// Mirror: the largest channel difference between an image and its mirrored
// counterpart. Measured: the reference 0 (its double rays mirror exactly on
// every case drawn), simd 2.9e-4 over 5 x 2000 cases (two float renders, each
// within the family's 6e-4 of the double one): 6e-4, 2x.
constexpr double kMirrorTol = 6e-4;

enum class Mode { kRaycast, kIso, kSplat };

Mode mode_of(const Family& f) {
  return f.name == "volume_iso" ? Mode::kIso : f.name == "splat" ? Mode::kSplat : Mode::kRaycast;
}

// ---------------------------------------------------------------- cases

struct VrCase {
  Volume volume;
  std::vector<ControlPoint> tf;
  int width = 16, height = 16;
  double az = 30, el = 20, roll = 0, step = 0.5, eps = 1.0 / 256, iso = 0.5;
};

using gen::hex;

std::string tf_text(const std::vector<ControlPoint>& tf) {
  std::string s;
  for (const ControlPoint& p : tf)
    s += hex(p.value) + " " + hex(p.r) + " " + hex(p.g) + " " + hex(p.b) + " " + hex(p.a) + "\n";
  return s;
}

std::string write_case(const VrCase& c) {
  const Volume& v = c.volume;
  std::ostringstream s;
  s << "vr_case " << v.nx << " " << v.ny << " " << v.nz << " size " << c.width << " " << c.height << "\n";
  gen::write_geometry(s, v);
  s << "view " << hex(c.az) << " " << hex(c.el) << " " << hex(c.roll) << " step " << hex(c.step) << " eps "
    << hex(c.eps) << " iso " << hex(c.iso) << "\n";
  s << "tf " << c.tf.size() << "\n" << tf_text(c.tf);
  gen::write_samples(s, v);
  return s.str();
}

VrCase read_case(const std::string& text, const std::string& file) {
  std::istringstream s(gen::without_comments(text));
  auto num = [&](const std::string& w) { return std::strtod(w.c_str(), nullptr); };
  auto expect = [&](const char* what) {
    std::string w;
    if (!(s >> w) || w != what) throw InputError(file, 0, std::string("expected '") + what + "'");
  };
  auto next = [&] {
    std::string w;
    if (!(s >> w)) throw InputError(file, 0, "the case ends early");
    return num(w);
  };
  VrCase c;
  Volume& v = c.volume;
  expect("vr_case");
  v.nx = int(next()), v.ny = int(next()), v.nz = int(next());
  if (v.nx < 2 || v.ny < 2 || v.nz < 2 || v.nx > 256 || v.ny > 256 || v.nz > 256)
    throw InputError(file, 0, "volume sizes must lie in 2..256");
  expect("size");
  c.width = int(next()), c.height = int(next());
  gen::read_geometry(s, v, file);
  expect("view");
  c.az = next(), c.el = next(), c.roll = next();
  expect("step");
  c.step = next();
  expect("eps");
  c.eps = next();
  expect("iso");
  c.iso = next();
  expect("tf");
  const int n = int(next());
  for (int q = 0; q < n; ++q) {
    ControlPoint p;
    p.value = next();
    p.r = float(next()), p.g = float(next()), p.b = float(next()), p.a = float(next());
    c.tf.push_back(p);
  }
  gen::read_samples(s, v, file);
  v.source = file;
  return c;
}

// ---------------------------------------------------------------- running

// The case's transfer function as a .tf file (named by its text's hash: the
// same function, the same file, whoever writes it).
std::string tf_file(const std::vector<ControlPoint>& tf) {
  const std::string text = tf_text(tf);
  const auto dir = std::filesystem::temp_directory_path() / "lockstep-props-volume";
  std::filesystem::create_directories(dir);
  const std::string path =
      (dir / (std::to_string(::getpid()) + "-" + std::to_string(std::hash<std::string>{}(text)) + ".tf")).string();
  if (!std::filesystem::exists(path)) {
    const std::string tmp = path + ".tmp";
    {
      std::ofstream f(tmp);
      f << text;
    }
    std::filesystem::rename(tmp, path);
  }
  return path;
}

struct Overrides {
  bool noskip = false;
  double eps = -1;  // >= 0: instead of the case's
};

Image render(const FamilyImpl& impl, Mode mode, const VrCase& c, Overrides ov = {}) {
  FrameOptions o;
  o.width = c.width;
  o.height = c.height;
  o.threads = 1;
  o.params.set("view", hex(c.az) + "," + hex(c.el) + "," + hex(c.roll));
  if (!c.tf.empty()) o.params.set("tf", tf_file(c.tf));
  if (mode != Mode::kSplat) o.params.set("step", hex(c.step));
  if (mode == Mode::kIso) {
    o.params.set("iso", hex(c.iso));
  } else {
    o.params.set("eps", hex(ov.eps >= 0 ? ov.eps : c.eps));
    if (ov.noskip) o.params.set("noskip", "1");
  }
  Input in = make_input<Volume>(c.volume, c.volume.source, 0, 0);
  return impl.run_as<Image>(in, o, nullptr);
}

std::string rgba(const float* p) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g, %.9g)", double(p[0]), double(p[1]), double(p[2]), double(p[3]));
  return buf;
}

std::string settings_line(const VrCase& c) {
  char buf[240];
  std::snprintf(buf, sizeof buf, "%dx%dx%d volume, %dx%d frame, view %.9g,%.9g,%.9g, step %.9g, eps %.9g, iso %.9g",
                c.volume.nx, c.volume.ny, c.volume.nz, c.width, c.height, c.az, c.el, c.roll, c.step, c.eps, c.iso);
  return buf;
}

// One outcome per pixel: the largest channel difference between a's pixel and
// b's pixel (b mirrored left-right when asked), ok within tol; explain(a, b, err)
// may classify a larger one.
Verdict compare(const Image& a, const Image& b, bool mirror, double tol, const std::string& what_a,
                const std::string& what_b, const VrCase& c,
                const std::function<std::string(const float*, const float*, double)>& explain = nullptr) {
  Verdict v;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const float* pa = a.pixel(x, y);
      const float* pb = b.pixel(mirror ? b.width - 1 - x : x, y);
      double err = 0;
      for (int ch = 0; ch < 4; ++ch) {
        const double d = std::abs(double(pa[ch]) - double(pb[ch]));
        err = std::isnan(d) ? kInfinity : std::max(err, d);
      }
      Outcome o;
      o.err = err;
      o.measured = true;
      if (err > tol) {
        const std::string label = explain ? explain(pa, pb, err) : "";
        o.kind = label.empty() ? Outcome::unexplained : Outcome::explained;
        o.label = label.empty() ? "differs" : label;
        std::ostringstream d;
        d << "pixel (" << x << ", " << y << "): " << what_a << " " << rgba(pa) << ", " << what_b << " " << rgba(pb)
          << "; error " << err << " > " << tol << "; " << settings_line(c);
        o.detail = d.str();
      }
      v.rays.push_back(o);
    }
  return v;
}

// ---------------------------------------------------------------- generators

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

// empty: smooth fields (blobs) and a transfer function clear at low values,
// so that much of the volume is empty space to skip.
rc::Gen<VrCase> gen_case(bool transparent, bool empty = false) {
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

// ---------------------------------------------------------------- checks

// Rays that stop at the 1 - eps threshold one sample apart (float and double,
// or two float rays, cross it differently): both alphas at the threshold, the
// difference at most eps (what one more sample can add under 1 - A <= eps).
// Splat too: a pixel stops taking footprints at 1 - eps, one splat apart.
std::function<std::string(const float*, const float*, double)> termination_flip(Mode mode, double eps, double tol) {
  return [tol, eps, mode](const float* pa, const float* pb, double err) -> std::string {
    const double floor_a = 1 - eps - 1e-5;
    if (mode != Mode::kIso && eps > 0 && err <= eps + tol && pa[3] >= floor_a && pb[3] >= floor_a)
      return "termination_flip";
    return "";
  };
}

Verdict agreement(const Family& family, const FamilyImpl& ref, const FamilyImpl& impl, const VrCase& c) {
  const Mode mode = mode_of(family);
  const Image a = render(ref, mode, c), b = render(impl, mode, c);
  const double tol = family.tol.abs;
  return compare(a, b, false, tol, std::string(ref.name), std::string(impl.name), c, termination_flip(mode, c.eps, tol));
}

Verdict skip_changes_nothing(const Family& family, const FamilyImpl& impl, const VrCase& c) {
  const Mode mode = mode_of(family);
  Verdict v = compare(render(impl, mode, c), render(impl, mode, c, {.noskip = true}), false, 1e-6, "skip", "noskip", c);
  if (c.eps > 0) {
    Verdict e = compare(render(impl, mode, c, {.noskip = true, .eps = 0}), render(impl, mode, c, {.noskip = true}), false,
                        c.eps + 1e-5, "eps 0", "eps " + hex(c.eps), c);
    for (Outcome& o : e.rays) {
      o.measured = false;  // the eps comparison's error is eps-sized by design
      v.rays.push_back(std::move(o));
    }
  }
  return v;
}

Verdict transparent(const Family& family, const FamilyImpl& impl, const VrCase& c) {
  const Image a = render(impl, mode_of(family), c);
  Image zero(c.width, c.height);
  return compare(a, zero, false, 0, std::string(impl.name), "background", c);
}

VrCase mirrored(const VrCase& c) {
  VrCase m = c;
  Volume& v = m.volume;
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i) v.at(i, j, k) = c.volume.at(v.nx - 1 - i, j, k);
  m.az = 180 - c.az;
  m.roll = -c.roll;
  return m;
}

Verdict mirror(const Family& family, const FamilyImpl& impl, const VrCase& c) {
  const Mode mode = mode_of(family);
  return compare(render(impl, mode, c), render(impl, mode, mirrored(c)), true, kMirrorTol, "image", "mirrored", c,
                 termination_flip(mode, c.eps, kMirrorTol));
}

Property property(const Family& family, const FamilyImpl& impl, std::string suite, std::string check,
                  std::string generator, rc::Gen<VrCase> gen, double bound,
                  std::function<Verdict(const VrCase&)> judge) {
  Property p;
  p.family = std::string(family.name);
  p.check = std::move(check);
  p.suite = std::move(suite);
  p.name = std::string(family.name) + "__" + std::string(impl.name);
  p.generator = std::move(generator);
  p.pair = std::string(family.name);
  p.impl = std::string(impl.name);
  p.bound = bound;
  p.unit = "largest channel difference";
  p.units = "pixels";
  set_case_runner<VrCase>(p, std::move(gen), std::move(judge), write_case, read_case);
  return p;
}

}  // namespace

FamilyProperties properties(const Family& family, RunResources&) {
  FamilyProperties out;
  const FamilyImpl& ref = family.reference();
  const Family* fam = &family;
  for (const FamilyImpl& impl : family.impls) {
    const FamilyImpl* ip = &impl;
    // A peer of another resampling (volpack: shear-warp, 8 bits, classified
    // then interpolated) is held to its own measured agreement on chosen frames
    // (tests/volpack_test.cpp: within its bound, wrong views caught) and in the
    // corpus, not to these float-against-double bounds; on random volumes dense
    // at the box's faces its soft edge alone puts 9-42% of pixels over 32/255.
    // It still must give the background for a transparent transfer function.
    const bool own_method = !impl.agree;
    if (family.has_property("agreement") && &impl != &ref && own_method)
      out.properties.push_back(property(family, impl, "Agreement", "agreement", "volumes", gen_case(false),
                                        family.tol.abs, [fam, &ref, ip](const VrCase& c) {
                                          return agreement(*fam, ref, *ip, c);
                                        }));
    if (family.has_property("skip") && &impl != &ref && own_method)
      out.properties.push_back(property(family, impl, "SkipChangesNothing", "skip", "volumes_empty_space",
                                        gen_case(false, true), 1e-6,
                                        [fam, ip](const VrCase& c) { return skip_changes_nothing(*fam, *ip, c); }));
    if (family.has_property("transparent"))
      out.properties.push_back(property(family, impl, "TransparentGivesBackground", "transparent",
                                        "volumes_transparent_tf", gen_case(true), 0,
                                        [fam, ip](const VrCase& c) { return transparent(*fam, *ip, c); }));
    if (family.has_property("mirror") && own_method)
      out.properties.push_back(property(family, impl, "Mirror", "mirror", "volumes", gen_case(false), kMirrorTol,
                                        [fam, ip](const VrCase& c) { return mirror(*fam, *ip, c); }));
  }
  return out;
}

}  // namespace lockstep::props::volume
