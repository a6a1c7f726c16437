// lockstep props/volume: the checks (see checks.h).
#include "props/volume/checks.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include "core/image.h"
#include "props/gen/case_text.h"

namespace lockstep::props::volume {

namespace {

using gen::hex;

enum class Mode { kRaycast, kIso, kSplat };

Mode mode_of(const Family& f) {
  return f.name == "volume_iso" ? Mode::kIso : f.name == "splat" ? Mode::kSplat : Mode::kRaycast;
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

}  // namespace

// ---------------------------------------------------------------- checks

namespace {

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

}  // namespace

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

namespace {

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

}  // namespace

Verdict mirror(const Family& family, const FamilyImpl& impl, const VrCase& c) {
  const Mode mode = mode_of(family);
  return compare(render(impl, mode, c), render(impl, mode, mirrored(c)), true, kMirrorTol, "image", "mirrored", c,
                 termination_flip(mode, c.eps, kMirrorTol));
}

}  // namespace lockstep::props::volume
