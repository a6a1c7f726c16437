// lockstep props: which property provider tests which registry family.
//
// One row per family of registry/registry.cpp. The driver (driver/driver.cpp) registers
// every property a provider lists, and a failing Registry.<family>_has_properties
// test for a registered family that has no row here (and
// Registry.<family>_is_registered for a row whose family is not registered).
#include "props/property.h"

namespace lockstep::props {
namespace ray_cast {
FamilyProperties properties(const Family&, RunResources&);
}
namespace composite {
FamilyProperties properties(const Family&, RunResources&);
}
namespace raster {
FamilyProperties properties(const Family&, RunResources&);
}
namespace marching_cubes {
FamilyProperties properties(const Family&, RunResources&);
}
namespace volume {
FamilyProperties properties(const Family&, RunResources&);
}
namespace ray_trace {
FamilyProperties properties(const Family&, RunResources&);
}
namespace texture {
FamilyProperties properties(const Family&, RunResources&);
}
namespace radiosity {
FamilyProperties properties(const Family&, RunResources&);
}

const std::vector<ProviderRow>& property_providers() {
  static const std::vector<ProviderRow> rows = {
      {"ray_cast", ray_cast::properties},
      {"composite", composite::properties},
      {"zbuffer", raster::properties},
      {"scanline", raster::properties},
      {"painter", raster::properties},
      {"marching_cubes", marching_cubes::properties},
      {"volume", volume::properties},
      {"volume_iso", volume::properties},
      {"splat", volume::properties},
      {"ray_trace", ray_trace::properties},
      {"texture", texture::properties},
      {"radiosity", radiosity::properties},
  };
  return rows;
}

}  // namespace lockstep::props
