// lockstep CLI: one frame of one implementation, timed by the harness.
#pragma once

#include <exception>
#include <string>

#include "core/family.h"
#include "core/timer.h"

namespace lockstep::cli {

struct Run {
  bool ok = false;  // rendered without throwing, at the size asked for
  Image image;
  double seconds = 0;  // wall time of the whole call (BVH build included)
  FrameStats stats;
  std::string error;
};

// Renders in.value with impl at opts' size (or the input's own when the family
// is not sized). Exceptions become Run::error when catch_errors (verify keeps
// going); otherwise they propagate (render reports them).
inline Run run_frame(const ImageFamily& family, const ImageImpl& impl, const Input& in, FrameOptions opts,
                     bool catch_errors) {
  if (!family.sized || opts.width <= 0 || opts.height <= 0) {
    opts.width = in.width;
    opts.height = in.height;
  }
  Run r;
  const Stopwatch timer;
  try {
    r.image = impl.render(in, opts, &r.stats);
    r.ok = r.image.width == opts.width && r.image.height == opts.height;
    if (!r.ok) r.error = "returned an image of the wrong size";
  } catch (const std::exception& e) {
    if (!catch_errors) throw;
    r.error = std::string("threw: ") + e.what();
  }
  r.seconds = timer.seconds();
  return r;
}

}  // namespace lockstep::cli
