// lockstep spd: the SPD library routines a generator calls, writing NFF.
//
// Eric Haines' Standard Procedural Databases (public domain) share one output
// library (lib*.c: view, lights, surface colours, spheres, cones and
// cylinders, polygons, patches, height fields, polygonalization, a transform
// stack). This is that library reduced to its NFF output (`-r 1`), written
// for lockstep: all of its state (the text so far, the transform stack, the
// polygonalization) lives in a Writer the generator is handed, and numbers
// are printed with printf's %g as the SPD prints them, so a generated file
// can be compared with one the SPD programs wrote.
//
// Curved primitives follow the SPD's two output modes: true curves (`s`, and
// `c` with all eight numbers on the `c` line, as the SPD writes them), or,
// with tess (the SPD's -t), polygonalized into three-vertex `pp` patches
// with vertex normals (spheres from a subdivided cube, cylinders and cones
// from 4*U strips).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "spd/vecmath.h"

namespace lockstep::spd {

class Writer {
 public:
  explicit Writer(bool tess) : tess_(tess) {}

  // The polygonalization of tessellated primitives (lib_set_polygonalization):
  // spheres get 6 * 2 * u * v triangles, cylinders and cones 2 * 4 * u.
  void set_polygonalization(int u, int v) {
    u_res_ = u;
    v_res_ = v;
  }

  void background(const Vec3& c);
  void viewpoint(const Vec3& from, const Vec3& at, const Vec3& up, double fov_degrees,
                 double hither, int resx, int resy);
  // A point light at xyz (transformed by the current transform); the SPD's
  // fourth component, its intensity, is not part of NFF.
  void light(const Vec4& center);
  // The surface for what follows. ang: the half angle, in degrees, at which
  // the highlight falls to half strength (turned into a Phong exponent as the
  // SPD does); ka and ks_spec are not part of NFF.
  void color(const Vec3& c, double ka, double kd, double ks, double ks_spec, double ang, double kt,
             double ior);
  // lockstep's NFF extension (io/nff.h): the polygons after the current
  // `f` line emit radiosity e per channel ("#lockstep emit r g b", a comment
  // to other readers).
  void emit(const Vec3& e);
  void sphere(Vec4 center);
  void cylcone(Vec4 base, Vec4 apex);
  // A planar polygon; adjacent duplicate vertices are merged first and a
  // polygon left with fewer than three is dropped (lib_output_polygon).
  void polygon(std::vector<Vec3> verts);
  // A triangle with vertex normals.
  void polypatch(std::array<Vec3, 3> verts, std::array<Vec3, 3> norms);
  // A height field of rows x cols samples z = data[row][col] (row-major),
  // spanning x0..x1 across columns and z0..z1 across rows, heights added to
  // y0, written as two triangles per cell (lib_output_polygon_height).
  void height_field(const std::vector<float>& data, int rows, int cols, double x0, double x1,
                    double y0, double z0, double z1);

  // The transform stack (libtx.c): each call pre-multiplies the current
  // transform, so the last one named applies first.
  void tx_push() { stack_.push_back(tx_); }
  void tx_pop();
  void tx_rotate(Axis axis, double angle) { tx_ = multiply(rotate(axis, angle), tx_); }
  void tx_scale(const Vec3& v) { tx_ = multiply(scale(v), tx_); }
  void tx_translate(const Vec3& v) { tx_ = multiply(translate(v), tx_); }

  const std::string& text() const { return out_; }
  std::string take() { return std::move(out_); }

 private:
  void print(const char* fmt, ...) __attribute__((format(printf, 2, 3)));
  bool tx_active() const;
  // The current transform's X scale, as the SPD scales radii under a
  // transform (it assumes uniform scaling).
  double tx_scale_x() const;
  void polygon_cylcone(const Vec4& base, const Vec4& apex);
  void polygon_sphere(const Vec4& center);

  std::string out_;
  bool tess_;
  int u_res_ = 3, v_res_ = 3;  // OUTPUT_RESOLUTION in the SPD's lib.h
  Matrix tx_ = identity();
  std::vector<Matrix> stack_;
};

}  // namespace lockstep::spd
