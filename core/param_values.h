// lockstep core: reading one setting's value (Params, core/family.h) with a
// message that names the setting, for every family's settings reader.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <string_view>

#include "core/error.h"

namespace lockstep {

// The index of value among the '|'-separated choices, or throws naming the setting.
inline int param_choice(const std::string& source, std::string_view name, const std::string& value,
                        std::string_view choices) {
  int index = 0;
  size_t start = 0;
  while (start <= choices.size()) {
    const size_t end = std::min(choices.find('|', start), choices.size());
    if (choices.substr(start, end - start) == value) return index;
    ++index;
    start = end + 1;
  }
  throw InputError(source, 0, std::string(name) + ": '" + value + "' is not one of " + std::string(choices));
}

// A finite number in [lo, hi], or throws naming the setting.
inline double param_number(const std::string& source, std::string_view name, const std::string& value, double lo,
                           double hi) {
  char* end = nullptr;
  const double x = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(x) || x < lo || x > hi)
    throw InputError(source, 0,
                     std::string(name) + ": '" + value + "' is not a number in [" + std::to_string(lo) + ", " +
                         std::to_string(hi) + "]");
  return x;
}

// A whole number in [lo, hi], or throws naming the setting.
inline int param_int(const std::string& source, std::string_view name, const std::string& value, int lo, int hi) {
  const double x = param_number(source, name, value, lo, hi);
  if (x != std::floor(x)) throw InputError(source, 0, std::string(name) + ": '" + value + "' is not a whole number");
  return int(x);
}

inline bool param_flag(const std::string& source, std::string_view name, const std::string& value) {
  return param_choice(source, name, value, "0|1") == 1;
}

}  // namespace lockstep
