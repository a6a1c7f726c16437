// lockstep CLI: one frame of one implementation, timed by the harness.
#pragma once

#include <exception>
#include <functional>
#include <map>
#include <string>

#include "core/family.h"
#include "core/process_memory.h"
#include "core/timer.h"

namespace lockstep::cli {

struct Run {
  bool ok = false;  // ran without throwing, and produced what was asked (the kind's check_frame)
  Output out;
  double seconds = 0;  // wall time of the whole call (BVH build included)
  FrameStats stats;
  std::string error;
  ResourceUse used;  // the frame's page faults and CPU time (run_for_cli; zero elsewhere)
};

// Runs in.value with impl at opts' size (or the input's own when the family
// is not sized). Exceptions become Run::error when catch_errors (verify keeps
// going); otherwise they propagate (render reports them).
// run: what to call instead of impl.run (a session's run, RowSessions), or null.
inline Run run_frame(const Family& family, const FamilyImpl& impl, const Input& in,
                     FrameOptions opts, bool catch_errors, const FamilyImpl::RunFn* run = nullptr) {
  if (!family.sized || opts.width <= 0 || opts.height <= 0) {
    opts.width = in.width;
    opts.height = in.height;
  }
  Run r;
  const Stopwatch timer;
  try {
    r.out = run ? (*run)(in, opts, &r.stats) : impl.run(in, opts, &r.stats);
    r.error = family.kind->check_frame(r.out, opts);
    r.ok = r.error.empty();
  } catch (const std::exception& e) {
    if (!catch_errors) throw;
    r.error = std::string("threw: ") + e.what();
  }
  r.seconds = timer.seconds();
  return r;
}

// The sessions of a run of many cases (verify): one per row whose session
// serves any input (FamilyImpl::session_any_input: the embree rows), started at
// the row's first case and kept to the end of the run. The run's resources
// (core/run_resources.h) are what those sessions share: the embree rows of
// ray_cast and ray_trace take the one Embree device of the run from there.
struct RowSessions {
  RunResources resources;  // declared first: the sessions below go before it
  std::map<const FamilyImpl*, FamilyImpl::RunFn> runs;
  // The row's session run, or null: the row has none, call impl.run.
  const FamilyImpl::RunFn* of(const FamilyImpl& impl, const Input& in, const FrameOptions& opts) {
    if (!impl.session || !impl.session_any_input) return nullptr;
    auto it = runs.find(&impl);
    if (it == runs.end()) it = runs.emplace(&impl, impl.session(in, opts, resources)).first;
    return &it->second;
  }
};

}  // namespace lockstep::cli
