// lockstep pairs: the volume-rendering families' rows (see pairs/volume.h).
#include "pairs/volume.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>

#include "core/output_image.h"
#include "core/volume_render.h"
#include "optimized/volume_raycast.h"
#include "pairs/loaders.h"
#include "reference/volume_render.h"

namespace lockstep {

namespace {

// The frames of issue #20 at 512^2: the CT head and the MRI brain, two transfer
// functions each; the reference draws them at 128^2 (heavy_for_reference).
std::vector<BenchInput> bench_frames(vr::Mode mode) {
  std::vector<BenchInput> out;
  auto add = [&](std::string name, const std::string& path, std::vector<std::pair<std::string, std::string>> params) {
    if (!std::filesystem::exists(path)) return;
    BenchInput b;
    b.name = std::move(name);
    b.make = [path] { return load_volume(path, 512, 512); };
    b.width = b.height = 512;
    b.heavy_for_reference = true;
    for (auto& [k, v] : params) b.params.set(k, v);
    out.push_back(std::move(b));
  };
  const std::string ct = volumes_dir() + "/cthead.nhdr", mri = volumes_dir() + "/ch2.nhdr";
  // The CT head seen from the front (the face looks along -y), a little from above.
  if (mode == vr::Mode::kIso) {
    add("cthead/bone", ct, {{"iso", "1200"}, {"view", "-90,-15,180"}});
    add("cthead/skin", ct, {{"iso", "600"}, {"view", "-90,-15,180"}});
    add("ch2/skin", mri, {{"iso", "80"}, {"view", "-90,-15,180"}});
  } else {
    add("cthead/bone", ct, {{"tf", "ct-bone"}, {"view", "-90,-15,180"}});
    // The same frame without empty-space skipping (the 10x target: SIMD alone).
    add("cthead/bone-noskip", ct, {{"tf", "ct-bone"}, {"view", "-90,-15,180"}, {"noskip", "1"}});
    add("cthead/skin", ct, {{"tf", "ct-skin"}, {"view", "-90,-15,180"}});
    add("ch2/mri", mri, {{"tf", "mri"}, {"view", "-90,-15,180"}});
  }
  return out;
}

Family base(vr::Mode mode) {
  Family f;
  f.input = "a volume: NRRD (.nrrd, .nhdr) or an analytic field (.field)";
  f.unit = "pixels";
  f.verb = "render";
  f.extension = ".nrrd .nhdr .field";
  f.default_impl = "reference";
  f.sized = true;
  f.kind = &image_kind();
  // 256 x 256 unless the CLI's --size or the manifest says otherwise.
  f.load = [](const std::string& path) { return load_volume(path, 256, 256); };
  f.params = vr::params(mode);
  f.check_params = [mode](const Params& p) { vr::settings(p, "settings", mode); };
  f.bench = [mode] { return bench_frames(mode); };
  // A family without an optimized row (splat) compares only the reference with
  // its golden; rows that have one set their own, measured tolerance below.
  f.tol.abs = 1.0 / 255;
  f.tol.fraction = 1.0;
  return f;
}

}  // namespace

Family volume_family() {
  Family f = base(vr::Mode::kRaycast);
  f.name = "volume";
  f.what = "volume rendering by V-buffer ray casting (transfer function, front-to-back over)";
  f.algo = "raycast";
  const TypedImpl<Volume> impls[] = {{"reference", ref::volume_raycast, 0, {}, {}, false},
                                      {"simd", opt::simd::volume_raycast}};
  f.impls = erase_all<Volume, Image>(impls);
  // error=E: the step is measured once, here, for every implementation alike
  // (ref::step_for_error), and handed on as step=; the note says what was
  // chosen, and the measuring counts as the run's build time.
  for (FamilyImpl& impl : f.impls)
    impl.run = [run = impl.run](const Input& in, const FrameOptions& o, FrameStats* stats) {
      const std::string error = o.params.get("error");
      if (error.empty()) return run(in, o, stats);
      const Volume& v = input_as<Volume>(in);
      double measured = 0;
      const auto t0 = std::chrono::steady_clock::now();
      const double step = ref::step_for_error(v, o.params, o.width, o.height, &measured);
      const double choosing = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      FrameOptions chosen = o;
      chosen.params.items.clear();
      for (const auto& [k, val] : o.params.items)
        if (k != "error") chosen.params.set(k, val);
      chosen.params.set("step", std::to_string(step));
      Output out = run(in, chosen, stats);
      if (stats) {
        stats->build_seconds += choosing;  // a one-shot cost, shown apart from the frame
        char note[200];
        std::snprintf(note, sizeof note, "error %s: step %g voxel (mean error %.3g on a preview, against step 1/16)%s",
                      error.c_str(), step, measured,
                      measured > std::strtod(error.c_str(), nullptr) ? "; no step down to 1/8 meets it" : "");
        stats->notes.push_back(note);
      }
      return out;
    };
  f.default_impl = "simd";
  f.properties = {"agreement", "skip", "transparent", "mirror"};
  // Float against double (props/volume Agreement, random volumes and transfer
  // functions): largest difference 3.7e-4 over 25,000 cases (8M pixels), p99
  // 7e-7; the CT head 1.9e-5. Rays that stop at 1 - eps one sample apart
  // (float and double cross it differently, ~1 pixel in 400,000) differ by up
  // to eps: props/volume classifies them (termination_flip).
  f.tol.abs = 6e-4;
  f.tol.fraction = 0.999;
  return f;
}

Family splat_family() {
  Family f = base(vr::Mode::kSplat);
  f.name = "splat";
  f.what = "volume rendering by splatting (Gaussian footprints in depth order)";
  f.algo = "splat";
  const TypedImpl<Volume> impls[] = {{"reference", ref::volume_splat, 0, {}, {}, false}};
  f.impls = erase_all<Volume, Image>(impls);
  f.properties = {"transparent", "mirror"};
  return f;
}

Family volume_iso_family() {
  Family f = base(vr::Mode::kIso);
  f.name = "volume_iso";
  f.what = "the isosurface of the trilinear interpolant, ray cast (first crossing, bisection, gradient shading)";
  f.algo = "iso";
  const TypedImpl<Volume> impls[] = {{"reference", ref::volume_iso, 0, {}, {}, false},
                                      {"simd", opt::simd::volume_iso}};
  f.impls = erase_all<Volume, Image>(impls);
  f.default_impl = "simd";
  f.properties = {"agreement", "mirror"};
  // simd finds the reference's bracket (float decisions near iso redone in
  // double) and bisects and shades with the reference's double code: measured
  // 0 difference (props/volume Agreement, 25,000 cases; the CT head at 256^2).
  f.tol.abs = 1e-6;
  f.tol.fraction = 1.0;
  // An iso value outside the volume's values is not an error: every
  // implementation's run says so in a note (the image is empty).
  for (FamilyImpl& impl : f.impls)
    impl.run = [run = impl.run](const Input& in, const FrameOptions& o, FrameStats* stats) {
      Output out = run(in, o, stats);
      if (stats)
        if (std::string note = vr::empty_note(input_as<Volume>(in), vr::settings(o.params, "", vr::Mode::kIso).iso);
            !note.empty())
          stats->notes.push_back(std::move(note));
      return out;
    };
  return f;
}

}  // namespace lockstep
