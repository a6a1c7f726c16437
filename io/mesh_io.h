// lockstep io: triangle meshes in files -- PLY (binary or ASCII) and OBJ,
// through CGAL's polygon-soup I/O (CGAL::IO::read_polygon_soup /
// write_polygon_soup; the one place outside props/ that includes CGAL), so
// that what we write opens in MeshLab, Blender or ParaView and what they write
// reads here. Binary PLY, the CLI's format, is written directly (the same
// bytes CGAL writes, a tenth of the time: no copy of the mesh into CGAL's
// points and polygons, no stream call per number; issue #35). Writing is
// atomic (a temporary file renamed into place).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/mesh.h"

namespace lockstep {

// The format follows the extension: .ply (binary little-endian; ascii = true
// for ASCII), .obj, .off. Throws InputError when path cannot be written, and
// leaves nothing behind then.
void write_mesh(const Mesh& mesh, const std::string& path, bool ascii = false);
// The same file, every format through CGAL's write_polygon_soup: what the
// direct binary PLY writer is tested against, byte for byte.
void write_mesh_through_cgal(const Mesh& mesh, const std::string& path, bool ascii = false);
// Throws InputError (naming the file) when it is missing, unreadable, not a
// mesh of triangles, or has a non-finite coordinate or an index out of range.
Mesh read_mesh(const std::string& path);
// Fails (InputError) before any work when path cannot take a mesh: missing
// folder, no or unknown extension.
void check_mesh_path(const std::string& path);

// Polygons of 3 or 4 corners with a colour value per vertex and per face (the
// radiosity family's patches), for viewers: MeshLab, Blender and ParaView
// show the uchar red green blue of vertices and faces. Binary little-endian
// PLY: vertex float x y z, uchar red green blue, float <name>_r _g _b; face
// list uchar int vertex_indices, uchar red green blue, float <name>_r _g _b,
// int group. The uchar colour is the value clamped to [0, 1] times 255,
// rounded (as the CLI's PNG); the floats keep it unclamped.
struct ColouredPolygons {
  std::string value_name = "value";  // "radiosity"
  std::vector<Vec3f> vertices;
  std::vector<Vec3f> vertex_values;
  std::vector<std::array<uint32_t, 4>> faces;  // corners; faces[k][3] unused when corners[k] == 3
  std::vector<uint8_t> corners;               // 3 or 4 per face
  std::vector<Vec3f> face_values;
  std::vector<int32_t> face_groups;           // e.g. the scene polygon a patch was cut from
};
// Only .ply; throws InputError naming path when it cannot be written (nothing left behind).
void write_coloured_polygons(const ColouredPolygons& polygons, const std::string& path);
// Fails (InputError) before any work when path cannot take them: missing folder, not .ply.
void check_coloured_polygons_path(const std::string& path);

}  // namespace lockstep
