// lockstep core: memory for large buffers (see core/large_buffer.h).
#include "core/large_buffer.h"

#include <sstream>

namespace lockstep {

std::string huge_page_summary() {
  const std::string m = huge_page_mode();
  std::ostringstream s;
  s << "transparent huge pages " << m << " (/sys/kernel/mm/transparent_hugepage/enabled): ";
  if (huge_pages_used())
    s << "buffers of " << (kHugeBytes >> 20) << " MiB and up are advised onto them";
  else if (m == "always" || m == "madvise")
    s << "not used (LOCKSTEP_HUGE_PAGES=0)";
  else
    s << "not available, 4 KiB pages";
  return s.str();
}

}  // namespace lockstep
