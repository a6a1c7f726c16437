// lockstep spd: sombrero, a height field (the SPD's sombrero.c, by Alexander
// Enzmann and Eduard Schwan): z = cos(2 pi r) e^-r on a 32*2^(size-1) square
// grid, two triangles per cell; one light.
#include <vector>

#include "spd/scenes.h"

namespace lockstep::spd {

namespace {

// Samples the sombrero on n x n points from -4 (sombrero.c create_sombrero).
// The SPD stores the samples as float and steps x and y by accumulation: both
// are kept, they decide the last printed digit.
std::vector<float> sample(int n, double x0, double x1, double y0, double y1) {
  const double a = 1.0, b = 1.0, c = 3.0;
  const double two_pi_a = 2.0 * 3.14159265358 * a;  // sombrero.c's own pi
  const double dx = (x1 - x0) / double(n), dy = (y1 - y0) / double(n);
  std::vector<float> data(size_t(n) * size_t(n));
  double y = y0;
  for (int i = 0; i < n; i++, y += dy) {
    double x = x0;
    for (int j = 0; j < n; j++, x += dx)
      data[size_t(i) * size_t(n) + size_t(j)] =
          float(c * std::cos(two_pi_a * std::sqrt(x * x + y * y)) *
                std::exp(-b * std::sqrt(x * x + y * y)) / 3.0);
  }
  return data;
}

}  // namespace

void sombrero(Writer& w, int size) {
  w.set_polygonalization(3, 3);
  w.background(kSkyBlue);
  w.viewpoint({0.0, 5.0, -8.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, 40.0, 0.01, 512, 512);
  w.light({10.0, 10.0, -10.0, 1.0});
  // Shiny red.
  w.color({1.0, 0.1, 0.1}, 0.1, 0.8, 0.0, 0.5, 40.0, 0.0, 1.0);
  const int n = 32 * (1 << (size - 1));
  w.height_field(sample(n, -4.0, 4.0, -4.0, 4.0), n, n, -4.0, 4.0, -3.0, -4.0, 4.0);
}

}  // namespace lockstep::spd
