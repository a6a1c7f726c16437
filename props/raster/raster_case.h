// lockstep props/raster: one generated case of the raster families -- an NFF
// scene (as text, so that a counterexample file is a scene anyone can render),
// a frame size and the family's settings.
//
// Text form (a counterexample file's body):
//   raster_case WIDTH HEIGHT [name=value ...]
//   <the NFF scene>
#pragma once

#include <rapidcheck.h>

#include <memory>
#include <string>

#include "core/family.h"
#include "core/scene.h"

namespace lockstep::props::raster {

struct RasterCase {
  std::string nff;
  int width = 32, height = 32;
  Params params;
  std::shared_ptr<const Scene> scene() const;  // parsed (throws InputError on a bad text)
  FrameOptions options() const;               // width, height, params, one thread
};

// A double as scene text that reads back to the same bits (%.17g).
std::string num(double x);

std::string write_case(const RasterCase& c);
RasterCase read_case(const std::string& text, const std::string& file);

// Random scenes. Every vertex is in front of the camera (depth 2..12) and most
// of each triangle is in view; coordinates are arbitrary doubles, so vertices
// land anywhere between sample positions.
//   triangle_soup: 1..6 triangles in random orientations, some two-sided
//   (transmissive), crossing each other at random; 1..2 lights; phong, cull=world.
rc::Gen<RasterCase> triangle_soup();
//   edge_on_soup: as triangle_soup, but each triangle's plane passes within a
//   random distance (1e-9 .. 1e-1 relative, either side) of the eye: faces seen
//   edge-on or nearly, where world-space and projection-space culling may part.
//   Half of the triangles are slivers drawn on screen instead: two vertices
//   within half a snapping step of two pixel centres of one row (or column),
//   the third on their exact line extended, off it by a hair (1e-7..1e-3
//   step) to either side, so that it snaps a step off the row whatever the
//   hair's side: the snapped triangle owns or leaves a run of samples, and
//   half the time its world-space facing and snapped area disagree.
rc::Gen<RasterCase> edge_on_soup();

//   shaded_soup: what the soups above never meet: 1..5 objects, each a flat
//   `p` triangle, a `pp` triangle or a planar `pp` quad (a patch) with curved
//   vertex normals (the face normal tilted up to about 50 degrees per vertex),
//   at depths 2..12 (so that perspective-correct and affine interpolation
//   differ), a third of them with vertices on pixel centres and an edge along
//   a row or column of samples (the fill rule); 1..3 lights, each a point light, an attenuated one or a spot
//   (`#lockstep spot`, cut-off 5..80 degrees, aimed near the objects so that
//   cone edges cross the frame); shading flat, gouraud, phong or blinn; some
//   two-sided materials; cull=world or projection; one sample per pixel.
rc::Gen<RasterCase> shaded_soup();

}  // namespace lockstep::props::raster
