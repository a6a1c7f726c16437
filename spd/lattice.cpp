// lockstep spd: lattice (the SPD's lattice.c, by Antonio Costa): shiny
// spheres on a cubic grid of (size+1)^3 points, neighbours joined by matte
// cylinders; six lights.
#include <cmath>

#include "spd/scenes.h"

namespace lockstep::spd {

void lattice(Writer& w, int size) {
  const double kRadius1 = 1.0 / 4.0, kRadius2 = 1.0 / 16.0;
  const double inv = 1.0 / double(size);
  const double radius1 = kRadius1 / double(size), radius2 = kRadius2 / double(size);
  // Cylinders stop a little inside the spheres they join.
  const double delta = (radius1 * (1.0 - std::sqrt(kRadius2 / kRadius1))) * 0.99;
  w.background(kSkyBlue);
  w.viewpoint({(double(size >> 1) + 0.5) * inv, 1.0, 1.0 - 1.0 / double(size << 1)},
              {(double(size >> 1) + 0.5) * inv, -1.0, -1.0 - 1.0 / double(size << 1)},
              {0.2, 1.0, 0.0}, 60.0, 0.0, 512, 512);
  for (const Vec4& l :
       {Vec4{2.0, 0.5, 0.5, 1.0}, Vec4{-1.0, 0.5, 0.5, 1.0}, Vec4{0.5, 2.0, 0.5, 1.0},
        Vec4{0.5, -1.0, 0.5, 1.0}, Vec4{0.5, 0.5, 2.0, 1.0}, Vec4{0.5, 0.5, -1.0, 1.0}})
    w.light(l);
  for (long x = 0; x <= size; x++) {
    const double x0 = double(x) / double(size);
    for (long y = 0; y <= size; y++) {
      const double y0 = double(y) / double(size);
      for (long z = 0; z <= size; z++) {
        const double z0 = double(z) / double(size);
        w.color({0.9, 0.9, 0.9}, 0.0, 0.5, 0.5, 0.5, 37.0, 0.0, 0.0);
        w.sphere({x0, y0, z0, radius1});
        if (x != size) {
          w.color({0.9, 0.1, 0.1}, 0.1, 0.99, 0.0, 0.0, 0.0, 0.0, 0.0);
          w.cylcone({x0 + delta, y0, z0, radius2}, {x0 + inv - delta, y0, z0, radius2});
        }
        if (y != size) {
          w.color({0.1, 0.9, 0.1}, 0.1, 0.99, 0.0, 0.0, 0.0, 0.0, 0.0);
          w.cylcone({x0, y0 + delta, z0, radius2}, {x0, y0 + inv - delta, z0, radius2});
        }
        if (z != size) {
          w.color({0.1, 0.1, 0.9}, 0.1, 0.99, 0.0, 0.0, 0.0, 0.0, 0.0);
          w.cylcone({x0, y0, z0 + delta, radius2}, {x0, y0, z0 + inv - delta, radius2});
        }
      }
    }
  }
}

}  // namespace lockstep::spd
