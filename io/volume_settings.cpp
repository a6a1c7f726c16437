// lockstep io: reading the volume families' settings (see io/volume_settings.h).
#include "io/volume_settings.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "core/error.h"
#include "io/transfer_function_io.h"

namespace lockstep::vr {

namespace {

double number(const std::string& name, const std::string& v, const std::string& source) {
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(v.c_str(), &end);
  if (v.empty() || end != v.c_str() + v.size() || errno == ERANGE || !std::isfinite(x))
    throw InputError(source, 0, name + " must be a finite number, got '" + v + "'");
  return x;
}

}  // namespace

Settings settings(const Params& p, const std::string& source, Mode mode) {
  Settings s;
  const auto specs = params(mode);
  for (const auto& [name, value] : p.items) {
    const bool known = std::any_of(specs.begin(), specs.end(), [&](const ParamSpec& q) { return q.name == name; });
    if (!known) {
      std::string names;
      for (const ParamSpec& q : specs) names += (names.empty() ? "" : ", ") + std::string(q.name);
      throw InputError(source, 0, "volume rendering has no setting '" + name + "' (it takes " + names + ")");
    }
  }
  if (const std::string tf = p.get("tf"); !tf.empty()) {
    s.tf = read_transfer_function(tf);
    s.has_tf = true;
  } else if (mode != Mode::kIso) {
    throw InputError(source, 0, std::string("volume rendering needs tf=PRESET|FILE.tf (presets: ") +
                                    transfer_presets() + ")");
  }
  if (mode == Mode::kIso) {
    const std::string iso = p.get("iso");
    if (iso.empty()) throw InputError(source, 0, "the isosurface needs iso=VALUE (the iso value)");
    s.iso = number("iso", iso, source);
  }
  if (const std::string v = p.get("step"); !v.empty()) {
    s.step = number("step", v, source);
    if (!(s.step > 0 && s.step <= 16)) throw InputError(source, 0, "step must lie in (0, 16] voxels, got " + v);
    // Below this a 512^2 frame of a 256^3 volume would take 10^11 samples.
    if (s.step < 1.0 / 64) throw InputError(source, 0, "step " + v + " is absurdly small (at least 1/64 of a voxel)");
  }
  if (const std::string v = p.get("view"); !v.empty()) {
    const size_t c1 = v.find(','), c2 = c1 == std::string::npos ? c1 : v.find(',', c1 + 1);
    if (c1 == std::string::npos) throw InputError(source, 0, "view is AZ,EL[,ROLL] in degrees, got '" + v + "'");
    s.azimuth = number("view's azimuth", v.substr(0, c1), source);
    s.elevation = number("view's elevation", v.substr(c1 + 1, c2 == std::string::npos ? c2 : c2 - c1 - 1), source);
    if (c2 != std::string::npos) s.roll = number("view's roll", v.substr(c2 + 1), source);
    if (std::abs(s.azimuth) > 3600 || std::abs(s.elevation) > 90 || std::abs(s.roll) > 3600)
      throw InputError(source, 0,
                       "view: the azimuth and roll lie in [-3600, 3600], the elevation in [-90, 90], got '" + v + "'");
  }
  if (const std::string v = p.get("eps"); !v.empty()) {
    s.eps = number("eps", v, source);
    if (!(s.eps >= 0 && s.eps <= 0.5)) throw InputError(source, 0, "eps must lie in [0, 0.5], got " + v);
  }
  if (const std::string v = p.get("error"); !v.empty()) {
    s.error = number("error", v, source);
    if (!(s.error > 0 && s.error <= 1)) throw InputError(source, 0, "error must lie in (0, 1], got " + v);
    if (!p.get("step").empty()) throw InputError(source, 0, "give step or error, not both");
    if (!p.get("eps").empty())
      throw InputError(source, 0, "give eps or error, not both (error chooses the step and eps)");
  }
  s.skip = p.get("noskip").empty() || p.get("noskip") == "0";
  return s;
}

}  // namespace lockstep::vr
