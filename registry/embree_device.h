// lockstep registry: the one Embree device of a run, shared by the embree rows
// (ray_cast's and ray_trace's) through the run's RunResources (issue #22: one
// device per process, not one per row).
//
// The run (verify, the property binary, the benchmarks) owns the
// RunResources; every embree session started in that run asks it for the
// same RunDevice. The device itself is made at the first frame that needs
// it, so a run that never renders with Embree (verify --impl simd) makes none.
#pragma once

#include <memory>
#include <mutex>

#include "core/run_resources.h"
#include "optimized/embree_scene.h"

namespace lockstep {

class EmbreeRunDevice {
 public:
  // The device, made at the first call; the same one afterwards. Thread-safe.
  opt::embree::Device get();

 private:
  std::mutex mutex_;
  opt::embree::Device device_;
};

// The run's Embree device slot: the same object for every caller with this run.
std::shared_ptr<EmbreeRunDevice> embree_device(RunResources& run);

}  // namespace lockstep
