// lockstep io: the NFF (Neutral File Format) reader.
//
// Format: ../shared/spd/README.md (Eric Haines' SPD). Entities v, b, l, f, s, p,
// pp are read; 'c' (open cone/cylinder, both layouts: io/nff.cpp read_cone) too. Any error throws
// InputError naming the file and line: unknown entity, missing or non-numeric
// fields, NaN or Inf, bad resolution, a polygon with fewer than 3 vertices, a
// truncated file, a degenerate camera.
//
// lockstep's extension: light attenuation and spotlights. A line whose first
// word is exactly "#lockstep" modifies the light ('l' line) immediately before
// it (blank lines and ordinary comments may come between; at most one line of
// each kind per light). Other NFF readers skip these lines as comments.
//
//   #lockstep atten c1 c2 c3
//       distance attenuation f_att = min(1, 1 / (c1 + c2 d + c3 d^2)), d the
//       distance from the lit point to the light (Foley et al., Computer
//       Graphics 2nd ed., 16.1.4); c1, c2, c3 >= 0, not all 0. Default 1 0 0.
//   #lockstep spot dx dy dz cutoff_degrees exponent
//       a Warn spotlight (Warn 1983; Foley et al. 16.1.6): the light shines
//       along D = (dx, dy, dz) (any non-zero length); a point whose direction
//       to the light is L (unit) receives the factor max(0, -L.D)^exponent when
//       the angle between -L and D is at most cutoff_degrees, else 0.
//       0 < cutoff_degrees <= 90, exponent >= 0.
//
// And per material, after an 'f' line (radiosity's emitters, issue #33):
//   #lockstep emit r g b
//       the radiosity the surfaces of that material emit, per channel, >= 0
//       (Material::emission); the material's colour times Kd is their
//       reflectance. Ray casting, the z-buffer and the others ignore it.
//
// Both light factors multiply the light's intensity (core/shading.h, light_at). Any
// other keyword, a missing or extra field, a non-number, NaN or Inf, a negative
// or all-zero attenuation, a zero direction, a cutoff outside (0, 90], a
// negative exponent or emission, a second line of the same kind, or a #lockstep
// line that does not follow a light (emit: a material) is an InputError naming
// the line. Only a first word
// of exactly "#lockstep" is special: "# lockstep ..." and "#lockstepx" are
// ordinary comments, and so is any '#' after the line's first word.
//
// Example: a spot at (0, 4, 0) pointing straight down, 30 degree cone, falloff
// cos^8, at full intensity up to d = 2.9 (where the denominator reaches 1),
// half at d = 6:
//   l 0 4 0
//   #lockstep spot 0 -1 0 30 8
//   #lockstep atten 0.5 0.1 0.025
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
