// lockstep props/raster: the exact oracle for the painter's predicates (CGAL's
// exact-predicates kernel; built into lockstep_oracle, the only place CGAL may be used).
#pragma once

#include <array>

#include "core/math.h"

namespace lockstep::props::raster {

// Whether the closed, non-degenerate triangles t and u share a point
// (CGAL::do_intersect on Epick's Triangle_3: exact predicates).
bool oracle_triangles_intersect(const std::array<Vec3, 3>& t, const std::array<Vec3, 3>& u);
// CGAL::orientation(a, b, c, d) as +1 / 0 / -1 (exact).
int oracle_orientation(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
// Whether a, b, c are collinear (exact).
bool oracle_collinear(const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace lockstep::props::raster
