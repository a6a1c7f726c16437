// lockstep core: scalar volumes -- a regular grid of samples, as scanners and
// simulations produce them (CT, MRI, NRRD files) or as analytic fields are
// sampled (core/volume_io.h reads both).
//
// Sample (i, j, k) sits at world position origin + (i sx, j sy, k sz), with
// i fastest in memory, then j, then k (NRRD's order). Values are float
// whatever the file stored (uchar, ushort, short, float): 12-bit CT and 8-bit
// MRI values are exact in float.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/math.h"

namespace lockstep {

struct Volume {
  int nx = 0, ny = 0, nz = 0;       // samples per axis
  Vec3 spacing{1, 1, 1};            // world distance between neighbouring samples, per axis
  Vec3 origin{0, 0, 0};             // world position of sample (0, 0, 0)
  std::vector<float> data;          // nx * ny * nz, i fastest
  std::string source;               // the file it came from (messages, reports)

  size_t index(int i, int j, int k) const { return (size_t(k) * size_t(ny) + size_t(j)) * size_t(nx) + size_t(i); }
  float at(int i, int j, int k) const { return data[index(i, j, k)]; }
  float& at(int i, int j, int k) { return data[index(i, j, k)]; }
  size_t cells() const { return nx > 1 && ny > 1 && nz > 1 ? size_t(nx - 1) * size_t(ny - 1) * size_t(nz - 1) : 0; }
  Vec3 position(int i, int j, int k) const {
    return {origin.x + i * spacing.x, origin.y + j * spacing.y, origin.z + k * spacing.z};
  }
};

}  // namespace lockstep
