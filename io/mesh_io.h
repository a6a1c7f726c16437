// lockstep io: triangle meshes in files -- PLY (binary or ASCII) and OBJ,
// through CGAL's polygon-soup I/O (CGAL::IO::read_polygon_soup /
// write_polygon_soup; the one place outside props/ that includes CGAL), so
// that what we write opens in MeshLab, Blender or ParaView and what they write
// reads here. Binary PLY, the CLI's format, is written directly (the same
// bytes CGAL writes, a tenth of the time: no copy of the mesh into CGAL's
// points and polygons, no stream call per number; issue #35). Writing is
// atomic (a temporary file renamed into place).
#pragma once

#include <string>

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

}  // namespace lockstep
