// lockstep props/ray_cast: closed meshes for the watertightness cases (deterministic).
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"

namespace lockstep::props::ray_cast {

// Closed triangle/quad meshes with vertices on a dyadic grid (shared vertices are
// the same doubles). faces index into verts, counter-clockwise seen from outside.
struct Mesh {
  std::vector<Vec3> verts;
  std::vector<std::vector<uint32_t>> faces;
};
Mesh octahedron();
// x rounded to the nearest multiple of 2^grid_exp.
double round_to(double x, int grid_exp);
Vec3 round_to(const Vec3& v, int grid_exp);
Mesh icosahedron(int grid_bits);          // vertices rounded to 2^-grid_bits
Mesh icosphere(int level, int grid_bits);  // subdivided icosahedron, on the unit sphere
Mesh tessellated_cube(int n, bool quads);  // n x n cells per face, as quads or triangle pairs

}  // namespace lockstep::props::ray_cast
