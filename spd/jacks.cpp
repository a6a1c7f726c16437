// lockstep spd: jacks (the SPD's jacks.c, by Alexander Enzmann): a jack of
// three cylinders with spheres at the ends, and a half-size copy in each of
// its eight octants, recursively (sort of a Menger sponge), through the SPD's
// transform stack; one light.
#include "spd/scenes.h"

namespace lockstep::spd {

namespace {

// One jack in the current transform (jacks.c make_jack_obj).
void jack(Writer& w) {
  w.tx_push();
  w.tx_scale({0.75, 0.75, 0.75});  // no overlaps between neighbours
  w.cylcone({-1, 0, 0, 0.1}, {1, 0, 0, 0.1});
  w.cylcone({0, -1, 0, 0.1}, {0, 1, 0, 0.1});
  w.cylcone({0, 0, -1, 0.1}, {0, 0, 1, 0.1});
  for (const Vec4& c : {Vec4{1, 0, 0, 0.2}, Vec4{0, 1, 0, 0.2}, Vec4{0, 0, 1, 0.2},
                        Vec4{-1, 0, 0, 0.2}, Vec4{0, -1, 0, 0.2}, Vec4{0, 0, -1, 0.2}})
    w.sphere(c);
  w.tx_pop();
}

void recursive_jack(Writer& w, int depth, int max_depth) {
  jack(w);
  if (depth >= max_depth) return;
  for (double i = -0.5; i <= 0.5; i += 1)
    for (double j = -0.5; j <= 0.5; j += 1)
      for (double k = -0.5; k <= 0.5; k += 1) {
        w.tx_push();
        w.tx_translate({i, j, k});
        w.tx_scale({0.5, 0.5, 0.5});
        recursive_jack(w, depth + 1, max_depth);
        w.tx_pop();
      }
}

}  // namespace

void jacks(Writer& w, int size) {
  w.set_polygonalization(2, 2);
  w.background({0.2, 0.05, 0.2});  // dark purple
  w.viewpoint({0, 0, -8}, {0, 0, 0}, {0, 1, 0}, 25.0, 0.001, 256, 256);
  w.light({-10, 3, -20, 1.0});
  w.tx_push();
  w.tx_rotate(kX, -30 * kPi / 180.0);
  w.tx_rotate(kY, -20 * kPi / 180.0);
  w.color({0.737, 0.561, 0.561}, 0.1, 0.7, 0.7, 0.4, 20.0, 0.0, 1.0);  // pink
  recursive_jack(w, 1, size);
  w.tx_pop();
}

}  // namespace lockstep::spd
