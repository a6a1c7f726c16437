// lockstep props/volume: the case's text form (see case.h).
#include "props/volume/case.h"

#include <cstdlib>
#include <sstream>

#include "core/error.h"
#include "props/gen/case_text.h"
#include "props/gen/numbers.h"

namespace lockstep::props::volume {

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

}  // namespace lockstep::props::volume
