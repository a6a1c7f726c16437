// lockstep pairs: the mesh output kind (core/output.h) -- triangle meshes as
// marching cubes produces them.
//
//   files       PLY (binary) and OBJ through CGAL (core/mesh_io.h); goldens PLY
//   compare     both meshes welded; every vertex of each to the nearest vertex
//               of the other (marching cubes puts every vertex on a grid edge,
//               so two meshes of one surface share their vertices up to
//               interpolation): a vertex fails over Tolerance::abs (world
//               units); the score is 20 log10(bounding-box diagonal / worst)
//   diagnostics the mesh drawn by the z-buffer family's simd row (a PNG, Phong
//               from two lights), and the second mesh drawn with each triangle
//               coloured by its vertices' distance to the first (blue 0, red at
//               Tolerance::abs)
// It lives in pairs/ because its pictures are drawn by a rasterizer row.
#pragma once

#include "core/mesh.h"
#include "core/output.h"

namespace lockstep {

const OutputKind& mesh_kind();

// The distance from each vertex of b to the nearest vertex of a (both as
// given; weld first to compare soups with indexed meshes).
std::vector<double> nearest_vertex_distance(const Mesh& a, const Mesh& b);

}  // namespace lockstep
