// lockstep props/raster: the parts of the raster families' properties.
//
// Each part adds what it tests of the family it is given (it looks at
// family.name: zbuffer, scanline, painter) to out; properties.cpp lists them.
// A new part: its file in props/raster/, its declaration here, its line in
// kParts (properties.cpp), its file in props/CMakeLists.txt.
#pragma once

#include "props/property.h"

namespace lockstep::props::raster {

// z-buffer frames against ray casting (properties.cpp).
void cross_check_part(const ImageFamily& family, FamilyProperties& out);
// The painter against the z-buffer, its reports, --split, its exact predicates (painter.cpp).
void painter_part(const ImageFamily& family, FamilyProperties& out);

}  // namespace lockstep::props::raster
