// lockstep reference: the textbook z-buffer (namespace ref; reference/zbuffer.cpp).
// The contract every raster implementation shares -- settings, the viewing
// pipeline, the screen mesh, samples and depth, shade_fragment, Visibility --
// is core/raster.h; the other textbook raster families are
// reference/scanline.h and reference/painter.h.
#pragma once

#include "core/family.h"
#include "core/image.h"
#include "core/raster.h"
#include "core/scene.h"

namespace lockstep {

namespace ref {
// Textbook z-buffer over a prepared mesh (Catmull 1974): per triangle, per
// covered sample, depth from the plane equation, compare, keep the nearer.
void zbuffer_visibility(const ScreenMesh& mesh, const RasterSettings& s, Visibility& vis);

// The raster families' reference frames (single-threaded). opts.params holds
// the RasterSettings; the image carries a depth plane (eye z; +inf where empty).
Image zbuffer(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
}  // namespace ref

}  // namespace lockstep
