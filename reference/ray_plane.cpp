// Ray-plane intersection, the textbook way.
//
// Source: Haines, "Essential Ray Tracing Algorithms" (Glassner, An Introduction
// to Ray Tracing, ch. 2.3). Plane A x + B y + C z + D = 0 with N = (A, B, C):
// substituting P(t) = o + t d gives N.o + t N.d + D = 0, so
//     t = -(N.o + D) / (N.d),
// and N.d = 0 means the ray runs parallel to the plane: no hit.
#include "reference/ray_cast.h"

namespace lockstep::ref {

namespace {

template <typename T>
double plane_t(const Ray& ray, const Plane& plane) {
  const Vec3T<T> n(plane.n), o(ray.o), d(ray.d);
  const T denominator = dot(n, d);
  if (denominator == T(0)) return kInfinity;  // parallel: no intersection (or the ray lies in it)
  const T t = -(dot(n, o) + T(plane.d)) / denominator;
  if (double(t) <= ray.tmin || double(t) >= ray.tmax) return kInfinity;  // behind the origin or too far
  return double(t);
}

}  // namespace

void ray_plane(std::span<const Ray> rays, const Plane& plane, std::span<double> t) {
  for (size_t i = 0; i < rays.size(); ++i) t[i] = plane_t<double>(rays[i], plane);
}

void ray_plane_f32(std::span<const Ray> rays, const Plane& plane, std::span<double> t) {
  for (size_t i = 0; i < rays.size(); ++i) t[i] = plane_t<float>(rays[i], plane);
}

}  // namespace lockstep::ref
