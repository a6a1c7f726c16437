// lockstep core: what one run shares among its rows (issue #22: one Embree
// device per process).
//
// A *run* is one process's pass over many frames: `lockstep verify` over the
// corpus, the property binary over its properties, the benchmark binary over
// its benchmarks. Some state is worth making once per run and sharing across
// rows (the embree rows of ray_cast and ray_trace both want one Embree device).
// The run owns a RunResources and hands it down explicitly (FamilyImpl::session,
// the property providers); there is no global. core/ cannot name what is
// shared (Embree lives in optimized/), so each resource is reached through a
// typed key that says its type and how to make it, and is stored type-erased:
// a key asked with another type than it was made with throws.
#pragma once

#include <any>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <string_view>

namespace lockstep {

// A resource of a run: its name (unique within the run) and how to make it.
// Defined once, next to the type (registry/embree_device.cpp: kEmbreeDevice).
template <class T>
struct RunKey {
  std::string_view name;
  std::shared_ptr<T> (*make)();
};

class RunResources {
 public:
  RunResources() = default;
  // One run, one holder: copies would make a second device.
  RunResources(const RunResources&) = delete;
  RunResources& operator=(const RunResources&) = delete;

  // The run's resource for key: made by key.make on the first ask, the same
  // object on every later one. Callers keep the shared_ptr as long as they use
  // it (a session's closure), so a resource outlives the holder if it must.
  // Thread-safe (rows may start sessions from several threads).
  template <class T>
  std::shared_ptr<T> get(const RunKey<T>& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = items_.find(key.name);
    if (it == items_.end()) it = items_.emplace(std::string(key.name), std::any(key.make())).first;
    const auto* p = std::any_cast<std::shared_ptr<T>>(&it->second);
    if (!p)
      throw std::logic_error("run resource '" + std::string(key.name) +
                             "' asked with another type");
    return *p;
  }

  // How many resources were made (tests: a run that needs none makes none).
  size_t size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return items_.size();
  }

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::any, std::less<>> items_;
};

}  // namespace lockstep
