// lockstep spd: gears (Eric Haines' SPD gears.c): size^3 meshing gears of 36
// teeth, each a concave 144-gon top and bottom plus 144 side rectangles, on a
// reflective ground square; one gear in five transmissive; five lights.
#include <cmath>
#include <vector>

#include "spd/scenes.h"

namespace lockstep::spd {

namespace {

constexpr int kTeeth = 36;  // must be a multiple of 4
// The outer radius is a little short of the full radius so that meshing
// gears do not touch.
constexpr double kOuterEdgeRatio = 0.995;
constexpr double kInnerEdgeRatio = 0.9;
constexpr double kEdgeDiff = 1.0 - kInnerEdgeRatio;
constexpr double kDepthRatio = 0.1;  // thickness / width

// The four corners of one tooth (gears.c create_tooth).
void tooth(double gear_angle, double tooth_angle, const Vec3& center, const Vec3& outer,
           const Vec3& inner, Vec3* out) {
  const double fraction[4] = {-0.19, 0.19, 0.3, 0.7};
  for (int k = 0; k < 4; ++k) {
    const Matrix mx = rotate(kZ, gear_angle + fraction[k] * tooth_angle);
    out[k] = add(transform_vector(k < 2 ? outer : inner, mx), center);
  }
}

void gear(Writer& w, const Vec3& center, double offset_angle, double outer_radius,
          double inner_radius, double thickness) {
  Vec3 outer = {outer_radius, 0.0, 0.0}, inner = {inner_radius, 0.0, 0.0};
  const double tooth_angle = 2.0 * kPi / double(kTeeth);
  std::vector<Vec3> pts(4 * kTeeth);
  for (int t = 0; t < kTeeth; t++)
    tooth(offset_angle + 2.0 * kPi * double(t) / double(kTeeth), tooth_angle, center, outer, inner,
          &pts[size_t(t) * 4]);
  w.polygon(pts);
  for (int s = 0; s < 4 * kTeeth; s++) {
    const Vec3& a = pts[size_t(s)];
    const Vec3& b = pts[size_t((s + 1) % (4 * kTeeth))];
    w.polygon({a, {a[0], a[1], a[2] - thickness}, {b[0], b[1], b[2] - thickness}, b});
  }
  // The bottom: the same outline traced the other way round, one thickness down.
  outer[2] = inner[2] = -thickness;
  for (int t = 0; t < kTeeth; t++)
    tooth(offset_angle - 2.0 * kPi * double(t) / double(kTeeth), -tooth_angle, center, outer, inner,
          &pts[size_t(t) * 4]);
  w.polygon(pts);
}

double fraction(double a) { return a - double(int(a)); }

}  // namespace

void gears(Writer& w, int size) {
  w.background(kSkyBlue);
  w.viewpoint({-1.1, -2.1, 2.6}, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, 45.0, 1.0, 512, 512);
  w.light({2.0, 4.0, 4.0, 1.0});
  w.light({-2.0, 4.0, 3.0, 1.0});
  w.light({2.0, -2.5, 2.5, 1.0});
  w.light({-1.0, -4.0, 2.0, 1.0});
  w.light({-1.111, -2.121, 2.626, 1.0});  // just behind the eye
  // Ground: off white.
  w.color({1.0, 0.85, 0.7}, 0.0, 0.3, 0.6, 0.3, 37.0, 0.0, 0.0);
  w.polygon({{2.0, 2.0, 0.0}, {-2.0, 2.0, 0.0}, {-2.0, -2.0, 0.0}, {2.0, -2.0, 0.0}});

  const double outer_radius = 1.0 / (double(size) - double(size - 1) * kEdgeDiff / 2.0);
  const Vec3 zero = {-1.0 + outer_radius, -1.0 + outer_radius, 1.0};
  const Vec3 offset = {outer_radius * (2.0 - kEdgeDiff), outer_radius * (2.0 - kEdgeDiff),
                       -1.0 / double(size)};
  Vec3 center;
  for (int iz = 0; iz < size; iz++) {
    center[2] = zero[2] + double(iz) * offset[2];
    for (int iy = 0; iy < size; iy++) {
      center[1] = zero[1] + double(iy) * offset[1];
      for (int ix = 0; ix < size; ix++) {
        center[0] = zero[0] + double(ix) * offset[0];
        // A pseudo-random colour, brightest channel 1.
        Vec3 c = {0.01 + fraction(double(ix * 3 + iy * 2 + iz + 1) * 5.0 / 7.0),
                  0.01 + fraction(double(iy * 3 + iz * 2 + ix + 1) * 3.0 / 7.0),
                  0.01 + fraction(double(iz * 3 + ix * 2 + iy + 1) * 2.0 / 7.0)};
        double m = c[0] > c[1] ? c[0] : c[1];
        m = m > c[2] ? m : c[2];
        for (double& x : c) x /= m;
        if ((ix * 4 + iy * 2 + iz) % 5 == 0)
          w.color(c, 0.0, 0.2, 0.0, 0.0, 0.0, 0.8, 1.1);
        else
          w.color(c, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        const double angle = kPi * double((ix + iy + iz) % 2) / double(kTeeth);
        const double thickness = std::fmin(kDepthRatio, 1.0 / (2.0 * double(size)));
        gear(w, center, angle, kOuterEdgeRatio * outer_radius, (1.0 - kEdgeDiff) * outer_radius,
             thickness);
      }
    }
  }
}

}  // namespace lockstep::spd
