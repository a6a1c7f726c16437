// lockstep core: shared objects of ours opened with dlopen (see core/module.h).
#include "core/module.h"

#include <dlfcn.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <vector>

#include "core/error.h"

namespace lockstep::module {

namespace {

// The folders searched, in order (see the header).
std::vector<std::string> search_dirs() {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("LOCKSTEP_PEER_DIR"); env && *env) dirs.emplace_back(env);
  std::string exe(4096, '\0');
  const ssize_t n = readlink("/proc/self/exe", exe.data(), exe.size() - 1);
  if (n > 0) {
    exe.resize(size_t(n));
    const size_t slash = exe.rfind('/');
    if (slash != std::string::npos) {
      const std::string dir = slash == 0 ? "/" : exe.substr(0, slash);
      dirs.push_back(dir);
      dirs.push_back(dir + "/..");
    }
  }
  return dirs;
}

bool is_file(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

}  // namespace

std::string find(std::string_view file) {
  for (const std::string& dir : search_dirs())
    if (const std::string path = dir + "/" + std::string(file); is_file(path)) return path;
  return {};
}

std::string recorded_version(std::string_view file) {
  std::string path = find(file);
  if (path.empty()) return {};
  path.replace(path.size() - 3, 3, ".version");
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

const void* open_api(std::string_view file, std::string_view kind, int abi, Binding binding) {
  const std::string path = find(file);
  const std::string k(kind);
  if (path.empty()) {
    std::string where;
    for (const std::string& dir : search_dirs()) where += (where.empty() ? "" : ", ") + dir;
    throw InputError(std::string(file), 0,
                     k + " not found (searched " + where + "; LOCKSTEP_PEER_DIR overrides)");
  }
  // RTLD_LOCAL: the library's symbols stay out of the global scope;
  // RTLD_NODELETE: never unloaded, so a second open is the loader's count only.
  const int bind = binding == Binding::lazy ? RTLD_LAZY : RTLD_NOW;
  void* handle = dlopen(path.c_str(), bind | RTLD_LOCAL | RTLD_NODELETE);
  if (handle == nullptr) {
    const char* err = dlerror();
    throw InputError(path, 0, "cannot open " + k + ": " + (err ? err : "unknown dlopen error"));
  }
  using ApiFn = const void* (*)();
  dlerror();
  auto fn = reinterpret_cast<ApiFn>(dlsym(handle, "lockstep_peer_api"));
  if (fn == nullptr) {
    const char* err = dlerror();
    throw InputError(path, 0, "not a lockstep " + k + ": " + (err ? err : "no lockstep_peer_api"));
  }
  const void* api = fn();
  dlclose(handle);  // RTLD_NODELETE: the module stays, api stays valid
  // Every table starts with its abi number (an int).
  if (api == nullptr || *static_cast<const int*>(api) != abi)
    throw InputError(path, 0, k + " from another build (interface version differs: rebuild it)");
  return api;
}

}  // namespace lockstep::module
