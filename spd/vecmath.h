// lockstep spd: the vector and matrix routines the SPD generators build on.
//
// They follow the SPD's own library (Eric Haines, libvec.c, with Alexander
// Enzmann's additions; public domain) operation for operation: row vectors
// times row-major 4x4 matrices, the same order of products and sums. The
// files ../shared/spd holds were written by those routines, and a scene
// generated here matches them digit for digit only when the arithmetic is the
// same arithmetic (a different but "equivalent" rotation formula moves the
// last printed digit of thousands of vertices).
#pragma once

#include <array>
#include <cmath>

namespace lockstep::spd {

using Vec3 = std::array<double, 3>;
using Vec4 = std::array<double, 4>;  // a point and a radius (the SPD's COORD4)
using Matrix = std::array<std::array<double, 4>, 4>;

// The SPD's constants (def.h): PI as written there, EPSILON and EPSILON2 of
// the non-Macintosh build.
inline constexpr double kPi = 3.141592653589793;
inline constexpr double kEpsilon = 1.0e-8;
inline constexpr double kEpsilon2 = 1.0e-6;

enum Axis { kX = 0, kY = 1, kZ = 2 };

inline Vec3 xyz(const Vec4& v) { return {v[0], v[1], v[2]}; }
inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

// Normalizes v in place (unless it is zero) and returns its former length.
double normalize(Vec3& v);

Matrix zero_matrix();
Matrix identity();
// Rotation about a principal axis by `angle` radians (lib_create_rotate_matrix).
Matrix rotate(Axis axis, double angle);
// Rotation about the unit vector `axis` (lib_create_axis_rotate_matrix).
Matrix axis_rotate(const Vec3& axis, double angle);
Matrix translate(const Vec3& v);
Matrix scale(const Vec3& v);
// a * b (lib_matrix_multiply: row vectors, so a is applied first).
Matrix multiply(const Matrix& a, const Matrix& b);
Matrix transpose(const Matrix& m);
// Inverse by the adjoint; the identity when the determinant is below kEpsilon.
Matrix invert(const Matrix& m);

Vec3 transform_point(const Vec3& v, const Matrix& m);   // v * m, with translation
Vec3 transform_vector(const Vec3& v, const Matrix& m);  // v * m, no translation
Vec3 transform_normal(const Vec3& v, const Matrix& m);  // v * transpose(m)
Vec4 transform_coord(const Vec4& v, const Matrix& m);   // homogeneous v * m

// Turns a vector on one cube face to the next (lib_rotate_cube_face).
void rotate_cube_face(Vec3& v, int major_axis, int face);

// The SPD's portable Gaussian deviate for a seed (lib_gauss_rand, after
// Numerical Recipes' GASDEV with its own small linear congruential generator).
// mount depends on it bit for bit.
double gauss_rand(long seed);

}  // namespace lockstep::spd
