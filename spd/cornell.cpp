// lockstep spd: the Cornell box, for radiosity (issue #33). Not one of Eric
// Haines' SPD programs: the Cornell University Program of Computer Graphics'
// measured "Cornell Box Data" (www.graphics.cornell.edu/online/box/data.html,
// provided for public use), in millimetres, written as NFF with the light an
// emitter ('#lockstep emit', io/nff.h), every polygon facing into the room.
// corpus/radiosity/cornell_box.nff is this file with its credits in comments
// (corpus/radiosity/README.md: the light lowered 0.1 mm below the ceiling, the
// spectra reduced to RGB, the emission pi times the light's radiance 17 12 4).
#include <array>
#include <vector>

#include "spd/scenes.h"

namespace lockstep::spd {

namespace {

using Quad = std::array<Vec3, 4>;

// Diffuse only: kd 1, no highlight (the SPD's angle 90: Phong exponent 1).
void diffuse(Writer& w, const Vec3& colour) { w.color(colour, 0, 1, 0, 0, 90, 0, 1); }

void quads(Writer& w, const std::vector<Quad>& qs) {
  for (const Quad& q : qs) w.polygon({q[0], q[1], q[2], q[3]});
}

}  // namespace

void cornell(Writer& w, int /*size: 1 only*/) {
  w.viewpoint({278, 273, -800}, {278, 273, 0}, {0, 1, 0}, 39.3, 1, 256, 256);
  w.background({0, 0, 0});
  const Vec3 white = {0.725, 0.71, 0.68}, red = {0.63, 0.065, 0.05}, green = {0.14, 0.45, 0.091};
  // The light, 130 x 105, 0.1 mm under the ceiling, facing down.
  diffuse(w, {0.78, 0.78, 0.78});
  w.emit({53.407, 37.699, 12.566});
  quads(w, {{{{343.0, 548.7, 227.0}, {343.0, 548.7, 332.0}, {213.0, 548.7, 332.0}, {213.0, 548.7, 227.0}}}});
  // Floor, ceiling, back wall.
  diffuse(w, white);
  quads(w, {{{{552.8, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 559.2}, {549.6, 0.0, 559.2}}},
            {{{556.0, 548.8, 0.0}, {556.0, 548.8, 559.2}, {0.0, 548.8, 559.2}, {0.0, 548.8, 0.0}}},
            {{{549.6, 0.0, 559.2}, {0.0, 0.0, 559.2}, {0.0, 548.8, 559.2}, {556.0, 548.8, 559.2}}}});
  // The right wall (x = 0), green; the left wall (x = 550), red.
  diffuse(w, green);
  quads(w, {{{{0.0, 0.0, 559.2}, {0.0, 0.0, 0.0}, {0.0, 548.8, 0.0}, {0.0, 548.8, 559.2}}}});
  diffuse(w, red);
  quads(w, {{{{552.8, 0.0, 0.0}, {549.6, 0.0, 559.2}, {556.0, 548.8, 559.2}, {556.0, 548.8, 0.0}}}});
  // The short block (165 mm) and the tall one (330 mm): top, then sides.
  diffuse(w, white);
  quads(w, {{{{130.0, 165.0, 65.0}, {82.0, 165.0, 225.0}, {240.0, 165.0, 272.0}, {290.0, 165.0, 114.0}}},
            {{{290.0, 0.0, 114.0}, {290.0, 165.0, 114.0}, {240.0, 165.0, 272.0}, {240.0, 0.0, 272.0}}},
            {{{130.0, 0.0, 65.0}, {130.0, 165.0, 65.0}, {290.0, 165.0, 114.0}, {290.0, 0.0, 114.0}}},
            {{{82.0, 0.0, 225.0}, {82.0, 165.0, 225.0}, {130.0, 165.0, 65.0}, {130.0, 0.0, 65.0}}},
            {{{240.0, 0.0, 272.0}, {240.0, 165.0, 272.0}, {82.0, 165.0, 225.0}, {82.0, 0.0, 225.0}}}});
  quads(w, {{{{423.0, 330.0, 247.0}, {265.0, 330.0, 296.0}, {314.0, 330.0, 456.0}, {472.0, 330.0, 406.0}}},
            {{{423.0, 0.0, 247.0}, {423.0, 330.0, 247.0}, {472.0, 330.0, 406.0}, {472.0, 0.0, 406.0}}},
            {{{472.0, 0.0, 406.0}, {472.0, 330.0, 406.0}, {314.0, 330.0, 456.0}, {314.0, 0.0, 456.0}}},
            {{{314.0, 0.0, 456.0}, {314.0, 330.0, 456.0}, {265.0, 330.0, 296.0}, {265.0, 0.0, 296.0}}},
            {{{265.0, 0.0, 296.0}, {265.0, 330.0, 296.0}, {423.0, 330.0, 247.0}, {423.0, 0.0, 247.0}}}});
}

}  // namespace lockstep::spd
