// lockstep core: the pair table.
//
// One entry per algorithm: its name, the implementations that provide it (the
// first is always the reference), the name of its input generator in
// props/gen/, and its tolerances. props/, bench/, corpus/ and the CLI iterate
// over this table; adding an algorithm or an implementation is one entry here.
//
// Tolerances are of two kinds:
//   agreement  each implementation against the reference on well-conditioned input
//   accuracy   each implementation against the exact/113-bit oracle (per implementation)
#pragma once

#include <span>
#include <string_view>

#include "core/ray_cast.h"

namespace lockstep {

// A known, documented failure of a third-party library that we report but cannot
// fix here: the outcome label it shows up as, and the most it may happen, as a
// share of the rays of its class (`per`: "vertex" = rays entering a closed mesh
// exactly through a shared vertex). The properties classify exactly this failure
// as explained, fail a run whose count is over max_rate, and fail on any other
// failure; see props/README.md.
struct KnownFailure {
  std::string_view label;  // empty = none
  double max_rate = 0;
  std::string_view per;
};

template <class Fn>
struct Impl {
  std::string_view name;
  Fn fn;
  double oracle_t_rel;  // accuracy: max relative error of t against the oracle (well-conditioned)
  // Agreement with the reference: relative error of t, when the pair's
  // Tolerance::t_rel does not fit this implementation (0 = the pair's).
  double agree_t_rel = 0;
  KnownFailure known_failure = {};
  // Unit roundoff of the arithmetic that decides hit/miss and which primitive,
  // when t is then refined in a wider type (0 = inferred from oracle_t_rel:
  // looser than 1e-9 is float, else double).
  double decide_eps = 0;
};

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

struct PairTable {
  Pair<RaySphereFn> ray_sphere;
  Pair<RayPlaneFn> ray_plane;
  Pair<RayPolygonFn> ray_polygon;
  Pair<CasterFns> ray_cast;
};

const PairTable& pairs();

}  // namespace lockstep
