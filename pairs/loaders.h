// lockstep pairs: inputs shared by families -- loaded once here, named by
// every row that reads them (ray_cast and the raster families read NFF
// scenes; the SPD scenes they benchmark live beside the repository).
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "core/family.h"

namespace lockstep {

// An NFF scene (core/nff.h) as a family's Input: its own resolution and
// background. Throws InputError naming file and line.
Input load_nff(const std::string& path);

// Where Eric Haines' SPD scenes are: $LOCKSTEP_SPD_DIR, else ../shared/spd
// beside the source tree (as configured at build time).
std::string spd_dir();

// Where the real CT/MRI volumes are: $LOCKSTEP_VOLUMES_DIR, else
// ../shared/volumes beside the source tree.
std::string volumes_dir();

// A volume (core/volume_io.h: NRRD through Teem, or a .field) as a family's
// Input, with the frame size a sized family draws it at by default (0: unsized).
// Throws InputError naming file and line.
Input load_volume(const std::string& path, int width = 0, int height = 0);

// The SPD scene `name` (e.g. "balls-3"), loaded, or nothing when it is not
// there (benchmarks time the scenes that are present).
std::optional<Input> load_spd(std::string_view name);

}  // namespace lockstep
