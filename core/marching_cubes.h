// lockstep core: marching cubes -- the contract every implementation shares:
// the cube's corner and edge numbering, the 256-case table, the vertex on a
// cut edge, and the settings.
//
// Marching cubes (Lorensen and Cline, "Marching Cubes: A High Resolution 3D
// Surface Construction Algorithm", SIGGRAPH 1987; Foley, van Dam et al. 2nd
// ed. 20.8; Schroeder, Martin, Lorensen, "The Visualization Toolkit", 6.2):
// the isosurface f = iso of a sampled volume is approximated cube by cube.
// A cube's 8 corners are classified below (f < iso) or not; the 8 bits index
// a table of 256 cases that says which of the 12 edges the surface cuts and
// how the cut points form triangles; each cut point is placed on its edge by
// linear interpolation of f.
//
// Numbering (Lorensen and Cline's; Paul Bourke's table uses the same):
//   corner v = (v&1 ^ v>>1&1, v>>1&1, v>>2&1):  0 (0,0,0) 1 (1,0,0) 2 (1,1,0) 3 (0,1,0)
//                                               4 (0,0,1) 5 (1,0,1) 6 (1,1,1) 7 (0,1,1)
//   edges 0-3 the bottom face's (0-1, 1-2, 2-3, 3-0), 4-7 the top face's
//   (4-5, 5-6, 6-7, 7-4), 8-11 the vertical ones (0-4, 1-5, 2-6, 3-7).
//
// The table is not typed in: case_table() derives it from first principles,
// which is how the textbook explains it. On each face of the cube the cut
// edges pair up into segments that separate its below corners from the
// others; the segments close into loops around the cube, and each loop is
// one polygon, cut into triangles (a fan, unless a fan triangle would lie in a
// face of the cube, where the neighbouring cube could make the same one and
// the surface would pinch: then another diagonal). A face with two below corners on
// one diagonal and two others on the other is ambiguous (the cases that left
// holes in the 1987 table): here the below corners are always kept apart
// (each cut off by its own segment). Both cubes that share a face see the same
// four signs and so make the same choice: the surface has no cracks, and
// away from the volume's border it is a closed, consistently oriented
// 2-manifold. It is one of the topologies the trilinear interpolant allows,
// not always the interpolant's own (that needs the asymptotic decider on faces
// and the MC33 interior tests). tests/topology_skimage.py measures how often,
// against scikit-image's Lewiner (MC33) marching cubes, by the components'
// Euler characteristics (quick run, seed 20): never without an ambiguity (0
// unexplained); analytic fields (sphere, torus, gyroid, Marschner-Lobb, 12 to
// 64 samples a side) agree in every case; single cubes of all 256
// configurations differ in 17.7% of cases (16.6% where the decider joins the
// below corners of a face, 1.1% by an interior tunnel), two cubes sharing an
// ambiguous face in 66%, noise fields in 53% (smoothed) to 100% (uniform, 8^3
// and up). skimage's Lorensen table on -f (the same rule) agrees everywhere.
//
// Orientation: triangles are counter-clockwise seen from the side of values at
// or above iso, so their normals point the way f increases (the gradient).
//
// Samples equal to iso (integer CT data at an integer iso value; issue 30,
// section 4). Two rules keep the surface a closed oriented 2-manifold after
// welding by position, with no zero-area triangle, for every iso value:
//   1. classification: a sample equal to iso is not below (it counts as at or
//      above, f >= iso), in every implementation alike; so the table sees the
//      same 8 bits a perturbed field f + epsilon would give (simulation of
//      simplicity: the tie is broken one way, consistently);
//   2. placement: a cut point never lies on a sample. Linear interpolation
//      would put it on the sample that equals iso (t = 0 or 1), so up to six
//      cut edges of up to eight cubes would share one position: triangles with
//      two corners there have zero area, and once equal positions are welded
//      (as MeshLab and slicers do) edges may carry four triangles and vertices
//      pinch -- a mesh manifold only by its own vertex indices. Where the
//      interpolated point (in float) is not strictly between its edge's two
//      samples (the sample equals iso, or is so near it that the point rounds
//      onto it), it is placed kTieOffset of the edge from that sample instead
//      (where the coordinates are too coarse even for that, one float step).
//      The limit of the perturbation (epsilon -> 0) would be the sample
//      itself; a finite offset keeps the cut points of different edges
//      apart.
// With every cut point strictly inside its edge, points of different edges
// never share a position (two of their three coordinates are grid
// coordinates, the third strictly between two), so welding by position is
// welding by edge and the manifold the table guarantees survives it; and
// three points strictly inside three edges that do not lie on one face of the
// cube are never on one line (the table makes no triangle in a face), so no
// triangle has zero area. Elsewhere the cut point is the interpolated one, bit
// for bit: outputs for iso values that no sample equals (or comes within a
// float rounding of) are unchanged.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/family.h"
#include "core/math.h"
#include "core/volume.h"

namespace lockstep::mc {

// Corner v's offset in the cube, per axis.
constexpr int corner_x(int v) { return (v & 1) ^ ((v >> 1) & 1); }
constexpr int corner_y(int v) { return (v >> 1) & 1; }
constexpr int corner_z(int v) { return (v >> 2) & 1; }

// Edge e joins corners kEdgeCorner[e][0] and [1]; the first is always the one
// nearer the origin, so two cubes sharing an edge interpolate it alike.
inline constexpr int kEdgeCorner[12][2] = {{0, 1}, {1, 2}, {3, 2}, {0, 3}, {4, 5}, {5, 6},
                                           {7, 6}, {4, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
// The axis edge e runs along (0 x, 1 y, 2 z).
inline constexpr int kEdgeAxis[12] = {0, 1, 0, 1, 0, 1, 0, 1, 2, 2, 2, 2};

// One case: up to 5 triangles (at most 12 cut edges, loops of at least 3),
// as edge numbers; cut: bit e set when edge e is cut.
struct Case {
  uint8_t triangles = 0;
  std::array<std::array<uint8_t, 3>, 5> tri{};
  uint16_t cut = 0;
};

// The 256 cases, indexed by the bits of the below corners (bit v: corner v < iso).
const std::array<Case, 256>& case_table();

// How far from a sample a cut point is kept, as a fraction of its edge (rule
// 2 above): 2^-10, under a thousandth of a sample spacing (marching cubes' own
// error on a sphere of radius R is 0.36 h^2 / R), and still dozens of float
// steps at the coordinates volumes have (512 samples of spacing 1: 2^-10
// against a float step of 2^-15).
inline constexpr double kTieOffset = 0x1p-10;

// The point a fraction t of the way from a to b, in double, rounded to float
// once.
inline Vec3f edge_point(const Vec3& a, const Vec3& b, double t) {
  return Vec3f(float(a.x + t * (b.x - a.x)), float(a.y + t * (b.y - a.y)), float(a.z + t * (b.z - a.z)));
}

// The linear interpolation alone: where f = iso on the edge from sample a
// (value fa) to sample b (value fb), fa and fb on either side of iso, from the
// end nearer the origin. May lie on a sample (rule 2 above); cut_point() is
// what implementations emit.
inline Vec3f interpolated_point(const Vec3& a, const Vec3& b, double fa, double fb, double iso) {
  return edge_point(a, b, (iso - fa) / (fb - fa));
}

// p strictly between the float positions pa and pb on every axis where they
// differ (an edge runs along one axis).
inline bool strictly_inside(const Vec3f& p, const Vec3f& pa, const Vec3f& pb) {
  auto in = [](float x, float u, float w) { return u == w || (u < w ? u < x && x < w : w < x && x < u); };
  return in(p.x, pa.x, pb.x) && in(p.y, pa.y, pb.y) && in(p.z, pa.z, pb.z);
}

// The cut point every implementation emits (the same arithmetic in each): the
// interpolated point where it lies strictly inside the edge, else kTieOffset
// of the edge from the sample it fell on (rule 2 above).
inline Vec3f cut_point(const Vec3& a, const Vec3& b, double fa, double fb, double iso) {
  const double t = (iso - fa) / (fb - fa);
  const Vec3f p = edge_point(a, b, t);
  const Vec3f pa(float(a.x), float(a.y), float(a.z)), pb(float(b.x), float(b.y), float(b.z));
  if (strictly_inside(p, pa, pb)) return p;
  // On (or, by rounding, past) sample a when t is small, b when it is near 1.
  const bool at_a = t < 0.5;
  const Vec3f q = edge_point(a, b, at_a ? kTieOffset : 1 - kTieOffset);
  if (strictly_inside(q, pa, pb)) return q;
  // Coordinates so large against the spacing that the offset rounds away: the
  // next float from the sample towards the other end.
  const Vec3f &from = at_a ? pa : pb, &to = at_a ? pb : pa;
  return Vec3f(std::nextafter(from.x, to.x), std::nextafter(from.y, to.y), std::nextafter(from.z, to.z));
}

// When a run found no triangle because iso lies outside the volume's values
// (not an error: a user asked for a surface that is not there), the note that
// says so for FrameStats::notes; "" when iso is within them.
std::string empty_note(const Samples& samples, double iso);

// ---------------------------------------------------------------- settings

// The iso value, from the family's settings (iso=VALUE; required).
struct Settings {
  double iso = 0;
};
// Throws InputError(source, 0, ...) naming a bad or missing setting.
Settings settings(const Params& p, const std::string& source);
// For --help and the manifest.
std::vector<ParamSpec> params();

}  // namespace lockstep::mc
