// lockstep pairs: the registry's one list. One line per family.
#include "pairs/registry.h"

#include "pairs/composite.h"
#include "pairs/marching_cubes.h"
#include "pairs/ray_cast.h"
#include "pairs/ray_trace.h"
#include "pairs/raster.h"
#include "pairs/volume.h"

namespace lockstep {

const Registry& registry() {
  static const Registry r{{
      ray_cast_family(),
      composite_family(),
      zbuffer_family(),
      scanline_family(),
      painter_family(),
      marching_cubes_family(),
      volume_family(),
      splat_family(),
      volume_iso_family(),
      ray_trace_family(),
  }};
  return r;
}

}  // namespace lockstep
