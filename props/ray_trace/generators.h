// lockstep props/ray_trace: the named case generators (each property's
// comment in properties.cpp says which it draws from).
#pragma once

#include <rapidcheck.h>

#include "props/ray_trace/case.h"

namespace lockstep::props::ray_trace {

// Spheres and a transmitting triangle over a floor, 1..3 lights, seen from ~6 away.
rc::Gen<TraceCase> gen_scene(int size);
// A glass slab: faces at s = 0 (outward normal -a) and s = h (outward +a), the
// eye 5 before the front face looking along w with w.a >= 0.2; the centre pixel.
rc::Gen<TraceCase> gen_slab();
// The eye inside a glass ball (or below a glass plane, its normal away from
// the eye) looking out at incidence angle theta: 0, or the critical angle
// asin(1/ior) times (1 + delta), |delta| in 1e-12..1e-3.
rc::Gen<TraceCase> gen_tir();
// An opaque wall (one-sided, facing the eye) covering the view, lights and a
// few objects on the eye's side, and the hidden objects behind it.
rc::Gen<TraceCase> gen_hidden();
// Laws: directions anywhere, and densely near the critical angle.
rc::Gen<LawCase> gen_laws();
// gen_scene's kind of scene, opaque, at depth 1, scaled, moved and seen from
// far (generators.cpp).
rc::Gen<TraceCase> gen_far();

}  // namespace lockstep::props::ray_trace
