// lockstep core: small vector math shared by every implementation.
//
// Vec3T<T> is instantiated for double (the scene and the reference), float
// (the optimized kernels and the textbook-in-float variant) and __float128
// (the oracle). Everything is header-only and constexpr-friendly.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

namespace lockstep {

// ---------------------------------------------------------------- Vec3
template <typename T>
struct Vec3T {
  T x{}, y{}, z{};

  constexpr Vec3T() = default;
  constexpr Vec3T(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
  template <typename U>
  constexpr explicit Vec3T(const Vec3T<U>& v) : x(T(v.x)), y(T(v.y)), z(T(v.z)) {}

  constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr Vec3T operator-() const { return {-x, -y, -z}; }
  constexpr Vec3T& operator+=(const Vec3T& b) { x += b.x; y += b.y; z += b.z; return *this; }
  constexpr Vec3T& operator-=(const Vec3T& b) { x -= b.x; y -= b.y; z -= b.z; return *this; }
  constexpr Vec3T& operator*=(T s) { x *= s; y *= s; z *= s; return *this; }
  friend constexpr bool operator==(const Vec3T&, const Vec3T&) = default;
};

using Vec3 = Vec3T<double>;
using Vec3f = Vec3T<float>;

template <typename T> constexpr Vec3T<T> operator+(Vec3T<T> a, const Vec3T<T>& b) { return a += b; }
template <typename T> constexpr Vec3T<T> operator-(Vec3T<T> a, const Vec3T<T>& b) { return a -= b; }
template <typename T> constexpr Vec3T<T> operator*(Vec3T<T> a, T s) { return a *= s; }
template <typename T> constexpr Vec3T<T> operator*(T s, Vec3T<T> a) { return a *= s; }
template <typename T> constexpr Vec3T<T> operator/(Vec3T<T> a, T s) { return {a.x / s, a.y / s, a.z / s}; }
// Component-wise product (colours).
template <typename T> constexpr Vec3T<T> mul(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {a.x * b.x, a.y * b.y, a.z * b.z};
}
template <typename T> constexpr T dot(const Vec3T<T>& a, const Vec3T<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <typename T> constexpr Vec3T<T> cross(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <typename T> inline T length(const Vec3T<T>& a) { using std::sqrt; return sqrt(dot(a, a)); }
template <typename T> inline Vec3T<T> normalize(const Vec3T<T>& a) { return a / length(a); }
template <typename T> constexpr T max_abs_component(const Vec3T<T>& a) {
  T ax = a.x < 0 ? -a.x : a.x, ay = a.y < 0 ? -a.y : a.y, az = a.z < 0 ? -a.z : a.z;
  return ax > ay ? (ax > az ? ax : az) : (ay > az ? ay : az);
}
// Index (0, 1, 2) of the component with the largest magnitude.
template <typename T> constexpr int dominant_axis(const Vec3T<T>& a) {
  T ax = a.x < 0 ? -a.x : a.x, ay = a.y < 0 ? -a.y : a.y, az = a.z < 0 ? -a.z : a.z;
  return ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
}
inline bool is_finite(const Vec3& a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

// ---------------------------------------------------------------- Ray / Hit
inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A ray o + t d, valid for tmin < t < tmax. d need not be unit length; t is in units of |d|.
struct Ray {
  Vec3 o;
  Vec3 d;
  double tmin = 0.0;
  double tmax = kInfinity;
};

// What a nearest-hit query returns. prim indexes Scene::spheres first, then
// Scene::polygons (see Scene::prim_count); kNoHit when the ray misses.
struct Hit {
  static constexpr uint32_t kNoHit = 0xffffffffu;
  double t = kInfinity;
  uint32_t prim = kNoHit;
  uint32_t tri = kNoHit;  // triangle of the polygon's triangulation (patches: for normal interpolation)
  bool hit() const { return prim != kNoHit; }
};

}  // namespace lockstep
