// lockstep kinds: the mesh output kind (core/output.h) -- triangle meshes as
// marching cubes produces them.
//
//   files       PLY (binary) and OBJ through CGAL (io/mesh_io.h); goldens PLY
//   compare     both meshes welded; every vertex of each to the nearest vertex
//               of the other (marching cubes puts every vertex on a grid edge,
//               so two meshes of one surface share their vertices up to
//               interpolation): a vertex fails over Tolerance::abs (world
//               units); the score is 20 log10(bounding-box diagonal / worst)
//   diagnostics the mesh drawn by a rasterizer row the registry names (the
//               z-buffer family's simd row: a PNG, Phong
//               from two lights), and the second mesh drawn with each triangle
//               coloured by its vertices' distance to the first (blue 0, red at
//               Tolerance::abs); pictures as the image kind's (PNG), another
//               renderer's picture (a case's beside=) scaled as there
// The kind sits below the implementations (kinds/ includes no reference/ or
// optimized/ file), so the rasterizer comes in as a template argument:
// registry/marching_cubes_row.cpp asks for mesh_kind<its drawer>().
#pragma once

#include <string>

#include "core/family.h"
#include "core/image.h"
#include "core/mesh.h"
#include "core/output.h"
#include "core/scene.h"

namespace lockstep {

// Draws a scene into an image (a rasterizer row: the report's mesh pictures).
using MeshDraw = Image (*)(const Scene&, const FrameOptions&);

namespace mesh_kind_detail {
OutputKind base();  // every function but the two pictures
std::string save_view(const Output& o, const std::string& stem, MeshDraw draw);
std::string save_difference(const Output& a, const Output& b, const Tolerance& tol, const std::string& stem,
                            MeshDraw draw);
}  // namespace mesh_kind_detail

// The mesh kind whose report pictures Draw renders; one per drawer, made on first use.
template <MeshDraw Draw>
const OutputKind& mesh_kind() {
  static const OutputKind k = [] {
    OutputKind kind = mesh_kind_detail::base();
    kind.save_view = [](const Output& o, const std::string& stem) {
      return mesh_kind_detail::save_view(o, stem, Draw);
    };
    kind.save_difference = [](const Output& a, const Output& b, const Tolerance& tol, const std::string& stem) {
      return mesh_kind_detail::save_difference(a, b, tol, stem, Draw);
    };
    return kind;
  }();
  return k;
}

// The distance from each vertex of b to the nearest vertex of a (both as
// given; weld first to compare soups with indexed meshes).
std::vector<double> nearest_vertex_distance(const Mesh& a, const Mesh& b);

}  // namespace lockstep
