// lockstep spd: the SPD library routines, NFF output (see spd/writer.h).
#include "spd/writer.h"

#include <cstdarg>
#include <cstdio>
#include <stdexcept>

namespace lockstep::spd {

void Writer::print(const char* fmt, ...) {
  char buf[512];
  va_list ap;
  va_start(ap, fmt);
  const int n = std::vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  if (n < 0 || size_t(n) >= sizeof buf)
    throw std::logic_error("spd: NFF line longer than 511 bytes");
  out_.append(buf, size_t(n));
}

bool Writer::tx_active() const {
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      if (std::fabs(tx_[i][j] - (i == j ? 1.0 : 0.0)) > kEpsilon) return true;
  return false;
}

double Writer::tx_scale_x() const {
  // lib_tx_unwind's X scale: the length of the first row of the upper 3x3,
  // after dividing by the homogeneous entry (1 for the transforms made here).
  const double w = tx_[3][3] != 0.0 ? tx_[3][3] : 1.0;
  Vec3 row = {tx_[0][0] / w, tx_[0][1] / w, tx_[0][2] / w};
  return std::fabs(normalize(row));
}

void Writer::tx_pop() {
  if (stack_.empty()) throw std::logic_error("spd: transform stack popped past its bottom");
  tx_ = stack_.back();
  stack_.pop_back();
}

void Writer::background(const Vec3& c) { print("b %g %g %g\n", c[0], c[1], c[2]); }

void Writer::viewpoint(const Vec3& from, const Vec3& at, const Vec3& up, double fov_degrees,
                       double hither, int resx, int resy) {
  print("v\n");
  print("from %g %g %g\n", from[0], from[1], from[2]);
  print("at %g %g %g\n", at[0], at[1], at[2]);
  print("up %g %g %g\n", up[0], up[1], up[2]);
  print("angle %g\n", fov_degrees);
  print("hither %g\n", hither);
  print("resolution %d %d\n", resx, resy);
}

void Writer::light(const Vec4& center) {
  // The SPD passes the light through lib_transform_vector (no translation).
  Vec3 v = xyz(center);
  if (tx_active()) v = transform_vector(v, tx_);
  print("l %g %g %g\n", v[0], v[1], v[2]);
}

void Writer::color(const Vec3& c, double /*ka*/, double kd, double ks, double /*ks_spec*/,
                   double ang, double kt, double ior) {
  const double rad = kPi * ang / 180.0;
  double phong;
  if (rad <= 0.0)
    phong = 100000.0;  // the SPD's "very very sharp": no visible highlight
  else if (rad >= kPi / 2.0)
    phong = 1.0;
  else
    phong = std::log(0.5) / std::log(std::cos(rad));
  print("f %g %g %g %g %g %g %g %g\n", c[0], c[1], c[2], kd, ks, phong, kt, ior);
}

void Writer::emit(const Vec3& e) { print("#lockstep emit %g %g %g\n", e[0], e[1], e[2]); }

void Writer::sphere(Vec4 c) {
  if (tess_) return polygon_sphere(c);
  if (tx_active()) {
    const Vec3 p = transform_point(xyz(c), tx_);
    c = {p[0], p[1], p[2], c[3] * tx_scale_x()};
  }
  print("s %g %g %g %g\n", c[0], c[1], c[2], c[3]);
}

void Writer::cylcone(Vec4 base, Vec4 apex) {
  if (tess_) return polygon_cylcone(base, apex);
  if (tx_active()) {
    const double s = tx_scale_x();
    const Vec3 b = transform_point(xyz(base), tx_), a = transform_point(xyz(apex), tx_);
    base = {b[0], b[1], b[2], base[3] * s};
    apex = {a[0], a[1], a[2], apex[3] * s};
  }
  print("c %g %g %g %g %g %g %g %g\n", base[0], base[1], base[2], base[3], apex[0], apex[1],
        apex[2], apex[3]);
}

void Writer::polygon(std::vector<Vec3> v) {
  // Merge a vertex into the next when they (nearly) coincide: the SPD's check.
  for (size_t i = 0; i < v.size();) {
    Vec3 d = sub(v[i], v[(i + 1) % v.size()]);
    if (normalize(d) < kEpsilon2)
      v.erase(v.begin() + long(i));
    else
      i++;
  }
  if (v.size() < 3) return;
  if (tx_active())
    for (Vec3& p : v) p = transform_point(p, tx_);
  print("p %d\n", int(v.size()));
  for (const Vec3& p : v) print("%g %g %g\n", p[0], p[1], p[2]);
}

void Writer::polypatch(std::array<Vec3, 3> v, std::array<Vec3, 3> n) {
  // A patch of three vertices passes the SPD's polygon splitter unchanged;
  // the transform moves points and carries normals by the inverse transpose
  // (not renormalized, as the SPD leaves them).
  if (tx_active()) {
    const Matrix inv = invert(tx_);
    for (int i = 0; i < 3; i++) {
      v[i] = transform_point(v[i], tx_);
      n[i] = transform_normal(n[i], inv);
    }
  }
  print("pp 3\n");
  for (int i = 0; i < 3; i++)
    print("%g %g %g %g %g %g\n", v[i][0], v[i][1], v[i][2], n[i][0], n[i][1], n[i][2]);
}

void Writer::height_field(const std::vector<float>& data, int rows, int cols, double x0, double x1,
                          double y0, double z0, double z1) {
  const double xdelta = (x1 - x0) / double(cols - 1), zdelta = (z1 - z0) / double(rows - 1);
  auto at = [&](int i, int j) { return double(data[size_t(i) * size_t(cols) + size_t(j)]); };
  for (int i = 0; i < rows - 1; i++) {
    for (int j = 0; j < cols - 1; j++) {
      const Vec3 v0 = {x0 + j * xdelta, y0 + at(i, j), z0 + i * zdelta};
      const Vec3 v1 = {x0 + (j + 1) * xdelta, y0 + at(i + 1, j + 1), z0 + (i + 1) * zdelta};
      const Vec3 v2 = {x0 + (j + 1) * xdelta, y0 + at(i, j + 1), z0 + i * zdelta};
      polygon({v0, v1, v2});
      const Vec3 v3 = {x0 + j * xdelta, y0 + at(i + 1, j), z0 + (i + 1) * zdelta};
      polygon({v0, v3, v1});
    }
  }
}

// A cylinder or cone as 4 * U quadrilateral strips, each two patches
// (lib_output_polygon_cylcone): a start direction perpendicular to the axis
// is swept round the axis by rotation matrices.
void Writer::polygon_cylcone(const Vec4& base, const Vec4& apex) {
  const Vec3 axis = sub(xyz(apex), xyz(base));
  Vec3 norm_axis = axis;
  const double height = normalize(norm_axis);
  Vec3 start_dir = cross(axis, Vec3{0.0, 0.0, 1.0});
  const double divisor = normalize(start_dir);
  if (std::fabs(divisor) < kEpsilon2) {
    start_dir = cross(axis, Vec3{1.0, 0.0, 0.0});
    normalize(start_dir);
  }
  const Vec3 r_base = {start_dir[0] * base[3], start_dir[1] * base[3], start_dir[2] * base[3]};
  const Vec3 r_apex = {start_dir[0] * apex[3], start_dir[1] * apex[3], start_dir[2] * apex[3]};
  std::array<Vec3, 3> vert, norm;
  vert[2] = add(xyz(base), r_base);
  vert[1] = add(xyz(apex), r_apex);
  Vec3 start_norm = start_dir;
  if (base[3] != apex[3]) {
    // A cone: tilt the normal by the slope of its side.
    const double ba = base[3] - apex[3];
    for (int k = 0; k < 3; k++) start_norm[k] = start_dir[k] * height + norm_axis[k] * ba;
    normalize(start_norm);
  }
  norm[2] = start_norm;
  norm[1] = start_norm;
  const double delta = 2.0 * kPi / double(4 * u_res_);
  double angle = delta;
  for (int i = 1; i <= 4 * u_res_; ++i, angle += delta) {
    const Matrix mx = axis_rotate(norm_axis, angle), nmx = invert(mx);
    vert[0] = add(transform_point(r_apex, mx), xyz(apex));
    norm[0] = transform_normal(start_norm, nmx);
    polypatch(vert, norm);
    vert[1] = vert[0];
    norm[1] = norm[0];
    vert[0] = add(transform_point(r_base, mx), xyz(base));
    polypatch(vert, norm);
    vert[2] = vert[0];
    norm[2] = norm[0];
  }
}

// A sphere as the six faces of a cube, each a grid of U x V cells split into
// two patches, pushed out to the sphere (lib_output_polygon_sphere).
void Writer::polygon_sphere(const Vec4& c) {
  const int nu = u_res_, nv = v_res_;
  std::vector<Vec3> x_axis(size_t(nu) + 1), y_axis(size_t(nv) + 1);
  for (int e = 0; e <= nu; ++e) {
    const double angle = (kPi / 4.0) * (2.0 * double(e) / nu - 1.0);
    x_axis[size_t(e)] = transform_vector({1.0, 0.0, 0.0}, rotate(kY, angle));
  }
  for (int e = 0; e <= nv; ++e) {
    const double angle = (kPi / 4.0) * (2.0 * double(e) / nv - 1.0);
    y_axis[size_t(e)] = transform_vector({0.0, 1.0, 0.0}, rotate(kX, angle));
  }
  // The grid on the +Z face (the SPD fills it U by U, as here).
  std::vector<std::vector<Vec3>> pt(size_t(nu) + 1, std::vector<Vec3>(size_t(nv) + 1));
  for (int u = 0; u <= nu; ++u)
    for (int v = 0; v <= nv; ++v) {
      pt[size_t(u)][size_t(v)] = cross(x_axis[size_t(u)], y_axis[size_t(v)]);
      normalize(pt[size_t(u)][size_t(v)]);
    }
  for (int face = 0; face < 6; ++face) {
    for (auto& row : pt)
      for (Vec3& p : row) rotate_cube_face(p, kZ, face);
    for (int u = 0; u < nu; ++u)
      for (int v = 0; v < nv; ++v)
        for (int tri = 0; tri < 2; ++tri) {
          std::array<Vec3, 3> ep, en;
          for (int e = 0; e < 3; ++e) {
            const int k = (tri * 2 + e) % 4;
            const int du = (k == 2 || k == 3) ? 1 : 0, dv = (k == 1 || k == 2) ? 1 : 0;
            const Vec3& p = pt[size_t(u + du)][size_t(v + dv)];
            en[size_t(e)] = p;
            ep[size_t(e)] = {p[0] * c[3] + c[0], p[1] * c[3] + c[1], p[2] * c[3] + c[2]};
          }
          polypatch(ep, en);
        }
  }
}

}  // namespace lockstep::spd
