// lockstep reference: the scanline z-buffer, and the interpolation lessons it
// is built from (the contract is core/raster.h).
//
// The scanline z-buffer draws the same ScreenMesh as ref::zbuffer, with the
// same samples, the same fill rule and the same tie rule (the first of equal
// depths stays), so its coverage equals ref::zbuffer_visibility's sample for
// sample; its depth and its attributes are interpolated incrementally, so they
// drift from direct evaluation by a few units in the last place along long
// spans (props/raster/interpolation.cpp measures and bounds the drift).
#pragma once

#include <array>
#include <functional>
#include <span>

#include "core/raster.h"

namespace lockstep {

namespace ref {

// Scanline z-buffer visibility (Foley et al. 15.4, Watkins 1970): an edge table,
// an active edge list, spans per sample row. Same contract as
// zbuffer_visibility.
void scanline_visibility(const ScreenMesh& mesh, const RasterSettings& s, Visibility& vis);

// Every covered sample, before the depth test, with the fragment the scan
// interpolated for it incrementally (b: perspective-correct or affine per
// s.perspective; z: from the incremental 1/z). Sample index as in Visibility.
// For the properties: the drift of the incremental values against direct
// evaluation.
void scanline_fragments(const ScreenMesh& mesh, const RasterSettings& s,
                        const std::function<void(size_t sample, const Fragment& f)>& on_sample);

// The reference frame (single-threaded): opts.params holds the RasterSettings;
// the image carries a depth plane (eye z of the nearest sample; +inf where empty).
Image scanline(const Scene& scene, const FrameOptions& opts, FrameStats* stats);

// ---------------------------------------------------------------- the interpolation lessons

// A screen point with one attribute value.
struct ScreenValue {
  double x = 0, y = 0, value = 0;
};

// Barycentric coordinates of p in triangle (a, b, c) as ratios of areas:
// b0 = area(p, b, c) / area(a, b, c), ... They sum to 1 and reproduce the
// vertices' values; they do not change when the triangle and p are rotated
// together on screen.
std::array<double, 3> barycentric(const ScreenValue& a, const ScreenValue& b, const ScreenValue& c,
                                  double px, double py);

// Bilinear (scanline, Gouraud 1971) interpolation over a convex polygon: the
// value down the left and the right edge crossing the row y = py, linear in y
// along each edge, then linear in x across the span between them. On a
// triangle this equals barycentric interpolation; on a quadrilateral it
// depends on the polygon's orientation on screen. p must be inside.
double bilinear_polygon(std::span<const ScreenValue> polygon, double px, double py);

}  // namespace ref

}  // namespace lockstep
