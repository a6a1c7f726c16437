// Ray-sphere kernel, reference: the quadratic formula, nearest root in range.
// See reference/ray_sphere.h for the derivation.
#include "reference/ray_sphere.h"

#include "reference/ray_cast.h"

namespace lockstep::ref {

namespace {

template <typename T>
double nearest_root(const Ray& ray, const Sphere& s) {
  T t0, t1;
  if (!sphere_roots<T>(Vec3T<T>(ray.o), Vec3T<T>(ray.d), Vec3T<T>(s.center), T(s.radius), t0, t1))
    return kInfinity;
  // The nearest root in front of the ray origin (past tmin) is the visible one.
  if (double(t0) > ray.tmin && double(t0) < ray.tmax) return double(t0);
  if (double(t1) > ray.tmin && double(t1) < ray.tmax) return double(t1);
  return kInfinity;
}

}  // namespace

void ray_sphere(std::span<const Ray> rays, const Sphere& sphere, std::span<double> t) {
  for (size_t i = 0; i < rays.size(); ++i) t[i] = nearest_root<double>(rays[i], sphere);
}

void ray_sphere_f32(std::span<const Ray> rays, const Sphere& sphere, std::span<double> t) {
  for (size_t i = 0; i < rays.size(); ++i) t[i] = nearest_root<float>(rays[i], sphere);
}

}  // namespace lockstep::ref
