// Ray-polygon intersection, the textbook way.
//
// Source: Haines, "Essential Ray Tracing Algorithms" (Glassner, An Introduction
// to Ray Tracing, ch. 2.4) and Haines, "Point in Polygon Strategies" (Graphics
// Gems IV): intersect the polygon's plane, then decide whether the hit point is
// inside by projecting polygon and point onto the coordinate plane that drops
// the axis of the normal's largest component (the projection with the largest
// area, so no polygon collapses) and running the 2D crossings (Jordan curve)
// test, which is right for concave polygons too.
#pragma once

#include <span>

#include "core/math.h"
#include "core/scene.h"

namespace lockstep::ref {

// 2D crossings test: does a ray from (px, py) towards +x cross the polygon's
// edges an odd number of times? Vertices are (vertex[k][ax], vertex[k][ay]).
bool inside_polygon_2d(std::span<const Vec3> vertex, int ax, int ay, double px, double py);

// t of the ray's hit on polygon poly of scene, or +inf; no culling.
double ray_polygon_t(const Ray& ray, const Scene& scene, uint32_t poly);

}  // namespace lockstep::ref
