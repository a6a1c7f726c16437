// lockstep registry: the registry's one list. One line per family.
#include "registry/registry.h"

#include "registry/composite_row.h"
#include "registry/marching_cubes_row.h"
#include "registry/radiosity_row.h"
#include "registry/ray_cast_row.h"
#include "registry/ray_trace_row.h"
#include "registry/raster_rows.h"
#include "registry/texture_row.h"
#include "registry/volume_rows.h"

namespace lockstep {

const Registry& registry() {
  static const Registry r{
      .families =
          {
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
              texture_family(),
              radiosity_family(),
          },
      // Old spellings still accepted (issue 31: one spelling per family).
      .aliases = {{"raytrace", "ray_trace"}},
  };
  return r;
}

}  // namespace lockstep
