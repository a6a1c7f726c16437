// lockstep registry: the one Embree device of a run (see registry/embree_device.h).
#include "registry/embree_device.h"

namespace lockstep {

namespace {

std::shared_ptr<EmbreeRunDevice> make_slot() { return std::make_shared<EmbreeRunDevice>(); }

constexpr RunKey<EmbreeRunDevice> kEmbreeDevice{"embree device", make_slot};

}  // namespace

opt::embree::Device EmbreeRunDevice::get() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!device_.handle) device_ = opt::embree::Device::create();
  return device_;
}

std::shared_ptr<EmbreeRunDevice> embree_device(RunResources& run) { return run.get(kEmbreeDevice); }

}  // namespace lockstep
