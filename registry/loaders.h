// lockstep registry: inputs shared by families -- loaded once here, named by
// every row that reads them (ray_cast and the raster families read NFF
// scenes; the SPD scenes they benchmark live beside the repository).
#pragma once

#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

#include "core/family.h"

namespace lockstep {

// An NFF scene (io/nff.h) as a family's Input: its own resolution and
// background. Throws InputError naming file and line.
Input load_nff(const std::string& path);

// Cones ('c'): every row of ray_cast, ray_trace, zbuffer, scanline and painter
// draws them (none calls this any more); kept for a family whose rows cannot
// yet. Wraps every implementation of f except those named in `draws_cones` so
// that a scene with cones is refused (InputError naming the file, the count and
// the row; exit 2) instead of drawn without them.
void refuse_cones(Family& f, std::initializer_list<std::string_view> draws_cones);

// Where Eric Haines' SPD scenes are: $LOCKSTEP_SPD_DIR, else ../shared/spd
// beside the source tree (as configured at build time).
std::string spd_dir();

// Where the corpus is (its inputs, for benchmarks that draw a corpus scene):
// $LOCKSTEP_CORPUS_DIR, else corpus/ in the source tree.
std::string corpus_dir();
// Where the real CT/MRI volumes are: $LOCKSTEP_VOLUMES_DIR, else
// ../shared/volumes beside the source tree.
std::string volumes_dir();

// A volume (io/volume_io.h: NRRD through Teem, or a .field) as a family's
// Input, with the frame size a sized family draws it at by default (0: unsized).
// Throws InputError naming file and line.
Input load_volume(const std::string& path, int width = 0, int height = 0);

// The SPD scene `name` (e.g. "balls-3", "tree-2-tess"): spd_dir()/name.nff
// when that file exists, else generated in memory by spd/ (the same text the
// SPD programs write: tests/spd checks it against ../shared/spd), so a clone
// without ../shared runs every benchmark. Nothing when the name is neither a
// file there nor a scene spd/ can make.
std::optional<Input> load_spd(std::string_view name);

// Whether the real CT and MRI volumes (cthead.nhdr, ch2.nhdr) are in
// volumes_dir(). They cannot be generated: benchmarks and tests that need
// them skip them when this is false (the analytic fields still run).
bool have_real_volumes();

}  // namespace lockstep
