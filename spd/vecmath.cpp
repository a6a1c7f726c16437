// lockstep spd: vector and matrix routines (see spd/vecmath.h).
#include "spd/vecmath.h"

namespace lockstep::spd {

double normalize(Vec3& v) {
  const double d = std::sqrt(dot(v, v));
  if (d > 0.0) {
    v[0] /= d;
    v[1] /= d;
    v[2] /= d;
  }
  return d;
}

Matrix zero_matrix() { return Matrix{}; }

Matrix identity() {
  Matrix m{};
  for (int i = 0; i < 4; ++i) m[i][i] = 1.0;
  return m;
}

Matrix rotate(Axis axis, double angle) {
  Matrix m{};
  const double c = std::cos(angle), s = std::sin(angle);
  switch (axis) {
    case kX:
      m[0][0] = 1.0;
      m[1][1] = c;
      m[2][2] = c;
      m[1][2] = s;
      m[2][1] = -s;
      break;
    case kY:
      m[1][1] = 1.0;
      m[0][0] = c;
      m[2][2] = c;
      m[2][0] = s;
      m[0][2] = -s;
      break;
    case kZ:
      m[2][2] = 1.0;
      m[0][0] = c;
      m[1][1] = c;
      m[0][1] = s;
      m[1][0] = -s;
      break;
  }
  m[3][3] = 1.0;
  return m;
}

Matrix axis_rotate(const Vec3& a, double angle) {
  const double c = std::cos(angle), s = std::sin(angle), omc = 1.0 - c;
  Matrix m{};
  m[0][0] = a[0] * a[0] + (1.0 - a[0] * a[0]) * c;
  m[0][1] = a[0] * a[1] * omc + a[2] * s;
  m[0][2] = a[0] * a[2] * omc - a[1] * s;
  m[1][0] = a[0] * a[1] * omc - a[2] * s;
  m[1][1] = a[1] * a[1] + (1.0 - a[1] * a[1]) * c;
  m[1][2] = a[1] * a[2] * omc + a[0] * s;
  m[2][0] = a[0] * a[2] * omc + a[1] * s;
  m[2][1] = a[1] * a[2] * omc - a[0] * s;
  m[2][2] = a[2] * a[2] + (1.0 - a[2] * a[2]) * c;
  m[3][3] = 1.0;
  return m;
}

Matrix translate(const Vec3& v) {
  Matrix m = identity();
  m[3][0] = v[0];
  m[3][1] = v[1];
  m[3][2] = v[2];
  return m;
}

Matrix scale(const Vec3& v) {
  Matrix m{};
  m[0][0] = v[0];
  m[1][1] = v[1];
  m[2][2] = v[2];
  m[3][3] = 1.0;
  return m;
}

Matrix multiply(const Matrix& a, const Matrix& b) {
  Matrix r;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j] + a[i][3] * b[3][j];
  return r;
}

Matrix transpose(const Matrix& m) {
  Matrix r;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) r[j][i] = m[i][j];
  return r;
}

namespace {

double det3(double a1, double a2, double a3, double b1, double b2, double b3, double c1, double c2,
            double c3) {
  return a1 * (b2 * c3 - b3 * c2) - b1 * (a2 * c3 - a3 * c2) + c1 * (a2 * b3 - a3 * b2);
}

// The entries of m named as the SPD names them: column letter, row number.
struct Named {
  double a1, b1, c1, d1, a2, b2, c2, d2, a3, b3, c3, d3, a4, b4, c4, d4;
  explicit Named(const Matrix& m)
      : a1(m[0][0]),
        b1(m[0][1]),
        c1(m[0][2]),
        d1(m[0][3]),
        a2(m[1][0]),
        b2(m[1][1]),
        c2(m[1][2]),
        d2(m[1][3]),
        a3(m[2][0]),
        b3(m[2][1]),
        c3(m[2][2]),
        d3(m[2][3]),
        a4(m[3][0]),
        b4(m[3][1]),
        c4(m[3][2]),
        d4(m[3][3]) {}
};

Matrix adjoint(const Matrix& in) {
  const Named n(in);
  Matrix o;
  o[0][0] = det3(n.b2, n.b3, n.b4, n.c2, n.c3, n.c4, n.d2, n.d3, n.d4);
  o[1][0] = -det3(n.a2, n.a3, n.a4, n.c2, n.c3, n.c4, n.d2, n.d3, n.d4);
  o[2][0] = det3(n.a2, n.a3, n.a4, n.b2, n.b3, n.b4, n.d2, n.d3, n.d4);
  o[3][0] = -det3(n.a2, n.a3, n.a4, n.b2, n.b3, n.b4, n.c2, n.c3, n.c4);
  o[0][1] = -det3(n.b1, n.b3, n.b4, n.c1, n.c3, n.c4, n.d1, n.d3, n.d4);
  o[1][1] = det3(n.a1, n.a3, n.a4, n.c1, n.c3, n.c4, n.d1, n.d3, n.d4);
  o[2][1] = -det3(n.a1, n.a3, n.a4, n.b1, n.b3, n.b4, n.d1, n.d3, n.d4);
  o[3][1] = det3(n.a1, n.a3, n.a4, n.b1, n.b3, n.b4, n.c1, n.c3, n.c4);
  o[0][2] = det3(n.b1, n.b2, n.b4, n.c1, n.c2, n.c4, n.d1, n.d2, n.d4);
  o[1][2] = -det3(n.a1, n.a2, n.a4, n.c1, n.c2, n.c4, n.d1, n.d2, n.d4);
  o[2][2] = det3(n.a1, n.a2, n.a4, n.b1, n.b2, n.b4, n.d1, n.d2, n.d4);
  o[3][2] = -det3(n.a1, n.a2, n.a4, n.b1, n.b2, n.b4, n.c1, n.c2, n.c4);
  o[0][3] = -det3(n.b1, n.b2, n.b3, n.c1, n.c2, n.c3, n.d1, n.d2, n.d3);
  o[1][3] = det3(n.a1, n.a2, n.a3, n.c1, n.c2, n.c3, n.d1, n.d2, n.d3);
  o[2][3] = -det3(n.a1, n.a2, n.a3, n.b1, n.b2, n.b3, n.d1, n.d2, n.d3);
  o[3][3] = det3(n.a1, n.a2, n.a3, n.b1, n.b2, n.b3, n.c1, n.c2, n.c3);
  return o;
}

double det4(const Matrix& m) {
  const Named n(m);
  return n.a1 * det3(n.b2, n.b3, n.b4, n.c2, n.c3, n.c4, n.d2, n.d3, n.d4) -
         n.b1 * det3(n.a2, n.a3, n.a4, n.c2, n.c3, n.c4, n.d2, n.d3, n.d4) +
         n.c1 * det3(n.a2, n.a3, n.a4, n.b2, n.b3, n.b4, n.d2, n.d3, n.d4) -
         n.d1 * det3(n.a2, n.a3, n.a4, n.b2, n.b3, n.b4, n.c2, n.c3, n.c4);
}

}  // namespace

Matrix invert(const Matrix& m) {
  Matrix o = adjoint(m);
  const double det = det4(m);
  if (std::fabs(det) < kEpsilon) return identity();
  for (auto& row : o)
    for (double& x : row) x /= det;
  return o;
}

Vec3 transform_point(const Vec3& v, const Matrix& m) {
  return {v[0] * m[0][0] + v[1] * m[1][0] + v[2] * m[2][0] + m[3][0],
          v[0] * m[0][1] + v[1] * m[1][1] + v[2] * m[2][1] + m[3][1],
          v[0] * m[0][2] + v[1] * m[1][2] + v[2] * m[2][2] + m[3][2]};
}

Vec3 transform_vector(const Vec3& v, const Matrix& m) {
  return {v[0] * m[0][0] + v[1] * m[1][0] + v[2] * m[2][0],
          v[0] * m[0][1] + v[1] * m[1][1] + v[2] * m[2][1],
          v[0] * m[0][2] + v[1] * m[1][2] + v[2] * m[2][2]};
}

Vec3 transform_normal(const Vec3& v, const Matrix& m) {
  return {v[0] * m[0][0] + v[1] * m[0][1] + v[2] * m[0][2],
          v[0] * m[1][0] + v[1] * m[1][1] + v[2] * m[1][2],
          v[0] * m[2][0] + v[1] * m[2][1] + v[2] * m[2][2]};
}

Vec4 transform_coord(const Vec4& v, const Matrix& m) {
  Vec4 r;
  for (int j = 0; j < 4; ++j)
    r[j] = v[0] * m[0][j] + v[1] * m[1][j] + v[2] * m[2][j] + v[3] * m[3][j];
  return r;
}

void rotate_cube_face(Vec3& v, int major_axis, int face) {
  face = (face + major_axis) % 3;
  double swap;
  if (face == 0) {
    swap = v[0];
    v[0] = -v[1];
    v[1] = swap;
  } else if (face == 1) {
    swap = v[1];
    v[1] = -v[2];
    v[2] = swap;
  } else {
    swap = v[0];
    v[0] = -v[2];
    v[2] = swap;
  }
}

double gauss_rand(long seed) {
  // The generator's constants (libvec.c). The SPD writes its scale factor as
  // the macro `1.0/M1`, so `ix * 2.0 * RM1` is (ix * 2.0 * 1.0) / M1.
  constexpr long kM1 = 134456, kIA1 = 8121, kIC1 = 28411;
  long ix1, ix2 = seed;
  double v1, v2, r;
  do {
    ix1 = (kIC1 + ix2 * kIA1) % kM1;
    ix2 = (kIC1 + ix1 * kIA1) % kM1;
    v1 = double(ix1) * 2.0 * 1.0 / double(kM1) - 1.0;
    v2 = double(ix2) * 2.0 * 1.0 / double(kM1) - 1.0;
    r = v1 * v1 + v2 * v2;
  } while (r >= 1.0);
  return v1 * std::sqrt(-2.0 * std::log(r) / r);
}

}  // namespace lockstep::spd
