// lockstep props/marching_cubes: the family's case (a volume and an iso
// value) and its text form, every sample a hexfloat.
#pragma once

#include <string>

#include "core/volume.h"

namespace lockstep::props::marching_cubes {

struct McCase {
  Volume volume;
  double iso = 0.5;
};

std::string write_case(const McCase& c);
McCase read_case(const std::string& text, const std::string& file);

}  // namespace lockstep::props::marching_cubes
