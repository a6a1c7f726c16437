// lockstep optimized: the peer rows' shared objects, opened when a row runs.
//
// A peer row (llvmpipe through OSMesa, VTK's flying edges, VolPack) is built as
// a module of its own, lockstep_peer_NAME.so (CMakeLists.txt), that holds the
// only code linked against the peer library. The rest of the binary links
// none of them: `lockstep --version`, `diff` and our own rows do not load
// Mesa, LLVM, VTK or VolPack (measured by bench/scripts/oneshot.sh). The host side
// of each row (optimized/raster_llvmpipe.cpp, marching_cubes_vtk.cpp,
// volume_volpack.cpp) prepares the call, opens the module here and calls the
// one table of functions it exports (lockstep_peer_api).
//
// Modules are found and opened by core/module.h (which says where they are
// looked for: $LOCKSTEP_PEER_DIR first, then beside the executable and the
// folder above it), as OpenImageIO's lockstep_oiio.so is. Beside each module,
// lockstep_peer_NAME.version (written when it is built, by
// cmake/peer_version.cpp) names the peer library's version, so that --version
// says it without opening the module.
//
// No state of ours outlives a call: the dynamic loader keeps its own count of
// each open module; a module is opened with RTLD_NODELETE, so the peer library
// (and what it caches, e.g. llvmpipe's screen) stays for the process.
#pragma once

#include <string>
#include <string_view>

namespace lockstep::peer {

// The module's file, e.g. "lockstep_peer_llvmpipe.so".
std::string module_file(std::string_view name);
// The module's path where it is found (see the top), or "" when it is in none of those folders.
std::string find_module(std::string_view name);
// The first line of the .version file beside the module ("" when there is none).
std::string recorded_version(std::string_view name);
// Opens the module and returns its lockstep_peer_api() table, whose
// abi field must equal abi (host and module from one build). Throws InputError
// naming the module's path (or the folders searched) and dlerror()'s words.
const void* open_api(std::string_view name, int abi);

}  // namespace lockstep::peer
