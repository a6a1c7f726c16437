// lockstep spd: shells (Eric Haines' SPD shells.c, after Pickover, IEEE CG&A
// November 1989): a spiral of 180*2^size+1 overlapping spheres growing
// exponentially, a pathological case for ray tracers; one light. The SPD's
// extra shape parameters keep their defaults here.
#include <cmath>

#include "spd/scenes.h"

namespace lockstep::spd {

void shells(Writer& w, int size) {
  const double gamma = 1.0, alpha = 0.0, beta = -2.0, a = 0.15, k = 1.0;
  w.background(kSkyBlue);
  w.viewpoint({-6.0, -60.0, 35.0}, {0.0, 8.0, -15.0}, {0.0, 0.0, 1.0}, 45.0, 0.5, 512, 512);
  w.light({-100.0, -100.0, 100.0, 1.0});
  w.color({1.0, 0.8, 0.4}, 0.0, 0.8, 0.2, 0.5, 10.0, 0.0, 1.0);
  const long steps = long(180.0 * std::pow(2.0, double(size)));
  for (long i = -steps * 2 / 3; i <= steps / 3; ++i) {
    const double angle = 3.0 * 6.0 * kPi * double(i) / double(steps);
    const double r = k * std::exp(a * angle);
    Vec4 s = {r * std::sin(angle), r * std::cos(angle), 0.0, r / gamma};
    s[2] = alpha > 0.0 ? alpha * angle : beta * r;
    w.sphere(s);
  }
}

}  // namespace lockstep::spd
