// lockstep props/marching_cubes: the accuracy oracle -- the two-sided
// Hausdorff distance between a mesh and an analytic surface (a sphere, a
// torus), for SphereConvergence and the grid-resolution study.
//
//   mesh -> surface   the largest distance from a point of the mesh (triangle
//                     interiors included: that is where the chordal error
//                     peaks) to the surface.
//                     Sphere |p| = R: exact per triangle. The distance of p is
//                     | |p| - R |; over a triangle |p| is largest at a vertex
//                     (a convex function) and smallest at the triangle's point
//                     nearest the centre (point-triangle distance, CGAL), so the
//                     largest distance is max(max |v| - R, R - min |p|).
//                     Torus: the distance | dist(p, core circle) - b | on a
//                     barycentric grid of 16 steps per triangle, then the best
//                     sample refined by pattern search.
//   surface -> mesh   the largest distance from a point of the surface to the
//                     mesh: points on the surface on a quasi-uniform grid (the
//                     sphere as a cube projected onto it, six faces; the torus
//                     by its two angles), each one's distance to the mesh from
//                     CGAL's AABB tree of the triangles (exact point-triangle
//                     distances), then the 64 largest refined by pattern search
//                     on the surface's parameters (step halved 20 times): the
//                     sampling alone would miss the peak by ~ c (spacing)^2.
#pragma once

#include "core/mesh.h"

namespace lockstep::props::marching_cubes {

struct Hausdorff {
  double mesh_to_surface = 0, surface_to_mesh = 0;
  double two_sided() const {
    return mesh_to_surface > surface_to_mesh ? mesh_to_surface : surface_to_mesh;
  }
};

// The sphere |p| = r centred at the origin; `spacing`: the surface samples'
// spacing before refinement (a fraction of the grid spacing h does; h / 2 in
// the tests).
Hausdorff sphere_hausdorff(const Mesh& mesh, double r, double spacing);
// The torus of core radius a (in the z = 0 plane, centred at the origin) and
// tube radius b (io/volume_io.h's torus field).
Hausdorff torus_hausdorff(const Mesh& mesh, double a, double b, double spacing);

}  // namespace lockstep::props::marching_cubes
