// lockstep pairs: the ray-casting family's rows.
//
// The family (ray_cast: an NFF scene -> an image) and its kernel rows: one
// primitive against many rays (ray_sphere, ray_plane, ray_polygon), and whole
// scenes (trace: arbitrary rays -> hits; render: the scene's view). The first
// implementation of each row is always the reference. props/ray_cast and the
// ray-casting benchmarks read these typed rows; everything generic (verify,
// render, frame benchmarks) sees the family through pairs/registry.h.
//
// Tolerances are of two kinds:
//   agreement  each implementation against the reference on well-conditioned input
//   accuracy   each implementation against the exact/113-bit oracle (Impl::accuracy,
//              relative error of t)
#pragma once

#include <span>
#include <string_view>

#include "core/family.h"
#include "core/ray_cast.h"

namespace lockstep {

// Agreement tolerances against the reference.
struct Tolerance {
  double t_rel = 0;          // relative error of t
  double color_abs = 0;      // per-channel absolute colour error of a pixel
  double pixel_fraction = 1; // share of pixels that must be within color_abs
};

template <class Fn>
struct Pair {
  std::string_view name;
  std::string_view generator;  // props/gen name of the input generator
  Tolerance tol;
  std::span<const Impl<Fn>> impls;
  const Impl<Fn>* find(std::string_view n) const {
    for (const auto& i : impls)
      if (i.name == n) return &i;
    return nullptr;
  }
};

struct CasterFns {
  TraceFn trace;
  RenderFn render;
};

struct RayCastRows {
  Pair<RaySphereFn> ray_sphere;
  Pair<RayPlaneFn> ray_plane;
  Pair<RayPolygonFn> ray_polygon;
  Pair<CasterFns> ray_cast;
};

const RayCastRows& ray_cast_rows();

// The family as the registry sees it (built from ray_cast_rows().ray_cast).
ImageFamily ray_cast_family();

}  // namespace lockstep
