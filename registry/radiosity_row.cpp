// lockstep registry: the radiosity family's row (core/radiosity.h for the
// contract, props/radiosity/ for the properties and bounds).
#include "registry/radiosity_row.h"

#include <memory>
#include <string>

#include "core/radiosity.h"
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
    // z-buffer rounds the tie its own way (props/radiosity Agree); measured
    // 0.029% and 0.106% of the pixels of hemicube cases (two seeds of 1000
    // deep cases; ties cluster in a case), cap 0.15%.
    {"simd", opt::simd::radiosity, 0, {"hemicube_tie", 0.0015, "hemicube"}},
};

}  // namespace

Family radiosity_family() {
  Family f;
  f.name = "radiosity";
  f.what = "radiosity: patches, form factors (rays, hemicube), Jacobi / Gauss-Seidel / progressive solve, "
           "Gouraud display through the z-buffer";
  f.input = "an NFF scene (.nff) with emitters ('#lockstep emit r g b' after an 'f' line)";
  f.unit = "form factors";
  f.verb = "solve";
  f.extension = ".nff";
  f.default_impl = "simd";
  f.algo = "radiosity";
  f.sized = true;
  f.kind = &image_kind();
  // Agreement of the simd row (props/radiosity Agree, 1000 deep cases): its
  // rays decide in float (Embree), the reference's in double: p99 3.7e-5 of
  // a pixel's value, never over 1/255 so far. Its hemicube z-buffer breaks
  // exact depth ties at shared edges its own way (the row's known failure):
  // 0.029-0.106% of the hemicube cases' pixels over 1/255, at most 0.0109.
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
        return [device](const Input& in, const FrameOptions& o, FrameStats* stats) {
          return make_output<Image>(opt::simd::radiosity_with(input_as<Scene>(in), o, stats, device->get()));
        };
      };
      impl.session_any_input = true;
    }
  f.properties = {"enclosure", "agree"};
  f.params = radiosity_params();
  f.check_params = [](const Params& p) { radiosity_settings(p, "settings"); };
  return f;
}

}  // namespace lockstep
