// lockstep reference: the painter's algorithm (reference/painter.cpp), drawn
// with the plan every painter row shares (core/painter_plan.h: the depth sort,
// the Newell-Newell-Sancha tests and the must-draw-before graph).
#pragma once

#include "core/painter_plan.h"

namespace lockstep {

namespace ref {
// Painter's algorithm: view_scene, depth sort, NNS graph, draw back to front
// with the z-buffer's fill rule, samples and shade_fragment. Reports cycles and
// interpenetrations in stats->notes; with settings.split, resolves them.
Image painter(const Scene& scene, const FrameOptions& opts, FrameStats* stats);
}  // namespace ref

}  // namespace lockstep
