// lockstep io: the host side of lockstep_oiio.so (see io/oiio.h).
#include "io/oiio.h"

#include <new>
#include <stdexcept>

#include "core/error.h"
#include "core/module.h"

namespace lockstep::oiio {

const ModuleApi& api() {
  // Opened once per process (a throw leaves it unset: the next call tries again).
  // Bound lazily, as an executable linking OIIO was: binding every call of its
  // ~250 libraries at open cost about 20 ms more (`lockstep diff`, medians of 15).
  static const ModuleApi* const table = static_cast<const ModuleApi*>(
      module::open_api(kModuleFile, "OpenImageIO module", kAbi, module::Binding::lazy));
  return *table;
}

void raise(const Error& err) {
  switch (err.kind) {
    case Error::Kind::input:
      throw InputError(err.file, err.line, err.what);
    case Error::Kind::out_of_memory:
      throw std::bad_alloc();
    case Error::Kind::other:
      break;
  }
  throw std::runtime_error(err.what);
}

std::string recorded_version() { return module::recorded_version(kModuleFile); }

}  // namespace lockstep::oiio
