// lockstep core: the NFF (Neutral File Format) reader.
//
// Format: ../shared/spd/README.md (Eric Haines' SPD). Entities v, b, l, f, s, p,
// pp are read; 'c' (cone/cylinder) is rejected as unsupported. Any error throws
// InputError naming the file and line: unknown entity, missing or non-numeric
// fields, NaN or Inf, bad resolution, a polygon with fewer than 3 vertices, a
// truncated file, a degenerate camera.
#pragma once

#include <string>
#include <string_view>

#include "core/scene.h"

namespace lockstep {

// Limits beyond which input is called absurd rather than big.
inline constexpr int kMaxResolution = 16384;
inline constexpr long kMaxPolygonVertices = 1 << 20;

Scene read_nff(const std::string& path);
// Parses text already in memory; name is used in messages.
Scene parse_nff(std::string_view text, const std::string& name);

// Validates a view (also used for --size overrides): throws InputError.
void validate_view(const View& v, const std::string& file, int line);

}  // namespace lockstep
