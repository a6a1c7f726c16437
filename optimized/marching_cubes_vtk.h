// lockstep optimized: the marching-cubes family's VTK peer row, Kitware's
// vtkFlyingEdges3D (optimized/marching_cubes_vtk.cpp; only built where CMake
// finds VTK: LOCKSTEP_HAVE_VTK; elsewhere available() is false and the row is
// not registered). No VTK header is included outside that one file.
#pragma once

#include <string>

#include "core/family.h"
#include "core/mesh.h"
#include "core/volume.h"

namespace lockstep::opt::vtk {

// Whether this binary has the row (VTK found at configure time).
bool available();
// "VTK 9.1.0, SMP backend TBB" ("" when not available).
std::string version();

// The isosurface at mc::settings(options.params).iso by vtkFlyingEdges3D, as an
// indexed mesh in our orientation (counter-clockwise seen from values >= iso).
// Threads: options.threads through vtkSMPTools (0: all cores).
// FrameStats::items = cubes. Throws std::logic_error when !available().
Mesh marching_cubes(const Volume& volume, const FrameOptions& options, FrameStats* stats);

}  // namespace lockstep::opt::vtk
