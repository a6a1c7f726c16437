// lockstep core: how the process's heap treats freed memory (see core/process_memory.h).
#include "core/process_memory.h"

#include <malloc.h>

#include <limits>

namespace lockstep {

void keep_freed_memory() {
  // No block mmapped on its own: every block comes from the heap (sbrk).
  mallopt(M_MMAP_MAX, 0);
  // The heap's top is never trimmed: freed pages stay mapped and warm.
  mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
}

}  // namespace lockstep
