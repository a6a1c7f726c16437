// lockstep reference: marching cubes, the textbook method (core/marching_cubes.h
// holds the contract: numbering, case table, cut points, settings).
#pragma once

#include "core/family.h"
#include "core/mesh.h"
#include "core/volume.h"

namespace lockstep::ref {

// The isosurface at FrameOptions::params' iso value, cube by cube: a triangle
// soup (each triangle its own three vertices, as the method emits them).
// FrameStats::items = cubes visited. Single-threaded.
Mesh marching_cubes(const Volume& volume, const FrameOptions& options, FrameStats* stats);

}  // namespace lockstep::ref
