// lockstep props/ray_cast: the named case generators of the ray-casting family.
//
// Every number comes from props/gen/numbers.h (integers that shrink
// meaningfully); closed meshes from meshes.h. Case generators are registered by
// name; the typed rows (registry/ray_cast_row.cpp) name the well-conditioned one of each
// row, and the stability generators are listed here with the subjects they
// exercise.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include <rapidcheck.h>

#include "core/math.h"
#include "props/ray_cast/case.h"

namespace lockstep::props::ray_cast {

// ---------------------------------------------------------------- named case generators
enum Kinds : unsigned {
  kSphereKernel = 1u << 0,
  kPlaneKernel = 1u << 1,
  kPolygonKernel = 1u << 2,
  kTrace = 1u << 3,
  kRender = 1u << 4,
  kWatertight = 1u << 5,
  kDegenerate = 1u << 6,
  kConeKernel = 1u << 7,
};

struct Named {
  std::string_view name;
  unsigned kinds;      // which checks the cases support
  bool stability;      // a stability generator (ill-conditioned on purpose)
  std::string_view what;
  rc::Gen<Case> gen;
};

const std::vector<Named>& generators();
const Named* find_generator(std::string_view name);

}  // namespace lockstep::props::ray_cast
