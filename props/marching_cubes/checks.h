// lockstep props/marching_cubes: the checks (one Outcome per case: its mesh)
// and the fixed tests' bodies (GoogleTest assertions); properties.cpp's header
// says what each checks.
#pragma once

#include "core/family.h"
#include "core/mesh.h"
#include "core/volume.h"
#include "props/marching_cubes/case.h"
#include "props/verdict.h"

namespace lockstep::props::marching_cubes {

// PeerAgrees: the largest vertex distance between a peer's welded mesh and the
// reference's, over the largest |coordinate| of the volume. vtk measured
// 1.24e-7 (3000 volumes of `field`, and 3 x 2000 more with random seeds) and
// 1.38e-7 (`field_ties`, 3000 + 3 x 2000): a float rounding of a coordinate
// (2^-23 = 1.19e-7) in 3D. Bound: 2.5e-7, margin 1.8.
inline constexpr double kPeerVertexBound = 2.5e-7;

// Agreement: the welded meshes equal, bit for bit.
Verdict agreement(const FamilyImpl& ref, const FamilyImpl& impl, const McCase& c);
// A peer's surface against the reference's (PeerAgrees; judge_topology false:
// PeerVertices, the vertices only, with the tie rule undone in the reference).
Verdict peer_agrees(const FamilyImpl& ref, const FamilyImpl& impl, const McCase& c,
                    bool judge_topology);
// Closed: a closed oriented 2-manifold (spheres: every component a sphere).
// border > 0: the inside is below (the volume must come out positive); < 0 the reverse.
Verdict closed(const FamilyImpl& impl, const McCase& c, int border, bool spheres);
// ClosedAtTies: the implementation's mesh as produced has no zero-area
// triangle, and welded by position it is a closed oriented 2-manifold
// enclosing volume of the right sign (closed()); the reference's figures on
// the same case are printed beside its own.
Verdict closed_at_ties(const FamilyImpl& ref, const FamilyImpl& impl, const McCase& c, int border);
// The mesh with the tie rule undone (core/marching_cubes.h, rule 2): every
// cut point the rule moved off a sample put back where the interpolation
// alone puts it (on the sample). What VTK computes, and the mutant
// ties_on_samples.
Mesh ties_on_samples(Mesh m, const Volume& v, double iso);

// The fixed tests.
// SingleCubes: all 256 single-cube configurations (and complements) closed, components spheres.
void single_cubes(const FamilyImpl& impl);
// Two-sided Hausdorff distance to the sphere |p| = kR (oracle.h), against h:
// c = distance R / h^2 over four halvings of h (h = 2/8 ... 2/128), each
// within 10% of the five's mean.
void sphere_convergence(const FamilyImpl& impl);
// TiesHandMade: on hand_made_ties(), our implementations' meshes have no
// zero-area triangle and weld into a closed oriented 2-manifold; the same
// meshes with the tie rule undone (on the samples, what the interpolation
// alone gives) must not (the field exercises the rule). A peer's figures are
// printed, not judged (VTK puts cut points on samples).
void ties_hand_made(const FamilyImpl& ref, const FamilyImpl& impl);

}  // namespace lockstep::props::marching_cubes
