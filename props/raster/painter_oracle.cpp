// lockstep props/raster: the painter's exact oracle (painter_oracle.h).
#include "props/raster/painter_oracle.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

namespace lockstep::props::raster {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
K::Point_3 pt(const Vec3& v) { return K::Point_3(v.x, v.y, v.z); }
}  // namespace

bool oracle_triangles_intersect(const std::array<Vec3, 3>& t, const std::array<Vec3, 3>& u) {
  const K::Triangle_3 a(pt(t[0]), pt(t[1]), pt(t[2])), b(pt(u[0]), pt(u[1]), pt(u[2]));
  return CGAL::do_intersect(a, b);
}

int oracle_orientation(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const CGAL::Orientation o = CGAL::orientation(pt(a), pt(b), pt(c), pt(d));
  return o == CGAL::POSITIVE ? 1 : (o == CGAL::NEGATIVE ? -1 : 0);
}

bool oracle_collinear(const Vec3& a, const Vec3& b, const Vec3& c) {
  return CGAL::collinear(pt(a), pt(b), pt(c));
}

}  // namespace lockstep::props::raster
