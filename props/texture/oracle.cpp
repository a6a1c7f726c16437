// lockstep props/texture: the pixel's exact box filter (props/texture/oracle.h).
#include "props/texture/oracle.h"

#include <algorithm>
#include <cmath>

namespace lockstep::props::texture {

BoxValue pixel_box_filter(const TextureScene& scene, const TexelMap& map, int x, int y) {
  BoxValue out;
  // The footprint: the pixel's corners in texel coordinates, all on the quad.
  Polygon2 fp;
  const double cx[4] = {double(x), double(x + 1), double(x + 1), double(x)};
  const double cy[4] = {double(y), double(y), double(y + 1), double(y + 1)};
  double dmin = 1e300, dmax = 0;
  for (int k = 0; k < 4; ++k) {
    double a, b;
    if (!map.texel_at(cx[k], cy[k], a, b) || !map.on_quad(a, b)) return out;
    fp.push_back({a, b});
    const double depth = map.depth_row.x * a + map.depth_row.y * b + map.depth_row.z;
    dmin = std::min(dmin, depth);
    dmax = std::max(dmax, depth);
  }
  out.interior = true;
  out.depth_ratio = dmax / dmin;
  // Counter-clockwise in the (a, b) frame, so each edge's inside is on its left.
  if (polygon_area(fp) < 0) std::reverse(fp.begin(), fp.end());
  double lo_a = 1e300, hi_a = -1e300, lo_b = 1e300, hi_b = -1e300;
  for (const Point2& p : fp) {
    lo_a = std::min(lo_a, p.x);
    hi_a = std::max(hi_a, p.x);
    lo_b = std::min(lo_b, p.y);
    hi_b = std::max(hi_b, p.y);
  }
  out.lo = {1e300, 1e300, 1e300, 1e300};
  out.hi = {-1e300, -1e300, -1e300, -1e300};
  const Texture& t = scene.texture;
  for (int64_t j = int64_t(std::floor(lo_b)); double(j) < hi_b; ++j)
    for (int64_t i = int64_t(std::floor(lo_a)); double(i) < hi_a; ++i) {
      // The texel square cut to the footprint ...
      Polygon2 cell{{double(i), double(j)}, {double(i + 1), double(j)}, {double(i + 1), double(j + 1)},
                    {double(i), double(j + 1)}};
      for (size_t k = 0; k < fp.size() && cell.size() >= 3; ++k) {
        const Point2& p = fp[k];
        const Point2& q = fp[(k + 1) % fp.size()];
        const double ex = q.x - p.x, ey = q.y - p.y;
        cell = clip_half_plane(cell, -ey, ex, ey * p.x - ex * p.y);
      }
      if (cell.size() < 3) continue;
      // ... mapped to pixel space, where its area is its share of the pixel.
      Polygon2 img;
      for (const Point2& p : cell) {
        const Vec3 h = map.to_pixel.apply(p.x, p.y);
        img.push_back({h.x / h.z, h.y / h.z});
      }
      const double w = std::abs(polygon_area(img));
      if (w == 0) continue;
      const float* v = t.wrapped(i, j);
      for (int c = 0; c < 4; ++c) {
        out.rgba[size_t(c)] += w * v[c];
        out.lo[size_t(c)] = std::min(out.lo[size_t(c)], double(v[c]));
        out.hi[size_t(c)] = std::max(out.hi[size_t(c)], double(v[c]));
      }
      out.weight_sum += w;
      ++out.texels;
    }
  return out;
}

}  // namespace lockstep::props::texture
