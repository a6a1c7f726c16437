// lockstep props/volume: the case generator.
#pragma once

#include <rapidcheck.h>

#include "props/volume/case.h"

namespace lockstep::props::volume {

// A volume (smooth blobs, analytic or rough), a transfer function (transparent:
// every alpha 0), a view, step, eps, iso and frame. empty: smooth fields (blobs)
// and a transfer function clear at low values, so that much of the volume is
// empty space to skip.
rc::Gen<VrCase> gen_case(bool transparent, bool empty = false);

}  // namespace lockstep::props::volume
