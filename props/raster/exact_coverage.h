// lockstep props/raster: the exact box-filtered image of flat-coloured,
// non-intersecting triangles -- the oracle that supersampling converges to.
//
// For every pixel square and every triangle, the area of the part of the
// triangle inside the square that no nearer triangle covers, computed exactly:
// triangle and square are convex, so their intersections with any set of
// nearer triangles are convex polygons, clipped one from another by Sutherland
// and Hodgman in exact rational arithmetic (CGAL::Gmpq); the uncovered part is
// then by inclusion and exclusion
//     area(T_i n P - U_{j nearer} T_j) = sum over S of (-1)^|S| area(T_i n P n (n_{j in S} T_j)).
// The pixel's colour is sum_i area_i colour_i + (1 - sum_i area_i) background.
// Triangles are ordered by one depth each (the scenes that use this keep each
// triangle at one depth, parallel to the image plane), so visibility is exact
// too. Inputs are doubles taken as exact rationals; the result is rounded once.
#pragma once

#include <vector>

#include "core/image.h"
#include "core/math.h"

namespace lockstep::props::raster {

struct FlatTri {
  double x[3], y[3];  // screen position, pixels (x right, y down), unsnapped
  double depth;       // smaller is nearer; distinct per triangle
  Vec3 color;
};

// The exact box-filtered image (no depth plane). At most 12 triangles.
Image exact_box_filtered(const std::vector<FlatTri>& tris, int width, int height, const Vec3& background);

}  // namespace lockstep::props::raster
