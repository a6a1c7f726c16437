// lockstep reference: texture filtering (issue #32), the textbook way.
//
// Contract (core/texture.h states the texel, pixel and mipmap conventions):
// texture_filter(scene, opts, stats) draws the scene's textured quad at
// opts.width x opts.height with the filter opts.params["filter"] (default
// trilinear): every pixel whose centre sees the quad gets one filtered RGBA
// value, the others the background (alpha 1). stats->items counts the
// filtered pixels (lookups).
//
// The single lookups are exported for the properties (props/texture/).
#pragma once

#include <array>
#include <vector>

#include "core/family.h"
#include "core/image.h"
#include "core/texture.h"

namespace lockstep::ref {

using Rgba = std::array<double, 4>;

// The mipmap pyramid by core/texture.h's rule; levels[0] is a copy of the texture.
std::vector<Texture> build_pyramid(const Texture& t);

// Lookups at texel point (a, b) of level 0's texel coordinates (core/texture.h).
Rgba lookup_point(const Texture& t, double a, double b);
// Bilinear in `level` (its own texel coordinates are (a, b) scaled by its size over level 0's).
Rgba lookup_bilinear(const std::vector<Texture>& pyramid, int level, double a, double b);
// Level of detail of a footprint with derivatives (dadx, dbdx), (dady, dbdy), in level-0 texels.
double level_of_detail(double dadx, double dbdx, double dady, double dbdy);
Rgba lookup_trilinear(const std::vector<Texture>& pyramid, double lod, double a, double b);
Rgba lookup_aniso(const std::vector<Texture>& pyramid, int max_probes, double a, double b, double dadx, double dbdx,
                  double dady, double dbdy);
Rgba lookup_ewa(const std::vector<Texture>& pyramid, double max_eccentricity, double a, double b, double dadx,
                double dbdx, double dady, double dbdy);
// The average of the texel-constant texture over a convex polygon in texel
// coordinates (area sampling); empty polygon: {0, 0, 0, 0}.
Rgba average_over(const Texture& t, const Polygon2& footprint);

// Pixel (x, y) filtered by f: false (c = background) when its centre misses
// the quad. pyramid: build_pyramid(tex) for the filters that use one, else
// at least level 0.
bool filter_pixel(const Texture& tex, const std::vector<Texture>& pyramid, const TexelMap& map,
                  const TextureFilterSettings& f, int x, int y, const Rgba& background, Rgba& c);

// The frame; params' filter_tiles (core/texture.h), when set, a filter per
// tile. stats: lookups (items) and the pyramid's build (or level 0's copy)
// as build_seconds, a one-shot cost.
Image texture_filter(const TextureScene& scene, const FrameOptions& opts, FrameStats* stats);

}  // namespace lockstep::ref
