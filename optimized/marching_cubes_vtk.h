// lockstep optimized: the marching-cubes family's VTK peer row, Kitware's
// vtkFlyingEdges3D (optimized/marching_cubes_vtk.cpp; only built where CMake
// finds VTK: LOCKSTEP_HAVE_VTK; elsewhere available() is false and the row is
// not registered). No VTK header is included outside the module's one file:
// the VTK calls are in optimized/marching_cubes_vtk_module.cpp, built as
// lockstep_peer_vtk.so and opened when the row runs (optimized/peer_module.h);
// optimized/marching_cubes_vtk.cpp is the host side, linked into the binary.
#pragma once

#include <string>

#include "core/family.h"
#include "core/mesh.h"
#include "core/volume.h"

namespace lockstep::opt::vtk {

// Whether this binary has the row (VTK found at configure time, and its module beside the binary).
bool available();
// "VTK 9.1.0, SMP backend TBB" ("" when not available), as recorded beside the module.
std::string version();

// The isosurface at mc::settings(options.params).iso by vtkFlyingEdges3D, as an
// indexed mesh in our orientation (counter-clockwise seen from values >= iso).
// Threads: options.threads through vtkSMPTools (0: all cores).
// FrameStats::items = cubes. Throws std::logic_error when !available().
Mesh marching_cubes(const Volume& volume, const FrameOptions& options, FrameStats* stats);

// The module's table (lockstep_peer_api() in lockstep_peer_vtk.so); abi must match kAbi.
struct Request {
  const float* samples = nullptr;  // nx ny nz, x fastest (Volume::data)
  int nx = 0, ny = 0, nz = 0;
  Vec3 spacing, origin;
  double iso = 0;
  int threads = 0;
};
struct ModuleApi {
  int abi;
  // vtkFlyingEdges3D's surface into out (vertices, triangles in our orientation).
  void (*marching_cubes)(const Request& request, Mesh& out);
};
inline constexpr int kAbi = 1;

}  // namespace lockstep::opt::vtk
