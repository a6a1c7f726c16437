// lockstep core: how the process's heap treats freed memory (see core/process_memory.h).
#include "core/process_memory.h"

#include <malloc.h>
#include <sys/resource.h>

#include <limits>

namespace lockstep {

void keep_freed_memory() {
  // No block mmapped on its own: every block comes from the heap (sbrk).
  mallopt(M_MMAP_MAX, 0);
  // The heap's top is never trimmed: freed pages stay mapped and warm.
  mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
}

ResourceUse resource_use() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  ResourceUse r;
  r.minor_faults = u.ru_minflt;
  r.major_faults = u.ru_majflt;
  r.system_seconds = double(u.ru_stime.tv_sec) + 1e-6 * double(u.ru_stime.tv_usec);
  r.user_seconds = double(u.ru_utime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec);
  return r;
}

}  // namespace lockstep
