// lockstep isosurface: a volume, one marching-cubes implementation, one mesh --
// `lockstep render` with the family fixed to marching_cubes (registry/marching_cubes_row.h).
#include <cstdio>

#include "app/cli.h"

namespace lockstep::cli {

namespace {

void print_help() {
  std::printf(
      "usage: lockstep isosurface VOLUME --iso C [--impl reference|simd|vtk] [--threads N] -o MESH\n"
      "\n"
      "Extracts the isosurface where VOLUME's value equals C by marching cubes and writes\n"
      "it as a triangle mesh; the format follows MESH's extension (.ply binary, .obj, .off;\n"
      "MeshLab, Blender and ParaView open them).\n"
      "\n"
      "  VOLUME          a NRRD volume (.nrrd, or a .nhdr header with its data file) or an\n"
      "                  analytic field (.field: sphere, torus, gyroid, marschner_lobb)\n"
      "  --iso C         the iso value (required); outside the data's range the mesh is empty\n"
      "  --impl NAME     reference (the textbook method, one cube at a time, a triangle soup)\n"
      "                  or simd (each cut edge once, slabs on all cores; default), or vtk\n"
      "                  (VTK's vtkFlyingEdges3D, a production peer; where VTK was found at build)\n"
      "  --threads N     worker threads, N >= 1 (default: all cores)\n"
      "  --repeat N      run N times in this process (default 1): the summary gives the last run\n"
      "                  (warm) and the first\n"
      "  -o, --output F  the mesh to write (required)\n"
      "\n"
      "Prints one summary line on stderr: implementation, triangles and vertices, seconds and\n"
      "cubes per second, page faults and system time (the extraction's and the call's so far).\n"
      "Exit codes: 0 ok, 2 bad usage or bad input (nothing written), 3 internal error.\n");
}

}  // namespace

int isosurface_main(Args args) { return render_subcommand("lockstep isosurface", "isosurface", args, print_help); }

}  // namespace lockstep::cli
