// lockstep props/marching_cubes: the case generators and fixed cases (see generators.h).
#include "props/marching_cubes/generators.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/marching_cubes.h"
#include "props/gen/numbers.h"

namespace lockstep::props::marching_cubes {

// Samples 0..8 (integers), iso k + 1/2; border: +1 all border samples 9 (above),
// -1 all 0 (below, iso >= 1/2), 0 anything.
rc::Gen<McCase> field(int border, bool ties) {
  return rc::gen::exec([border, ties] {
    McCase c;
    Volume& v = c.volume;
    v.nx = int(*gen::int_in(2, 9));
    v.ny = int(*gen::int_in(2, 9));
    v.nz = int(*gen::int_in(2, 9));
    if (border != 0) {
      v.nx = std::max(v.nx, 3);
      v.ny = std::max(v.ny, 3);
      v.nz = std::max(v.nz, 3);
    }
    // Spacings and origins of every scale: the same arithmetic must give the same bits.
    v.spacing = {std::ldexp(1.0 + double(*gen::int_in(0, 15)) / 16, int(*gen::int_in(-6, 6))),
                 std::ldexp(1.0 + double(*gen::int_in(0, 15)) / 16, int(*gen::int_in(-6, 6))),
                 std::ldexp(1.0 + double(*gen::int_in(0, 15)) / 16, int(*gen::int_in(-6, 6)))};
    v.origin = {double(*gen::int_in(-1000, 1000)) / 7, double(*gen::int_in(-1000, 1000)) / 7,
                double(*gen::int_in(-1000, 1000)) / 7};
    const int64_t kind = ties ? *gen::int_in(0, 3) : 3;
    c.iso = double(*gen::int_in(0, 7)) + (kind == 0 ? 1.0 : kind == 1 ? 0.1 : 0.5);
    // kind 1: an iso value no float equals, and samples at the floats around
    // it (the classification in float must match the reference's in double).
    const float near = float(c.iso);
    const float around[4] = {near, std::nextafter(near, -1e30f), std::nextafter(near, 1e30f), float(c.iso - 1)};
    v.data.resize(size_t(v.nx) * size_t(v.ny) * size_t(v.nz));
    for (int k = 0; k < v.nz; ++k)
      for (int j = 0; j < v.ny; ++j)
        for (int i = 0; i < v.nx; ++i) {
          const bool edge = i == 0 || j == 0 || k == 0 || i == v.nx - 1 || j == v.ny - 1 || k == v.nz - 1;
          v.at(i, j, k) = edge && border > 0 ? 9.0f
                          : edge && border < 0 ? -1.0f
                          : kind == 1          ? around[size_t(*gen::int_in(0, 3))]
                                               : float(*gen::int_in(0, 8));
        }
    v.source = "<generated>";
    return c;
  });
}

// Integer samples at an integer iso value that many of them equal (issue 30,
// section 4: CT data at an integer iso value): iso 2..6, the inner samples
// iso - 2 .. iso + 2 (a fifth equal to iso), or 0..8 in a quarter of the
// cases; the border 9 (above) or -1 (below), so the surface stays inside.
rc::Gen<McCase> ties_field(int border) {
  return rc::gen::exec([border] {
    McCase c;
    Volume& v = c.volume;
    v.nx = int(*gen::int_in(3, 9));
    v.ny = int(*gen::int_in(3, 9));
    v.nz = int(*gen::int_in(3, 9));
    v.spacing = {std::ldexp(1.0 + double(*gen::int_in(0, 15)) / 16, int(*gen::int_in(-6, 6))),
                 std::ldexp(1.0 + double(*gen::int_in(0, 15)) / 16, int(*gen::int_in(-6, 6))),
                 std::ldexp(1.0 + double(*gen::int_in(0, 15)) / 16, int(*gen::int_in(-6, 6)))};
    v.origin = {double(*gen::int_in(-1000, 1000)) / 7, double(*gen::int_in(-1000, 1000)) / 7,
                double(*gen::int_in(-1000, 1000)) / 7};
    const int iso = int(*gen::int_in(2, 6));
    const bool wide = *gen::int_in(0, 3) == 0;
    c.iso = iso;
    v.data.resize(size_t(v.nx) * size_t(v.ny) * size_t(v.nz));
    for (int k = 0; k < v.nz; ++k)
      for (int j = 0; j < v.ny; ++j)
        for (int i = 0; i < v.nx; ++i) {
          const bool edge = i == 0 || j == 0 || k == 0 || i == v.nx - 1 || j == v.ny - 1 || k == v.nz - 1;
          v.at(i, j, k) = edge ? (border > 0 ? 9.0f : -1.0f)
                          : wide ? float(*gen::int_in(0, 8))
                                 : float(iso + *gen::int_in(-2, 2));
        }
    v.source = "<generated>";
    return c;
  });
}

// One cube's configuration `bits` (bit v: corner v below) in a 4x4x4 grid whose
// other samples are above (or, complemented, below).
McCase single_cube(int bits, bool complement) {
  McCase c;
  Volume& v = c.volume;
  v.nx = v.ny = v.nz = 4;
  v.data.assign(64, complement ? 0.0f : 9.0f);
  for (int corner = 0; corner < 8; ++corner) {
    const bool below = ((bits >> corner) & 1) != complement;
    v.at(1 + mc::corner_x(corner), 1 + mc::corner_y(corner), 1 + mc::corner_z(corner)) = below ? 0.0f : 9.0f;
  }
  // Values other than 0 and 9 make the cut points fall off the edges' midpoints.
  for (int k = 1; k <= 2; ++k)
    for (int j = 1; j <= 2; ++j)
      for (int i = 1; i <= 2; ++i) v.at(i, j, k) += float((i * 3 + j * 5 + k * 7) % 4) * (v.at(i, j, k) > 4 ? -1 : 1);
  c.iso = 4.5;
  v.source = "single cube " + std::to_string(bits) + (complement ? " (complemented)" : "");
  return c;
}

// A hand-made field where many samples equal the iso value 2 (integers 0..4,
// the border 0): a plateau of 2s (every cut point of its surface on a sample
// before the tie rule), a diamond |i - 10| + |j - 6| + |k - 6| <= 2 of values
// 4 - that distance (its shell equal to 2), and a patch of 1, 2, 3 mixed by
// (7 i + 3 j + 5 k) mod 3.
McCase hand_made_ties() {
  McCase c;
  Volume& v = c.volume;
  v.nx = 14;
  v.ny = v.nz = 12;
  v.data.assign(size_t(v.nx) * size_t(v.ny) * size_t(v.nz), 0.0f);
  for (int k = 1; k + 1 < v.nz; ++k)
    for (int j = 1; j + 1 < v.ny; ++j)
      for (int i = 1; i + 1 < v.nx; ++i) {
        float f = 0;
        if (i <= 4) f = float((7 * i + 3 * j + 5 * k) % 3 + 1);
        else if (i <= 8) f = j >= 3 && j <= 8 && k >= 3 && k <= 8 ? 2.0f : 1.0f;
        else f = float(std::max(0, 4 - (std::abs(i - 10) + std::abs(j - 6) + std::abs(k - 6))));
        v.at(i, j, k) = f;
      }
  c.iso = 2;
  v.source = "hand-made ties field";
  return c;
}

}  // namespace lockstep::props::marching_cubes
