// lockstep registry: the ray-casting family's analytic judges, for corpus cases
// where the reference itself is expected to be wrong (or where "right" has a
// closed form worth checking).
//
// A judge says, for every pixel-centre ray, whether it must hit the scene or
// must see the background, computed in double straight from the geometry, and
// never through any ray-casting implementation. A pixel whose answer changes
// when its ray is moved by kJudgeMargin of a pixel in any of the four image
// directions is on the boundary and is skipped: there the answer depends on
// rounding, not on the method.
//
//   disk    the scene is one sphere (either sign of radius) seen from outside:
//           a ray hits iff its angle to the direction of the centre is below the
//           sphere's angular radius asin(|r| / distance).
//   convex  the scene is a closed convex polyhedron made of polygons facing out:
//           a ray hits iff it enters the intersection of the faces' half-spaces
//           beyond hither (slab clipping, Kay & Kajiya 1986 with planes).
//
// verify counts an image pixel as "hit" when its colour differs from the
// background colour: with NFF's ambient term (core/shading.h) a hit is never
// exactly the background as long as the material has kd > 0 and a non-black
// colour, which the judged scenes in the corpus have.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/error.h"
#include "core/family.h"
#include "kinds/image_kind.h"
#include "core/scene.h"

namespace lockstep::ray_cast_judges {

// Boundary margin in pixels (1/1000 of the pixel pitch). An absolute angle such
// as 1e-6 rad would be meaningless here: the far-sphere case's whole disk
// subtends 1e-8 rad.
inline constexpr double kJudgeMargin = 1e-3;

enum class JudgeKind { kReference, kDisk, kConvex };

// Throws InputError (naming the scene) when the scene is not what the judge needs.
inline void check_judgeable(const Scene& s, JudgeKind kind) {
  if (kind == JudgeKind::kDisk) {
    if (s.sphere_count() != 1 || s.polygon_count() != 0)
      throw InputError(s.source, 0, "judge 'disk' needs a scene of exactly one sphere and nothing else");
    const double dist = length(s.sphere_center[0] - s.view.from);
    if (!(dist > std::abs(s.sphere_radius[0])))
      throw InputError(s.source, 0, "judge 'disk' needs the camera outside the sphere");
  } else if (kind == JudgeKind::kConvex) {
    if (s.sphere_count() != 0 || s.polygon_count() < 4)
      throw InputError(s.source, 0, "judge 'convex' needs a scene of polygons only (at least 4)");
    double scale = 0;
    for (const Vec3& v : s.vertex) scale = std::max(scale, max_abs_component(v));
    for (uint32_t p = 0; p < s.polygon_count(); ++p) {
      const Plane& pl = s.poly_plane[p];
      if (length(pl.n) == 0) throw InputError(s.source, 0, "judge 'convex': degenerate polygon " + std::to_string(p));
      for (const Vec3& v : s.vertex)
        if (dot(pl.n, v) + pl.d > 1e-9 * scale)
          throw InputError(s.source, 0,
                           "judge 'convex': polygon " + std::to_string(p) +
                               " does not face out of a convex solid (a vertex lies in front of it)");
    }
    // The eye must be outside, or every ray would "enter" at hither.
    bool outside = false;
    for (uint32_t p = 0; p < s.polygon_count(); ++p)
      outside = outside || dot(s.poly_plane[p].n, s.view.from) + s.poly_plane[p].d > 0;
    if (!outside) throw InputError(s.source, 0, "judge 'convex' needs the camera outside the solid");
  }
}

namespace judge_detail {

// Does the ray o + t d (t > tmin) hit the scene, by the judge's closed form?
inline bool disk_hit(const Scene& s, const Vec3& o, const Vec3& d) {
  const Vec3 u = s.sphere_center[0] - o;
  const double dist = length(u);
  const double alpha = std::asin(std::abs(s.sphere_radius[0]) / dist);
  const double theta = std::atan2(length(cross(d, u)), dot(d, u));  // accurate at tiny angles
  return theta < alpha;
}

inline bool convex_hit(const Scene& s, const Vec3& o, const Vec3& d, double tmin) {
  double t0 = tmin, t1 = kInfinity;
  for (uint32_t p = 0; p < s.polygon_count(); ++p) {
    const Plane& pl = s.poly_plane[p];
    const double dn = dot(d, pl.n);
    const double dist = dot(o, pl.n) + pl.d;  // > 0: o is outside this face
    if (dn == 0) {
      if (dist > 0) return false;
      continue;
    }
    const double t = -dist / dn;
    if (dn < 0) t0 = std::max(t0, t);  // entering
    else t1 = std::min(t1, t);         // leaving
  }
  return t0 < t1;
}

}  // namespace judge_detail

// The analytic coverage of every pixel of the scene's view at width x height.
inline std::vector<Cover> analytic_coverage(const Scene& s, JudgeKind kind, int width, int height) {
  const Camera cam = Camera::from_view(s.view, width, height);
  auto hit_at = [&](double fi, double fj) {
    const double sx = (fi - 0.5 * (width - 1)) * cam.pitch;
    const double sy = (0.5 * (height - 1) - fj) * cam.pitch;
    const Vec3 d = normalize(cam.forward + sx * cam.right + sy * cam.up);
    const double tmin = cam.hither * std::sqrt(1 + sx * sx + sy * sy);
    return kind == JudgeKind::kDisk ? judge_detail::disk_hit(s, cam.eye, d)
                                    : judge_detail::convex_hit(s, cam.eye, d, tmin);
  };
  std::vector<Cover> cover(size_t(width) * size_t(height));
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      const bool c = hit_at(i, j);
      const bool stable = hit_at(i + kJudgeMargin, j) == c && hit_at(i - kJudgeMargin, j) == c &&
                          hit_at(i, j + kJudgeMargin) == c && hit_at(i, j - kJudgeMargin) == c;
      cover[size_t(j) * size_t(width) + size_t(i)] = !stable ? Cover::kSkip : c ? Cover::kHit : Cover::kMiss;
    }
  return cover;
}

}  // namespace lockstep::ray_cast_judges
