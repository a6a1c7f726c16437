// lockstep reference: deterministic synthetic layer stacks (benchmarks, corpus, tests).
//
// synthetic_stack(width, height, layers, opaque_from, alpha, storage, seed):
// `layers` RGBA layers, front first, with smooth, varied colours (a few
// smoothed triangle waves per channel at random frequencies and phases) and
// alphas strictly inside (0, 1). Layers from index `opaque_from` on (-1: none)
// are opaque (alpha exactly 1) except in a few small round holes, different per
// layer, so front-to-back compositing can stop early over most of the frame.
// alpha says how the colours are stored (straight, or premultiplied = colour *
// alpha); Storage::unorm8 also fills rgba8 (to_unorm8).
//
// Only +, -, *, / and comparisons on floats (no libm), so the same seed gives
// the same bits on every machine.
#pragma once

#include <cstdint>

#include "io/layers.h"

namespace lockstep {

LayerStack synthetic_stack(int width, int height, int layers, int opaque_from, Alpha alpha,
                           Storage storage, uint64_t seed);

}  // namespace lockstep
