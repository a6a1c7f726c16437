// lockstep core: triangle meshes -- what isosurface extraction produces
// (marching cubes), written and read as PLY and OBJ (io/mesh_io.h).
//
// An indexed mesh: vertices shared between triangles where the producer
// shares them (the optimized marching cubes computes each cut edge once), or a
// soup (the textbook method emits each cube's triangles on their own);
// weld() turns either into the other's form for comparison. Triangles are
// oriented: counter-clockwise seen from the side the normal points to
// (marching cubes: from the side of values below the iso value).
#pragma once

#include <array>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "core/large_buffer.h"
#include "core/math.h"

namespace lockstep {

// Union-find over n items (path halving): the connected components of
// vertices (weld's topology) and of triangles (shadow volumes' occluders).
struct UnionFind {
  std::vector<uint32_t> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(uint32_t a, uint32_t b) { parent[find(a)] = find(b); }
};

struct Mesh {
  // Large buffers: on huge pages where the kernel allows (core/large_buffer.h).
  // resize leaves new entries unwritten (the meshers write every one).
  std::vector<Vec3f, NoInitAllocator<Vec3f>> vertices;  // float, as every production mesher stores them
  std::vector<std::array<uint32_t, 3>, NoInitAllocator<std::array<uint32_t, 3>>> triangles;

  size_t size() const { return triangles.size(); }
};

// The mesh with vertices of equal position merged (bit-equal coordinates; -0
// and +0 alike), in order of first use, and triangles that lost a corner to
// the merge (two corners at one point) dropped: what a soup and an indexed
// mesh of the same surface have in common.
Mesh weld(const Mesh& mesh);

// What a surface is, combinatorially (of a welded mesh):
struct Topology {
  long vertices = 0, edges = 0, faces = 0;
  long boundary_edges = 0;      // edges of one triangle: holes, cracks, or the volume's border
  long nonmanifold_edges = 0;   // edges of three or more triangles
  long misoriented_edges = 0;   // edges two triangles run the same way (inconsistent orientation)
  long nonmanifold_vertices = 0;  // vertices whose triangles do not form one fan (pinched)
  long components = 0;          // connected by shared edges
  long euler() const { return vertices - edges + faces; }  // 2 - 2g per closed component
  bool closed_manifold() const {
    return boundary_edges == 0 && nonmanifold_edges == 0 && misoriented_edges == 0 && nonmanifold_vertices == 0;
  }
  std::string str() const;  // "V 120 E 354 F 236 chi 2, 1 component, closed oriented manifold"
};
Topology topology(const Mesh& welded);

// Triangles of zero area: two corners at one position, or three on one line
// (the cross product of two edges, from the float corners in double, exactly
// 0). Counted on the mesh as produced, soup or indexed: weld() drops the first
// kind, a welded mesh still has the second.
size_t zero_area_triangles(const Mesh& mesh);

}  // namespace lockstep
