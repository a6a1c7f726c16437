// lockstep optimized: the scene as the SIMD kernels see it.
//
// Everything is moved into a local frame in double and only then rounded to
// float: the origin is the camera eye (or the rays' origin) and, for renders,
// the axes are the camera's. A scene translated 1e7 units from the world origin
// then costs no precision, and primary rays (x, y, 1) keep their small lateral
// components exact. Spheres and triangles are structure-of-arrays; the kernels
// broadcast one primitive against a packet of 8 rays.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/scene.h"

namespace lockstep::opt::simd {

struct Frame {
  Vec3 origin{0, 0, 0};
  Vec3 ex{1, 0, 0}, ey{0, 1, 0}, ez{0, 0, 1};  // rows of the rotation world -> frame
  Vec3 point(const Vec3& p) const {
    const Vec3 q = p - origin;
    return {dot(ex, q), dot(ey, q), dot(ez, q)};
  }
  Vec3 dir(const Vec3& d) const { return {dot(ex, d), dot(ey, d), dot(ez, d)}; }
};

struct SimdScene {
  Frame frame;
  bool cull = true;  // NFF sidedness (frames); kernels count every root
  // Spheres.
  std::vector<float> sx, sy, sz, sr2;
  std::vector<uint8_t> s_inside;  // radius < 0: only the inside is visible
  std::vector<uint32_t> s_prim;
  // Triangles: tv[k][a] is axis a of vertex k; tn the polygon's plane normal.
  std::vector<float> tv[3][3];
  std::vector<float> tn[3];
  std::vector<uint8_t> t_two_sided;
  std::vector<uint32_t> t_prim, t_tri;
  // Bounding sphere of every primitive (spheres first, then triangles), in the
  // frame, in double: what the per-tile culling tests against.
  std::vector<Vec3> b_center;
  std::vector<double> b_radius;
  // Primitives out of the float range, kept as empty stand-ins (so that indices
  // stay the scene's) and counted by reason.
  std::map<std::string, uint64_t> dropped;

  size_t spheres() const { return sx.size(); }
  size_t triangles() const { return t_prim.size(); }
  void add_sphere(const Vec3& c, double r, uint32_t prim);
  void add_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n, bool two_sided,
                    uint32_t prim, uint32_t tri);
};

SimdScene prepare_scene(const Scene& scene, const Frame& frame, bool cull);

// The range the float kernels (ours and Embree's) can draw in, in the frame:
// the watertight triangle test forms products of three coordinates (T ~ 42 M^3
// for coordinates up to M), which overflow float beyond about 2e12 and
// underflow below about 2e-13; the sphere test squares them. Outside it a
// primitive is left out and counted (FrameStats::dropped), never silently
// missed (issue #22). Measured: a triangle at 7e12 vanished from simd and embree.
inline constexpr double kFloatTriangleMax = 0x1p40;  // 1.1e12
inline constexpr double kFloatSphereMax = 0x1p60;    // 1.2e18
inline constexpr double kFloatMin = 0x1p-40;         // 9.1e-13: a primitive's extent
// Why a triangle (vertices in the frame) or a sphere is out of that range; "" when it is not.
std::string float_triangle_limit(const Vec3& a, const Vec3& b, const Vec3& c);
std::string float_sphere_limit(const Vec3& centre, double radius);

// Primitives a packet may hit: sphere ids and triangle ids to test.
struct Candidates {
  std::vector<uint32_t> spheres, triangles;
};
// Every primitive: for rays with no shared origin (trace).
Candidates all_candidates(const SimdScene& s);

// One packet of up to kPacket rays in the frame, directions of unit length.
inline constexpr int kPacket = 8;
struct Packet {
  alignas(32) float ox[kPacket], oy[kPacket], oz[kPacket];
  alignas(32) float dx[kPacket], dy[kPacket], dz[kPacket];
  alignas(32) float tmin[kPacket], tmax[kPacket];
  int count = 0;
};
// id < spheres(): sphere id; else triangle id - spheres(); -1: no hit.
struct PacketHits {
  alignas(32) float t[kPacket];
  alignas(32) int32_t id[kPacket];
};

}  // namespace lockstep::opt::simd
