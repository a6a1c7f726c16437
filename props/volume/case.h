// lockstep props/volume: the volume families' case (volume, transfer
// function, view, step, eps, iso, frame size) and its text form, every number
// a hexfloat (properties.cpp's header describes what the generators draw).
#pragma once

#include <string>
#include <vector>

#include "core/transfer_function.h"
#include "core/volume.h"

namespace lockstep::props::volume {

struct VrCase {
  Volume volume;
  std::vector<ControlPoint> tf;
  int width = 16, height = 16;
  double az = 30, el = 20, roll = 0, step = 0.5, eps = 1.0 / 256, iso = 0.5;
};

// The transfer function's points, one "value r g b a" line each (hexfloats).
std::string tf_text(const std::vector<ControlPoint>& tf);
std::string write_case(const VrCase& c);
VrCase read_case(const std::string& text, const std::string& file);

}  // namespace lockstep::props::volume
