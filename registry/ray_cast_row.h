// lockstep registry: the ray-casting family's rows.
//
// The family (ray_cast: an NFF scene -> an image) and its kernel rows: one
// primitive against many rays (ray_sphere, ray_plane, ray_polygon), and whole
// scenes (trace: arbitrary rays -> hits; render: the scene's view). The first
// implementation of each row is always the reference. ray_cone: NFF's open
// cones (core/cone_quadric.h, optimized/ray_cone.h). props/ray_cast and the
// ray-casting benchmarks read these typed rows; everything generic (verify,
// render, frame benchmarks) sees the family through registry/registry.h.
//
// Tolerances are of two kinds:
//   agreement  each implementation against the reference on well-conditioned input
//   accuracy   each implementation against the exact/113-bit oracle (Impl::accuracy,
//              relative error of t)
#pragma once

#include <functional>
#include <span>
#include <string_view>

#include "core/family.h"
#include "core/ray_cast.h"

namespace lockstep {

// A caster's trace and render for a whole run of many scenes (the properties'
// cases), sharing what they keep (the embree row: one Embree device).
struct CasterRun {
  std::function<void(const Scene&, std::span<const Ray>, std::span<Hit>, FrameStats*)> trace;
  std::function<Image(const Scene&, const FrameOptions&, FrameStats*)> render;
};

struct CasterFns {
  TraceFn trace;
  RenderFn render;
  // Empty, or starts a run that keeps its state across calls (the embree row's
  // device, made at its first call, shared with every other embree row of the
  // caller's run); the family's FamilyImpl::session is the same.
  CasterRun (*session)(RunResources& run) = nullptr;
};

// The family's kernel rows (core/family.h: KernelRow), the reference first.
struct RayCastRows {
  KernelRow<RaySphereFn> ray_sphere;
  KernelRow<RayPlaneFn> ray_plane;
  KernelRow<RayPolygonFn> ray_polygon;
  KernelRow<CasterFns> ray_cast;
  KernelRow<RayConeFn> ray_cone;  // last: appended after the others
};

const RayCastRows& ray_cast_rows();

// The family as the registry sees it (built from ray_cast_rows().ray_cast; its
// kernel rows are its benchmark hooks: kernel/<row>/<impl>, throughput/...).
Family ray_cast_family();

}  // namespace lockstep
