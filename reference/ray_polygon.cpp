#include "reference/ray_polygon.h"

#include <cmath>

#include "reference/ray_cast.h"

namespace lockstep::ref {

bool inside_polygon_2d(std::span<const Vec3> vertex, int ax, int ay, double px, double py) {
  bool inside = false;
  const size_t n = vertex.size();
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const double xi = vertex[i][ax], yi = vertex[i][ay];
    const double xj = vertex[j][ax], yj = vertex[j][ay];
    // Does edge (j, i) straddle the horizontal line y = py? The half-open rule
    // (one end strictly above, the other not) counts a vertex on the line once.
    if ((yi > py) != (yj > py)) {
      // x where the edge crosses that line; a crossing to the right of p toggles.
      const double x_cross = xj + (py - yj) * (xi - xj) / (yi - yj);
      if (px < x_cross) inside = !inside;
    }
  }
  return inside;
}

double ray_polygon_t(const Ray& ray, const Scene& scene, uint32_t poly) {
  const Plane& plane = scene.poly_plane[poly];
  // Step 1: the plane. N.d = 0: parallel, no hit (also for degenerate polygons, N = 0).
  const double denominator = dot(plane.n, ray.d);
  if (denominator == 0) return kInfinity;
  const double t = -(dot(plane.n, ray.o) + plane.d) / denominator;
  if (!(t > ray.tmin && t < ray.tmax)) return kInfinity;
  // Step 2: the hit point, projected by dropping the dominant axis of N.
  const Vec3 p = ray.o + t * ray.d;
  const int drop = dominant_axis(plane.n);
  const int ax = (drop + 1) % 3, ay = (drop + 2) % 3;
  // Step 3: inside the polygon?
  if (!inside_polygon_2d(scene.polygon_vertices(poly), ax, ay, p[ax], p[ay])) return kInfinity;
  return t;
}

void ray_polygon(std::span<const Ray> rays, const Scene& scene, uint32_t poly, std::span<double> t) {
  for (size_t i = 0; i < rays.size(); ++i) t[i] = ray_polygon_t(rays[i], scene, poly);
}

}  // namespace lockstep::ref
