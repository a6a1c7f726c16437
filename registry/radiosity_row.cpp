// lockstep registry: the radiosity family's row (core/radiosity.h for the
// contract, props/radiosity/ for the properties and bounds).
#include "registry/radiosity_row.h"

#include <filesystem>
#include <memory>
#include <string>

#include "core/radiosity.h"
#include "io/mesh_io.h"
#include "kinds/image_kind.h"
#include "optimized/radiosity_simd.h"
#include "reference/radiosity.h"
#include "registry/embree_device.h"
#include "registry/loaders.h"

namespace lockstep {

namespace {

constexpr TypedImpl<Scene> kImpls[] = {
    {"reference", ref::radiosity, 0, {}, {}, false},
    // A hemicube sample exactly on an edge shared by two polygons: each
    // z-buffer rounds the tie its own way (props/radiosity Agree). Per
    // hemicube case (ties cluster in a case: per pixel five seeds gave 0%,
    // 0%, 0.0017%, 0.12% and 0.023%): measured 0.42%, 0.40%, 0.2% and 0.198%
    // of the hemicube cases on four seeds of 1000 deep cases (2 of 480, 2 of
    // 497, 1, 1 of 504), cap 1%.
    {"simd", opt::simd::radiosity, 0, {"hemicube_tie", 0.01, "hemicube case"}},
};

// The Cornell box (corpus/radiosity/) at 128 x 128 and three patch counts
// (305, 1078, 4119 patches), rays k = 2; the hemicube (32) at the first.
// items: form factors (n^2).
std::vector<BenchInput> bench_frames() {
  std::vector<BenchInput> out;
  const std::string path = corpus_dir() + "/radiosity/cornell_box.nff";
  if (!std::filesystem::exists(path)) return out;
  const Input in = load_nff(path);
  struct Case {
    const char* name;
    const char* area;
    const char* method;
  };
  for (const Case& c : {Case{"cornell-305-rays", "8000", "rays"}, Case{"cornell-1078-rays", "2000", "rays"},
                        Case{"cornell-4119-rays", "500", "rays"}, Case{"cornell-305-hemicube", "8000", "hemicube"}}) {
    BenchInput b;
    b.name = c.name;
    b.input = in;
    b.width = b.height = 128;
    b.params.set("patch_area", c.area);
    b.params.set("form_factors", c.method);
    if (std::string(c.method) == "hemicube") b.params.set("hemicube", "32");
    b.counters = {{"patches", double(mesh_scene(input_as<Scene>(in), std::stod(c.area)).patches.size())}};
    out.push_back(std::move(b));
  }
  return out;
}

// --patches OUT.ply: each patch a face with its radiosity, the display
// vertices with theirs (the image's Gouraud colours), in scene units.
void write_patches(const Output& value, const std::string& path) {
  const PatchSolution& s = output_as<PatchSolution>(value);
  ColouredPolygons p;
  p.value_name = "radiosity";
  for (size_t v = 0; v < s.mesh.vertex.size(); ++v) {
    p.vertices.push_back(Vec3f(s.mesh.vertex[v]));
    p.vertex_values.push_back(Vec3f(s.vertex_b[v]));
  }
  for (size_t k = 0; k < s.mesh.patches.size(); ++k) {
    p.faces.push_back(s.mesh.corner[k]);
    p.corners.push_back(uint8_t(s.mesh.patches[k].count));
    p.face_values.push_back(Vec3f(s.b[k]));
    p.face_groups.push_back(s.mesh.patches[k].polygon);
  }
  write_coloured_polygons(p, path);
}

}  // namespace

Family radiosity_family() {
  Family f;
  f.name = "radiosity";
  f.what = "radiosity: patches, form factors (rays, hemicube, exact), Jacobi / Gauss-Seidel / progressive solve, "
           "Gouraud display through the z-buffer";
  f.input = "an NFF scene (.nff) with emitters ('#lockstep emit r g b' after an 'f' line)";
  f.unit = "form factors";
  f.verb = "solve";
  f.extension = ".nff";
  f.default_impl = "simd";
  f.algo = "radiosity";
  f.sized = true;
  f.kind = &image_kind();
  // Agreement of the simd row (props/radiosity Agree, 1000 deep cases, a
  // third of the rays and exact ones refined by --error): its rays decide
  // each segment by the reference's own test (shadow polygons choose which
  // blockers to ask): p99 4.4e-5 of a pixel's value, from the solve's
  // rounding. Its hemicube z-buffer breaks exact depth ties at shared edges
  // its own way (the row's known failure): 0.2-0.42% of the hemicube cases,
  // their pixels at most 0.0109 off.
  f.tol.abs = 1.0 / 255;
  f.tol.fraction = 0.999;
  f.tol.hard = 0.02;
  f.load = load_nff;
  f.impls = erase_all<Scene>(kImpls);
  // One Embree device per run, as the other embree rows.
  for (FamilyImpl& impl : f.impls)
    if (impl.name == "simd") {
      impl.session = [](const Input&, const FrameOptions&, RunResources& resources) {
        auto device = embree_device(resources);
        auto scratch = std::make_shared<opt::simd::RadiosityScratch>();  // the form factors' storage
        return [device, scratch](const Input& in, const FrameOptions& o, FrameStats* stats) {
          return make_output<Image>(
              opt::simd::radiosity_with(input_as<Scene>(in), o, stats, device->get(), scratch.get()));
        };
      };
      impl.session_any_input = true;
    }
  f.bench = bench_frames;
  f.properties = {"enclosure", "agree"};
  f.params = radiosity_params();
  f.check_params = [](const Params& p) { radiosity_settings(p, "settings"); };
  f.sides = {{"patches", "the patches as binary PLY: faces coloured by their radiosity, vertices by the display's",
              check_coloured_polygons_path, write_patches}};
  return f;
}

}  // namespace lockstep
