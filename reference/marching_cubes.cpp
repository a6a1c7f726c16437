// lockstep reference: marching cubes as the lecture notes give it.
//
// Lorensen and Cline, "Marching Cubes: A High Resolution 3D Surface
// Construction Algorithm", SIGGRAPH 1987; Foley, van Dam, Feiner, Hughes, 2nd
// ed., 20.8. For every cube of eight neighbouring samples:
//   1. classify its 8 corners: below the iso value or not (8 bits); a sample
//      equal to iso is not below (f >= iso counts as inside the at-or-above
//      side), the same in every implementation;
//   2. look the 8 bits up in the 256-case table (core/marching_cubes.h): which
//      edges the surface cuts and how their cut points form triangles;
//   3. place the cut point on each cut edge by linear interpolation, but never
//      on a sample: where the interpolated point is not strictly inside the
//      edge (its sample equals iso, as integer CT data at an integer iso value
//      give by the thousand), it goes 2^-10 of the edge from that sample
//      (core/marching_cubes.h: cut_point, kTieOffset). On the sample, the cut
//      points of up to six edges would coincide: zero-area triangles, and
//      after welding by position edges of four triangles and pinched
//      vertices. Strictly inside, welding by position is welding by edge, and
//      the surface stays a closed oriented 2-manifold with no zero-area
//      triangle (away from the volume's border);
//   4. emit the case's triangles.
// Each cube is handled on its own: a cut point shared by up to four cubes is
// computed (identically) by each, and each triangle has its own vertices.
#include "reference/marching_cubes.h"

#include "core/marching_cubes.h"

namespace lockstep::ref {

Mesh marching_cubes(const Volume& v, const FrameOptions& options, FrameStats* stats) {
  const mc::Settings s = mc::settings(options.params, v.source);
  const std::array<mc::Case, 256>& table = mc::case_table();
  Mesh mesh;
  for (int k = 0; k + 1 < v.nz; ++k) {
    for (int j = 0; j + 1 < v.ny; ++j)
      for (int i = 0; i + 1 < v.nx; ++i) {
        // 1. Classify the corners.
        double value[8];
        Vec3 position[8];
        int bits = 0;
        for (int c = 0; c < 8; ++c) {
          const int ci = i + mc::corner_x(c), cj = j + mc::corner_y(c), ck = k + mc::corner_z(c);
          value[c] = v.at(ci, cj, ck);
          position[c] = v.position(ci, cj, ck);
          if (value[c] < s.iso) bits |= 1 << c;
        }
        // 2. The case.
        const mc::Case& cube = table[size_t(bits)];
        // 3 and 4. Cut points and triangles.
        for (int t = 0; t < cube.triangles; ++t) {
          const uint32_t first = uint32_t(mesh.vertices.size());
          for (int e : cube.tri[size_t(t)]) {
            const int a = mc::kEdgeCorner[e][0], b = mc::kEdgeCorner[e][1];
            mesh.vertices.push_back(mc::cut_point(position[a], position[b], value[a], value[b], s.iso));
          }
          mesh.triangles.push_back({first, first + 1, first + 2});
        }
      }
    if (options.progress) options.progress(double(k + 1) / double(v.nz - 1));
  }
  if (stats) {
    stats->items = v.cells();
    if (mesh.triangles.empty())
      if (std::string note = mc::empty_note(v.data, s.iso); !note.empty()) stats->notes.push_back(std::move(note));
  }
  return mesh;
}

}  // namespace lockstep::ref
