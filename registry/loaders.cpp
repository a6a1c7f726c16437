// lockstep registry: inputs shared by families (see registry/loaders.h).
#include "registry/loaders.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "core/error.h"
#include "io/nff.h"
#include "core/scene.h"
#include "io/volume_io.h"
#include "spd/spd.h"

namespace lockstep {

Input load_nff(const std::string& path) {
  Scene s = read_nff(path);
  const int w = s.view.xres, h = s.view.yres;
  const Vec3 bg = s.background;
  return make_input<Scene>(std::move(s), path, w, h, bg);
}

void refuse_cones(Family& f, std::initializer_list<std::string_view> draws_cones) {
  for (FamilyImpl& impl : f.impls) {
    if (std::find(draws_cones.begin(), draws_cones.end(), impl.name) != draws_cones.end()) continue;
    std::string why = std::string(f.name) + " --impl " + std::string(impl.name) +
                      " does not draw cones yet";
    impl.run = [run = std::move(impl.run), why](const Input& in, const FrameOptions& o, FrameStats* s) {
      const Scene& scene = input_as<Scene>(in);
      if (scene.cone_count() > 0)
        throw InputError(scene.source, 0, std::to_string(scene.cone_count()) + " cones ('c'): " + why);
      return run(in, o, s);
    };
  }
}

Input load_volume(const std::string& path, int width, int height) {
  return make_input<Volume>(read_volume(path), path, width, height);
}

std::string spd_dir() {
  if (const char* e = std::getenv("LOCKSTEP_SPD_DIR")) return e;
  return LOCKSTEP_SPD_DIR;
}

std::string corpus_dir() {
  if (const char* e = std::getenv("LOCKSTEP_CORPUS_DIR")) return e;
  return LOCKSTEP_CORPUS_DIR;
}

std::string volumes_dir() {
  if (const char* e = std::getenv("LOCKSTEP_VOLUMES_DIR")) return e;
  return LOCKSTEP_VOLUMES_DIR;
}

std::optional<Input> load_spd(std::string_view name) {
  const std::string path = spd_dir() + "/" + std::string(name) + ".nff";
  if (std::filesystem::exists(path)) return load_nff(path);
  const std::optional<spd::Request> r = spd::parse_stem(name);
  if (!r) return std::nullopt;
  // Named as the file would be, marked generated, for messages and reports.
  const std::string label = std::string(name) + ".nff (generated: lockstep spd)";
  Scene s = parse_nff(spd::generate(r->name, r->size, r->tess), label);
  const int w = s.view.xres, h = s.view.yres;
  const Vec3 bg = s.background;
  return make_input<Scene>(std::move(s), label, w, h, bg);
}

bool have_real_volumes() {
  const std::string dir = volumes_dir();
  return std::filesystem::exists(dir + "/cthead.nhdr") &&
         std::filesystem::exists(dir + "/ch2.nhdr");
}

}  // namespace lockstep
