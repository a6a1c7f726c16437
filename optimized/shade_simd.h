// lockstep optimized: Phong shading of 8 hits at once (Highway).
//
// The same local illumination as core/shading.h (ambient 0.1 kd C, per light
// Ip [kd C max(0, N.L) + ks max(0, R.V)^shine], Ip = colour or 1/sqrt(lights),
// times the extension's distance attenuation and spot factor),
// evaluated in float across a packet, with pow as exp(shine log x) from
// hwy/contrib/math. The per-hit set-up (hit point, normal, material) stays
// scalar and double (fill_lane), because it differs per primitive type; the
// per-light work, which is where the time goes, is vectorised. Agreement with
// the reference's double shading is checked like everything else (1/255).
#pragma once

#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/math.h"
#include "core/scene.h"
#include "optimized/simd_scene.h"

namespace lockstep::opt {

struct ShadeScene {
  std::vector<float> lx, ly, lz;   // light positions in the frame
  std::vector<float> ir, ig, ib;   // light intensities
  // lockstep's NFF extension (core/shading.h, light_at), per light:
  std::vector<float> c1, c2, c3;   // attenuation 1 / (c1 + c2 d + c3 d^2), clamped to 1
  std::vector<uint8_t> attenuated; // false: c = 1 0 0, skip the division
  std::vector<uint8_t> spot;       // a spotlight:
  std::vector<float> dx, dy, dz;   //   unit direction in the frame
  std::vector<float> cos_cutoff;   //   spot_cos_cutoff(), from the same double
  std::vector<float> exponent;     //   falloff exponent
  Vec3 background;
};
ShadeScene prepare_shading(const Scene& scene, const simd::Frame& frame);

struct ShadePacket {
  static constexpr int kLanes = simd::kPacket;
  alignas(32) float px[kLanes], py[kLanes], pz[kLanes];  // hit point, frame
  alignas(32) float nx[kLanes], ny[kLanes], nz[kLanes];  // unit normal facing the viewer, frame
  alignas(32) float vx[kLanes], vy[kLanes], vz[kLanes];  // unit direction to the viewer, frame
  alignas(32) float kr[kLanes], kg[kLanes], kb[kLanes];  // kd * colour
  alignas(32) float ks[kLanes], shine[kLanes];
  alignas(32) int32_t hit[kLanes];                       // 0: background
  alignas(32) float r[kLanes], g[kLanes], b[kLanes];     // result
};

// Scalar set-up of lane k for a hit (already refined) of the world ray `ray`,
// whose direction must be of unit length.
void fill_lane(const Scene& scene, const simd::Frame& frame, const Ray& ray, const Hit& hit,
               ShadePacket& p, int k);
// Shades every lane; misses get the background.
void shade_packet(const ShadeScene& s, ShadePacket& p);

}  // namespace lockstep::opt
