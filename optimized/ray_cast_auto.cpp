// Ray casting, automatic choice between the Highway SIMD caster and Embree.
//
// Neither wins everywhere. ray_cast_simd.cpp tests every primitive that survives
// its per-tile cone culling against packets of 8 rays: no set-up, and unbeatable
// on small scenes, but its cost grows with the primitive count. Embree builds a
// BVH first and then costs roughly log(primitives) per ray, with a larger
// constant (its generic traversal, and the sidedness filter callbacks). So auto
// measures the scene's size and picks simd below a crossover, Embree above.
//
// The crossover, measured: 512 x 512, one thread (FrameOptions.threads = 1),
// wall time of the whole render call including Embree's device and BVH build,
// best of 7, AVX-512 machine (Highway target AVX3), Embree 3.13.5. SPD scenes
// from ../shared/spd (or `lockstep spd`); the last four are SPD scenes cut short (the first N
// spheres of balls-4, the first polygons of lattice-2-tess and gears-2) to fill
// the gap between sizes.
//
//   scene            spheres  triangles   simd s   embree s  (build s)  embree/simd
//   balls-1               10          2   0.0078     0.0190   (0.0002)    2.45
//   tetra-3                0         64   0.0058     0.0077   (0.0001)    1.33
//   balls-2               91          2   0.0084     0.0218   (0.0002)    2.60
//   mount-3                4        128   0.0086     0.0210   (0.0002)    2.45
//   teapot-2               0        248   0.0107     0.0122   (0.0002)    1.14
//   shells-1             361          0   0.0078     0.0187   (0.0002)    2.40
//   balls-3              820          2   0.0122     0.0245   (0.0003)    2.01
//   tree-2-tess            0        926   0.0133     0.0110   (0.0003)    0.83
//   jacks-2-tess           0       3024   0.0278     0.0143   (0.0007)    0.51
//   rings-1-tess           0       3962   0.0412     0.0181   (0.0010)    0.44
//   lattice-2-tess         0       4212   0.0533     0.0247   (0.0010)    0.46
//   gears-2                0       4578   0.0667     0.0292   (0.0011)    0.44
//   balls-4             7381          2   0.0442     0.0290   (0.0015)    0.66
//   sombrero-2             0       7938   0.0483     0.0125   (0.0018)    0.26
//   balls-5            66430          2   0.3314     0.0442   (0.0130)    0.13
//   lattice (cut)          0        600   0.0088     0.0072   (0.0002)    0.82
//   gears (cut)            0        720   0.0237     0.0173   (0.0003)    0.73
//   balls-4 (cut)       1500          2   0.0150     0.0192   (0.0004)    1.28
//   balls-4 (cut)       3000          2   0.0225     0.0223   (0.0007)    0.99
//
// What the table says: spheres and triangles do not cross over at the same
// count. Sphere scenes break even near 3000 spheres (balls-4 cut to 3000: 0.99),
// triangle scenes between 248 (teapot-2, simd 1.14x faster) and 600 triangles
// (lattice cut to 600, Embree 1.2x faster): a triangle costs simd's watertight
// test several times what a sphere costs, and Embree's point primitive is its
// slow one. No single threshold on spheres + triangles gets both right (1000
// would give tree-2-tess and the cut lattice/gears to simd and the 1500-sphere
// balls to Embree, each 1.2-1.4x slower than the other choice). So the size is
// counted in sphere-equivalents, a triangle weighing 6 (break-even 500
// triangles), and the crossover is 3000: every scene above is then assigned
// the faster of the two. Below the crossover the losses avoided are large in
// ratio (2-2.6x on the small sphere scenes); above it, Embree's lead grows
// with the size (7.5x on balls-5), since simd's cost stays roughly proportional
// to rays x primitives: culling trims the constant, not the order.
//
// trace() uses the same rule. Its rays share no origin, so simd cannot cull and
// Embree's lead on large scenes is larger still; for a handful of rays the BVH
// build (about 0.2 us per primitive) dominates, but costs little in absolute terms.
#include <string>

#include "optimized/ray_cast_simd.h"
#include "optimized/ray_cast_embree.h"
#include "optimized/ray_cast_auto.h"

namespace lockstep::opt::autosel {

namespace {

// A triangle costs simd about as much as this many spheres (see the table).
constexpr uint64_t kTriangleWeight = 6;
// Sphere-equivalents at and above which Embree is faster (see the table).
constexpr uint64_t kCrossover = 3000;

uint64_t scene_size(const Scene& scene) {
  return uint64_t(scene.sphere_count()) + kTriangleWeight * uint64_t(scene.triangle_count());
}

// For FrameStats::chosen, e.g.
//   "embree (size 5556 = 0 spheres + 6 x 926 triangles >= crossover 3000)".
std::string reason(const Scene& scene) {
  const bool embree = prefers_embree(scene);
  return std::string(embree ? "embree" : "simd") + " (size " + std::to_string(scene_size(scene)) +
         " = " + std::to_string(scene.sphere_count()) + " spheres + " +
         std::to_string(kTriangleWeight) + " x " + std::to_string(scene.triangle_count()) +
         " triangles " + (embree ? ">=" : "<") + " crossover " + std::to_string(kCrossover) +
         // Cones are not weighed: both rows test them in double, scalar per
         // candidate (lattice-2, 54 cylinders: simd 0.14 s, embree 0.15-0.19 s
         // a 512^2 frame on one thread, the machine loaded).
         (scene.cone_count() > 0 ? "; " + std::to_string(scene.cone_count()) + " cones not weighed"
                                 : "") +
         ")";
}

}  // namespace

bool prefers_embree(const Scene& scene) { return scene_size(scene) >= kCrossover; }

void trace(const Scene& scene, std::span<const Ray> rays, std::span<Hit> hits, FrameStats* stats) {
  if (prefers_embree(scene))
    embree::trace(scene, rays, hits, stats);
  else
    simd::trace(scene, rays, hits, stats);
  if (stats) stats->chosen = reason(scene);
}

Image render(const Scene& scene, const FrameOptions& opts, FrameStats* stats) {
  Image image =
      prefers_embree(scene) ? embree::render(scene, opts, stats) : simd::render(scene, opts, stats);
  if (stats) stats->chosen = reason(scene);
  return image;
}

}  // namespace lockstep::opt::autosel
