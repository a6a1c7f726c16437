// lockstep pairs: inputs shared by families (see pairs/loaders.h).
#include "pairs/loaders.h"

#include <cstdlib>
#include <filesystem>

#include "core/nff.h"
#include "core/volume_io.h"

namespace lockstep {

Input load_nff(const std::string& path) {
  Scene s = read_nff(path);
  const int w = s.view.xres, h = s.view.yres;
  const Vec3 bg = s.background;
  return make_input<Scene>(std::move(s), path, w, h, bg);
}

Input load_volume(const std::string& path, int width, int height) {
  return make_input<Volume>(read_volume(path), path, width, height);
}

std::string spd_dir() {
  if (const char* e = std::getenv("LOCKSTEP_SPD_DIR")) return e;
  return LOCKSTEP_SPD_DIR;
}

std::string volumes_dir() {
  if (const char* e = std::getenv("LOCKSTEP_VOLUMES_DIR")) return e;
  return LOCKSTEP_VOLUMES_DIR;
}

std::optional<Input> load_spd(std::string_view name) {
  const std::string path = spd_dir() + "/" + std::string(name) + ".nff";
  if (!std::filesystem::exists(path)) return std::nullopt;
  return load_nff(path);
}

}  // namespace lockstep
