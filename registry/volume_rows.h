// lockstep registry: the volume-rendering families' rows (a volume -> an image).
//
//   volume      V-buffer ray casting: reference/volume_raycast.cpp
//   splat       splatting: reference/volume_splat.cpp
//   volume_iso  the interpolant's isosurface, ray cast: reference/volume_iso.cpp
//
// They read the volumes of io/volume_io.h (NRRD through Teem, analytic .field
// files), share the contract of core/volume_render.h (settings tf=, step=,
// view=, eps=, iso=) and draw premultiplied RGBA on a transparent background.
// `lockstep volume --algo raycast|splat|iso` picks one (their algo names).
#pragma once

#include "core/family.h"

namespace lockstep {

Family volume_family();
Family splat_family();
Family volume_iso_family();

}  // namespace lockstep
