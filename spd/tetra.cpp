// lockstep spd: tetra, a Sierpinski tetrahedral pyramid (Eric Haines' SPD
// tetra.c, after the scene of Glassner 1984 and Kay & Kajiya 1986):
// 4^size triangles, one light.
#include <array>

#include "spd/scenes.h"

namespace lockstep::spd {

namespace {

// center: xyz and W, the half-width of the cube whose alternate corners make
// the tetrahedron (tetra.c create_tetra).
void tetrahedra(Writer& w, int depth, const Vec4& center) {
  if (depth <= 1) {
    std::array<Vec3, 4> pt;
    int n = 0;
    for (int x = -1; x <= 1; x += 2)
      for (int y = -1; y <= 1; y += 2)
        for (int z = -1; z <= 1; z += 2)
          if (x * y * z == 1)
            pt[size_t(n++)] = {center[0] + double(x) * center[3], center[1] + double(y) * center[3],
                               center[2] + double(z) * center[3]};
    // Faces 0 1 2, 3 2 1, 2 3 0, 1 0 3: odd faces reversed to face outwards.
    for (int face = 0; face < 4; ++face) {
      std::array<int, 3> ord = {face % 4, (face + 1) % 4, (face + 2) % 4};
      if (face % 2 == 1) std::swap(ord[0], ord[2]);
      w.polygon({pt[size_t(ord[0])], pt[size_t(ord[1])], pt[size_t(ord[2])]});
    }
    return;
  }
  for (int x = -1; x <= 1; x += 2)
    for (int y = -1; y <= 1; y += 2)
      for (int z = -1; z <= 1; z += 2)
        if (x * y * z == 1)
          tetrahedra(
              w, depth - 1,
              {center[0] + double(x) * center[3] / 2.0, center[1] + double(y) * center[3] / 2.0,
               center[2] + double(z) * center[3] / 2.0, center[3] / 2.0});
}

}  // namespace

void tetra(Writer& w, int size) {
  w.background(kSkyBlue);
  // Kay & Kajiya's view and light, in the SPD's world coordinates.
  w.viewpoint({1.022846, -3.177154, -2.174512}, {-0.004103, -0.004103, 0.216539},
              {-0.816497, -0.816497, 0.816497}, 45.0, 1.0, 512, 512);
  w.light({2.0, -18.0, -5.0, 1.0});
  w.color({1.0, 0.2, 0.2}, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  tetrahedra(w, size, {0.0, 0.0, 0.0, 1.0});
}

}  // namespace lockstep::spd
