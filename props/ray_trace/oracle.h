// lockstep props/ray_trace: the exact shadow answer (Far's oracle), in long double.
#pragma once

#include <cstdint>
#include <optional>

#include "core/math.h"
#include "core/scene.h"

namespace lockstep::props::ray_trace {

using LD = long double;
using V3L = Vec3T<LD>;

inline V3L sub(const V3L& a, const V3L& b) { return a - b; }
inline LD dotl(const V3L& a, const V3L& b) { return dot(a, b); }
inline V3L crossl(const V3L& a, const V3L& b) { return cross(a, b); }
inline V3L to_l(const Vec3& v) { return V3L(v); }

// The exact shadow answer for the segment from p (on primitive own) to the
// light, in long double: blocked by any other sphere or polygon (both sides,
// core/ray_trace.h). Ambiguous (nullopt) when the segment passes within m of
// another sphere's surface, crosses a polygon's plane within m of one of its
// edges, or within m of either end: rounding may decide those either way.
std::optional<bool> exact_blocked(const Scene& scene, uint32_t own, const V3L& p, const V3L& light,
                                  LD m);

}  // namespace lockstep::props::ray_trace
