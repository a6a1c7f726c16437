// lockstep core: shared objects of ours opened with dlopen on first use.
//
// Code that links a large library is built as a module of its own, a .so
// beside the binary, so that only the calls that need the library load it:
// OpenImageIO's image I/O and comparison (io/oiio.h, lockstep_oiio.so: about
// 250 shared libraries that `lockstep --version` and commands touching no
// image need not map) and the peer rows (optimized/peer_module.h,
// lockstep_peer_NAME.so: Mesa, LLVM, VTK, VolPack). A module exports
//   const void* lockstep_peer_api()                   its one table of functions,
//                                                     whose first field is an int abi number;
//   void lockstep_peer_version(char*, unsigned long)  the library's version, written at
//                                                     build time to NAME.version beside it
//                                                     (cmake/peer_version.cpp).
//
// Where a module is looked for, first hit wins:
//   $LOCKSTEP_PEER_DIR                 (the override, e.g. an installed layout)
//   the executable's own folder        (build/lockstep, build/bench/lockstep_llvmpipe_check)
//   the folder above it                (build/bench/lockstep_bench, build/props/lockstep_props,
//                                       build/tests/lockstep_volpack_test)
//
// No state of ours outlives a call: the dynamic loader keeps its own count of
// each open module; a module is opened with RTLD_NODELETE, so it (and its
// library) stays for the process.
#pragma once

#include <string>
#include <string_view>

namespace lockstep::module {

// The module's path where it is found (see the top), or "" when it is in none of those folders.
std::string find(std::string_view file);
// The first line of the .version file beside the module ("" when there is none).
std::string recorded_version(std::string_view file);
// How the module's and its libraries' function calls are bound: all at open
// (RTLD_NOW: a missing symbol fails the open, with dlerror()'s words), or each
// at its first call (RTLD_LAZY, as the loader binds an executable's own
// libraries at start: lockstep_oiio.so's ~250 libraries open 20 ms sooner).
enum class Binding { now, lazy };
// Opens the module and returns its lockstep_peer_api() table, whose abi field
// must equal abi (host and module from one build). Throws InputError naming
// the module's path (or the folders searched) and dlerror()'s words; `kind`
// names the module in those messages ("peer module").
const void* open_api(std::string_view file, std::string_view kind, int abi,
                     Binding binding = Binding::now);

}  // namespace lockstep::module
