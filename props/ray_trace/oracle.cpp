// lockstep props/ray_trace: the exact shadow answer (see oracle.h).
#include "props/ray_trace/oracle.h"

#include <cmath>

namespace lockstep::props::ray_trace {

std::optional<bool> exact_blocked(const Scene& scene, uint32_t own, const V3L& p, const V3L& light,
                                  LD m) {
  const V3L seg = sub(light, p);
  const LD len2 = dotl(seg, seg), len = std::sqrt(len2);
  bool blocked = false;
  for (uint32_t k = 0; k < scene.sphere_count(); ++k) {
    if (k == own) continue;
    const V3L pc = sub(to_l(scene.sphere_center[k]), p);
    LD u = dotl(pc, seg) / len2;
    u = u < 0 ? 0 : u > 1 ? 1 : u;
    const V3L q = {pc.x - u * seg.x, pc.y - u * seg.y, pc.z - u * seg.z};
    const LD dist = std::sqrt(dotl(q, q)), r = std::abs(scene.sphere_radius[k]);
    if (std::abs(dist - r) < m) return std::nullopt;
    blocked = blocked || dist < r;
  }
  for (uint32_t poly = 0; poly < scene.polygon_count(); ++poly) {
    if (scene.sphere_count() + poly == own) continue;
    const uint32_t first = scene.poly_first[poly], n = scene.poly_first[poly + 1] - first;
    const V3L a = to_l(scene.vertex[first]);
    V3L nrm{};
    for (uint32_t i = 0; i < n; ++i) {  // Newell's normal, in long double
      const V3L u = to_l(scene.vertex[first + i]), v = to_l(scene.vertex[first + (i + 1) % n]);
      nrm.x += (u.y - v.y) * (u.z + v.z), nrm.y += (u.z - v.z) * (u.x + v.x),
          nrm.z += (u.x - v.x) * (u.y + v.y);
    }
    const LD nl = std::sqrt(dotl(nrm, nrm));
    if (!(nl > 0)) continue;
    nrm = {nrm.x / nl, nrm.y / nl, nrm.z / nl};
    const LD h0 = dotl(nrm, sub(p, a)), h1 = dotl(nrm, sub(light, a));
    if ((h0 > 0) == (h1 > 0)) continue;  // both ends on one side
    const LD u = h0 / (h0 - h1);
    if (u * len < m || (1 - u) * len < m) return std::nullopt;
    const V3L x = {p.x + u * seg.x, p.y + u * seg.y, p.z + u * seg.z};
    // Inside the (convex) polygon: on the inner side of every edge, by more than m.
    bool inside = true;
    for (uint32_t i = 0; i < n; ++i) {
      const V3L u0 = to_l(scene.vertex[first + i]), u1 = to_l(scene.vertex[first + (i + 1) % n]);
      const V3L e = sub(u1, u0);
      const LD el = std::sqrt(dotl(e, e));
      const LD side = dotl(crossl(e, sub(x, u0)), nrm) / el;
      if (std::abs(side) < m) return std::nullopt;
      inside = inside && side > 0;
    }
    blocked = blocked || inside;
  }
  return blocked;
}

}  // namespace lockstep::props::ray_trace
