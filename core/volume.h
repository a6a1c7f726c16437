// lockstep core: scalar volumes -- a regular grid of samples, as scanners and
// simulations produce them (CT, MRI, NRRD files) or as analytic fields are
// sampled (io/volume_io.h reads both).
//
// Sample (i, j, k) sits at world position origin + (i sx, j sy, k sz), with
// i fastest in memory, then j, then k (NRRD's order). Values are float
// whatever the file stored (uchar, ushort, short, float): 12-bit CT and 8-bit
// MRI values are exact in float.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/large_buffer.h"
#include "core/math.h"

namespace lockstep {

// Data an implementation derives from a volume's samples (opt::simd's min/max
// macro cells) and keeps with the volume between frames instead of rebuilding
// it every frame: the state lives in the input it was derived from, passed
// like the input, never in a global. An entry is found by its tag and by the
// samples' address and count (a guard: the samples must not change in place
// once the volume has been rendered; a copy starts with no entries). Thread-safe; at most kMaxEntries are kept (the
// oldest goes first).
class DerivedData {
 public:
  static constexpr size_t kMaxEntries = 8;
  // The entry (tag, key, count), made by make() -> T when absent. *made says
  // whether it was made now (a one-shot cost the caller reports).
  template <class T, class Make>
  std::shared_ptr<const T> get(const std::string& tag, const void* key, size_t count, Make make, bool* made) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const Entry& e : entries_)
      if (e.tag == tag && e.key == key && e.count == count) {
        if (made) *made = false;
        return std::static_pointer_cast<const T>(e.value);
      }
    auto value = std::make_shared<const T>(make());
    if (entries_.size() == kMaxEntries) entries_.erase(entries_.begin());
    entries_.push_back({tag, key, count, value});
    if (made) *made = true;
    return value;
  }

 private:
  struct Entry {
    std::string tag;
    const void* key;
    size_t count;
    std::shared_ptr<const void> value;
  };
  std::mutex mutex_;
  std::vector<Entry> entries_;
};

// A volume's DerivedData, fresh in every copy and move (see Volume::derived).
struct DerivedSlot {
  std::shared_ptr<DerivedData> data = std::make_shared<DerivedData>();
  DerivedSlot() = default;
  DerivedSlot(const DerivedSlot&) : DerivedSlot() {}
  DerivedSlot(DerivedSlot&&) : DerivedSlot() {}
  DerivedSlot& operator=(const DerivedSlot&) {
    data = std::make_shared<DerivedData>();
    return *this;
  }
  DerivedSlot& operator=(DerivedSlot&&) {
    data = std::make_shared<DerivedData>();
    return *this;
  }
  DerivedData* operator->() const { return data.get(); }
};

// A volume's samples: a large buffer, on huge pages where the kernel allows
// (core/large_buffer.h); resize leaves new samples unwritten (every reader
// writes them all).
using Samples = std::vector<float, NoInitAllocator<float>>;

struct Volume {
  int nx = 0, ny = 0, nz = 0;       // samples per axis
  Vec3 spacing{1, 1, 1};            // world distance between neighbouring samples, per axis
  Vec3 origin{0, 0, 0};             // world position of sample (0, 0, 0)
  Samples data;                     // nx * ny * nz, i fastest
  std::string source;               // the file it came from (messages, reports)
  // What implementations derived from the samples (DerivedData above). A copy
  // or a moved-to volume starts empty: it may be changed before it is
  // rendered, and an allocator may give a later volume's samples the address
  // of freed ones, so entries never outlive or leave the volume they came from.
  DerivedSlot derived;

  size_t index(int i, int j, int k) const { return (size_t(k) * size_t(ny) + size_t(j)) * size_t(nx) + size_t(i); }
  float at(int i, int j, int k) const { return data[index(i, j, k)]; }
  float& at(int i, int j, int k) { return data[index(i, j, k)]; }
  size_t cells() const { return nx > 1 && ny > 1 && nz > 1 ? size_t(nx - 1) * size_t(ny - 1) * size_t(nz - 1) : 0; }
  Vec3 position(int i, int j, int k) const {
    return {origin.x + i * spacing.x, origin.y + j * spacing.y, origin.z + k * spacing.z};
  }
};

}  // namespace lockstep
