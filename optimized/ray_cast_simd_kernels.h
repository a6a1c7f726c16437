// lockstep optimized: the Highway ray-casting kernels (ray_cast_simd_kernels.cpp).
//
// Entry points that dispatch, at run time, to the best target the CPU has
// (HWY_DYNAMIC_DISPATCH). They see only float data already moved into a frame
// (optimized/simd_scene.h); what a packet's lanes mean, and what is done with
// the answers, is up to the caller (optimized/ray_cast_simd.cpp).
#pragma once

#include <cstddef>

#include "optimized/ray_cone.h"
#include "optimized/simd_scene.h"

namespace lockstep::opt::simd {

// The nearest hit of each of the packet's p.count rays among the candidates:
// out.t (in the packet's units, within (tmin, tmax)) and out.id (see
// PacketHits; -1: no hit). Lanes past p.count must hold a harmless ray.
void trace_packet(const SimdScene& s, const Candidates& cand, const Packet& p, PacketHits& out);

// Plane kernel: t = -dist / (n.d) per ray, in float, where dist = n.o + D is
// each ray origin's signed distance to the plane (computed in double by the
// caller); +inf where the ray is parallel or t is outside (tmin, tmax).
// count is a multiple of kPacket; the arrays need not be aligned.
void plane_t(const float* dx, const float* dy, const float* dz, const float* tmin, const float* tmax,
             const float n[3], const float* dist, float* t, size_t count);

// Rays in double, structure of arrays (the cone kernel's input).
struct ConeRays {
  const double *ox, *oy, *oz, *dx, *dy, *dz, *tmin, *tmax;
};

// Cone kernel, in double: t[i] = cone_nearest(c, o_i, d_i, tmin[i], tmax[i],
// solid) (optimized/ray_cone.h), bit for bit, for every ray i < count; count
// is a multiple of kPacket; the arrays need not be aligned. A lane's ray that
// is harmless to compute (tmax <= tmin) answers +inf.
void cone_t(const ConeShape& c, const ConeRays& r, double* t, size_t count, bool solid);

}  // namespace lockstep::opt::simd
