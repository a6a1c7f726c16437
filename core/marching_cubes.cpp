// lockstep core: marching cubes' case table and settings (see
// core/marching_cubes.h for the method and the conventions).
#include "core/marching_cubes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <vector>

#include "core/error.h"

namespace lockstep::mc {

namespace {

Vec3 corner(int v) { return {double(corner_x(v)), double(corner_y(v)), double(corner_z(v))}; }

// The midpoint of edge e: where the table's geometry puts its cut point (the
// table depends only on which corners are below, not on the values).
Vec3 midpoint(int e) { return 0.5 * (corner(kEdgeCorner[e][0]) + corner(kEdgeCorner[e][1])); }

bool on_face(int v, int axis, int side) {
  const int c[3] = {corner_x(v), corner_y(v), corner_z(v)};
  return c[axis] == side;
}

// The two faces edge e lies on, as bits 2 axis + side.
int faces_of(int e) {
  int m = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      if (on_face(kEdgeCorner[e][0], axis, side) && on_face(kEdgeCorner[e][1], axis, side)) m |= 1 << (2 * axis + side);
  return m;
}

// A triangulation of the loop's polygon loop[lo..hi] (closed by hi -> lo) in
// which no triangle has its three corners on one face of the cube: such a
// triangle lies in the face, and the cube across it may make the same one
// (the pair would share edges with four triangles). Tries the diagonals in a
// fixed order (a fan from loop[lo] first); false when none exists.
bool triangulate(const int* loop, int lo, int hi, std::vector<std::array<int, 3>>& out) {
  if (hi - lo < 2) return true;
  for (int k = hi - 1; k > lo; --k) {
    if ((faces_of(loop[lo]) & faces_of(loop[k]) & faces_of(loop[hi])) != 0) continue;
    const size_t mark = out.size();
    out.push_back({loop[lo], loop[k], loop[hi]});
    if (triangulate(loop, lo, k, out) && triangulate(loop, k, hi, out)) return true;
    out.resize(mark);
  }
  return false;
}

// One case of the table, derived (see the header):
//   1. on each face, pair the cut edges into segments that separate the face's
//      below corners from the others (an ambiguous face: each below corner cut
//      off by its own segment);
//   2. direct each segment so that, seen from outside the cube, the below
//      corner it cuts off lies on its left;
//   3. every cut edge then starts one segment and ends another: follow them
//      into loops;
//   4. cut each loop into triangles (a fan where it can: no triangle may lie in
//      a face of the cube, see triangulate()), reversed: step 2 makes loops
//      run clockwise seen from the side at or above iso, and triangles must be
//      counter-clockwise from there.
Case make_case(int bits) {
  auto below = [bits](int v) { return ((bits >> v) & 1) != 0; };
  Case c;
  for (int e = 0; e < 12; ++e)
    if (below(kEdgeCorner[e][0]) != below(kEdgeCorner[e][1])) c.cut |= uint16_t(1u << e);
  if (c.cut == 0) return c;

  int next[12];
  for (int& n : next) n = -1;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      Vec3 n{0, 0, 0};
      (axis == 0 ? n.x : axis == 1 ? n.y : n.z) = side ? 1.0 : -1.0;  // outward normal
      // The face's cut edges, and for each the face's below corner at one end of it.
      int edges[4], ends[4], k = 0;
      for (int e = 0; e < 12; ++e) {
        const int a = kEdgeCorner[e][0], b = kEdgeCorner[e][1];
        if (!on_face(a, axis, side) || !on_face(b, axis, side) || !((c.cut >> e) & 1)) continue;
        edges[k] = e;
        ends[k] = below(a) ? a : b;
        ++k;
      }
      // Step 1: segments. Two cut edges: one segment. Four (ambiguous): the two
      // cut edges at each below corner make its segment.
      std::pair<int, int> segs[2];
      int nseg = 0;
      if (k == 2) {
        segs[nseg++] = {0, 1};
      } else if (k == 4) {
        for (int i = 0; i < 4; ++i)
          for (int j = i + 1; j < 4; ++j)
            if (ends[i] == ends[j]) segs[nseg++] = {i, j};
        if (nseg != 2) throw std::logic_error("marching cubes table: an ambiguous face without two below corners");
      } else if (k != 0) {
        throw std::logic_error("marching cubes table: a face with an odd number of cut edges");
      }
      // Step 2: direction.
      for (int s = 0; s < nseg; ++s) {
        int p = edges[segs[s].first], q = edges[segs[s].second];
        const Vec3 left = cross(n, midpoint(q) - midpoint(p));
        if (dot(corner(ends[segs[s].first]) - midpoint(p), left) < 0) std::swap(p, q);
        if (next[p] != -1) throw std::logic_error("marching cubes table: a cut edge starts two segments");
        next[p] = q;
      }
    }

  // Steps 3 and 4: loops, triangles.
  uint16_t done = 0;
  for (int start = 0; start < 12; ++start) {
    if (!((c.cut >> start) & 1) || ((done >> start) & 1)) continue;
    int loop[12], len = 0;
    for (int e = start; !((done >> e) & 1); e = next[e]) {
      if (e < 0) throw std::logic_error("marching cubes table: an open loop");
      done |= uint16_t(1u << e);
      loop[len++] = e;
    }
    std::vector<std::array<int, 3>> tris;
    if (!triangulate(loop, 0, len - 1, tris))
      throw std::logic_error("marching cubes table: a loop with no triangulation off the faces");
    for (const auto& t : tris) {
      if (c.triangles == c.tri.size()) throw std::logic_error("marching cubes table: too many triangles");
      // Reversed: the loop runs clockwise seen from above iso.
      c.tri[c.triangles++] = {uint8_t(t[0]), uint8_t(t[2]), uint8_t(t[1])};
    }
  }
  return c;
}

}  // namespace

const std::array<Case, 256>& case_table() {
  static const std::array<Case, 256> table = [] {
    std::array<Case, 256> t;
    for (int bits = 0; bits < 256; ++bits) t[size_t(bits)] = make_case(bits);
    return t;
  }();
  return table;
}

std::string empty_note(const Samples& samples, double iso) {
  if (samples.empty()) return "the volume has no samples: the mesh is empty";
  const auto [lo, hi] = std::minmax_element(samples.begin(), samples.end());
  if (iso >= double(*lo) && iso <= double(*hi)) return {};
  char buf[200];
  std::snprintf(buf, sizeof buf, "iso %g is outside the volume's values [%g, %g]: the mesh is empty", iso,
                double(*lo), double(*hi));
  return buf;
}

// ---------------------------------------------------------------- settings

std::vector<ParamSpec> params() {
  return {{"iso", "a finite number", "", "the iso value: the surface where the volume's value equals it (required)"}};
}

Settings settings(const Params& p, const std::string& source) {
  Settings s;
  for (const auto& [name, value] : p.items)
    if (name != "iso") throw InputError(source, 0, "marching cubes has no setting '" + name + "' (it takes iso=VALUE)");
  const std::string v = p.get("iso");
  if (v.empty()) throw InputError(source, 0, "marching cubes needs iso=VALUE (the iso value)");
  char* end = nullptr;
  s.iso = std::strtod(v.c_str(), &end);
  if (end != v.c_str() + v.size() || !std::isfinite(s.iso))
    throw InputError(source, 0, "iso must be a finite number, got '" + v + "'");
  return s;
}

}  // namespace lockstep::mc
