// lockstep optimized: the peer rows' shared objects (see optimized/peer_module.h),
// found and opened by core/module.h.
#include "optimized/peer_module.h"

#include "core/module.h"

namespace lockstep::peer {

std::string module_file(std::string_view name) {
  return "lockstep_peer_" + std::string(name) + ".so";
}

std::string find_module(std::string_view name) { return module::find(module_file(name)); }

std::string recorded_version(std::string_view name) {
  return module::recorded_version(module_file(name));
}

const void* open_api(std::string_view name, int abi) {
  return module::open_api(module_file(name), "peer module", abi);
}

}  // namespace lockstep::peer
