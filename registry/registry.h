// lockstep registry: the registry of every algorithm family.
//
// props/, bench/, `lockstep verify` and the CLI iterate over this and nothing
// else: a family that is listed here is tested, benchmarked and verifiable; a
// row that is not reachable from here does not exist. Adding a family is its
// contract header, its reference and optimized files, its row file in registry/
// and one line in registry/registry.cpp.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/family.h"

namespace lockstep {

struct Alias {
  std::string_view old_name;  // "raytrace"
  std::string_view name;      // "ray_trace"
};

struct Registry {
  std::vector<Family> families;  // every family, whatever its output kind
  // Old spellings a family is still found by (find(), so manifests, `render
  // --algo`, `trace` and `verify --filter`); `lockstep families` lists none.
  std::vector<Alias> aliases;

  // name itself, or the family name an old spelling stands for.
  std::string_view canonical(std::string_view name) const {
    for (const Alias& a : aliases)
      if (a.old_name == name) return a.name;
    return name;
  }
  const Family* find(std::string_view name) const {
    name = canonical(name);
    for (const auto& f : families)
      if (f.name == name) return &f;
    return nullptr;
  }
  // "ray_cast, composite"
  std::string names(std::string_view sep = ", ") const {
    std::string s;
    for (const auto& f : families) {
      if (!s.empty()) s += sep;
      s += f.name;
    }
    return s;
  }
};

// Built once, on first use; immutable.
const Registry& registry();


}  // namespace lockstep
