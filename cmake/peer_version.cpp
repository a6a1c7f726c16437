// lockstep: writes a peer module's version beside it, at build time
// (CMakeLists.txt runs it after linking each lockstep_peer_NAME.so), so that
// `lockstep --version` names the peer library's version without loading it
// (optimized/peer_module.h).
//
//   lockstep_peer_version MODULE.so OUT.version
//
// Opens the module, calls its lockstep_peer_version(), writes one line to
// OUT.version.tmp and renames it into place. Exit 2 (and no file) when the
// module does not open: the build fails there, naming the module and dlerror().
#include <dlfcn.h>

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: lockstep_peer_version MODULE.so OUT.version\n");
    return 2;
  }
  void* handle = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    std::fprintf(stderr, "lockstep_peer_version: %s: cannot open: %s\n", argv[1], dlerror());
    return 2;
  }
  using VersionFn = void (*)(char*, unsigned long);
  auto fn = reinterpret_cast<VersionFn>(dlsym(handle, "lockstep_peer_version"));
  if (fn == nullptr) {
    std::fprintf(stderr, "lockstep_peer_version: %s: no lockstep_peer_version: %s\n", argv[1],
                 dlerror());
    return 2;
  }
  char buf[512] = {};
  fn(buf, sizeof buf);
  const std::string out = argv[2], tmp = out + ".tmp";
  FILE* f = std::fopen(tmp.c_str(), "w");
  if (f == nullptr || std::fprintf(f, "%s\n", buf) < 0 || std::fclose(f) != 0 ||
      std::rename(tmp.c_str(), out.c_str()) != 0) {
    std::fprintf(stderr, "lockstep_peer_version: %s: cannot write\n", out.c_str());
    std::remove(tmp.c_str());
    return 2;
  }
  return 0;
}
