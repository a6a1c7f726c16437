// lockstep core: triangle meshes -- what isosurface extraction produces
// (marching cubes), written and read as PLY and OBJ (core/mesh_io.h).
//
// An indexed mesh: vertices shared between triangles where the producer
// shares them (the optimized marching cubes computes each cut edge once), or a
// soup (the textbook method emits each cube's triangles on their own);
// weld() turns either into the other's form for comparison. Triangles are
// oriented: counter-clockwise seen from the side the normal points to
// (marching cubes: from the side of values below the iso value).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"

namespace lockstep {

struct Mesh {
  std::vector<Vec3f> vertices;  // float, as every production mesher stores them
  std::vector<std::array<uint32_t, 3>> triangles;

  size_t size() const { return triangles.size(); }
};

}  // namespace lockstep
