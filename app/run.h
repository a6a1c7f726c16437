// lockstep CLI: one frame of one implementation, timed by the harness.
#pragma once

#include <exception>
#include <string>

#include "core/family.h"
#include "core/timer.h"

namespace lockstep::cli {

struct Run {
  bool ok = false;  // ran without throwing, and produced what was asked (the kind's check_frame)
  Output out;
  double seconds = 0;  // wall time of the whole call (BVH build included)
  FrameStats stats;
  std::string error;
};

// Runs in.value with impl at opts' size (or the input's own when the family
// is not sized). Exceptions become Run::error when catch_errors (verify keeps
// going); otherwise they propagate (render reports them).
inline Run run_frame(const Family& family, const FamilyImpl& impl, const Input& in, FrameOptions opts,
                     bool catch_errors) {
  if (!family.sized || opts.width <= 0 || opts.height <= 0) {
    opts.width = in.width;
    opts.height = in.height;
  }
  Run r;
  const Stopwatch timer;
  try {
    r.out = impl.run(in, opts, &r.stats);
    r.error = family.kind->check_frame(r.out, opts);
    r.ok = r.error.empty();
  } catch (const std::exception& e) {
    if (!catch_errors) throw;
    r.error = std::string("threw: ") + e.what();
  }
  r.seconds = timer.seconds();
  return r;
}

}  // namespace lockstep::cli
