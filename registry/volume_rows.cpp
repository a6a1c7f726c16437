// lockstep registry: the volume-rendering families' rows (see registry/volume_rows.h).
#include "registry/volume_rows.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>

#include "core/error.h"
#include "kinds/image_kind.h"
#include "core/volume_render.h"
#include "io/volume_settings.h"
#include "optimized/volume_raycast_simd.h"
#include "optimized/volume_splat_simd.h"
#include "optimized/volume_volpack.h"
#include "registry/loaders.h"
#include "reference/volume_render.h"

namespace lockstep {

namespace {

// The frames of issue #20 at 512^2: the CT head and the MRI brain, two transfer
// functions each; the reference draws them at 128^2 (heavy_for_reference).
std::vector<BenchInput> bench_frames(vr::Mode mode) {
  std::vector<BenchInput> out;
  auto add = [&](std::string name, const std::string& path, std::vector<std::pair<std::string, std::string>> params) {
    if (!std::filesystem::exists(path)) return;
    // The real volumes cannot be generated: without them, their frames are
    // left out (bench/bench_main.cpp says so once).
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
  // Every family sets its own, measured tolerance below (the rows' agreement
  // with the reference); this is only the default.
  f.tol.abs = 1.0 / 255;
  f.tol.fraction = 1.0;
  return f;
}

// The volpack row's agreement with the reference (FamilyImpl::agree): a pixel
// is over when its largest channel differs by more than 32/255; at most 8% of
// the pixels may be, none by more than 0.95. Shear-warp resamples otherwise
// (optimized/volume_volpack.cpp): it classifies voxels and interpolates their
// colours and opacities bilinearly per slice (the reference interpolates the
// value and classifies the sample), one sample per slice, an 8-bit result. So
// at transfer-function edges a pixel can change from transparent to bone.
// Measured (tests/volpack_test.cpp, DISABLED_Figures; per pixel the largest
// channel's |difference|; max, mean, share of pixels over 2/255, 8/255, 32/255):
//   CT head ct-bone -90,-15,180 512^2  max 0.873 mean 2.11/255  14.0%  9.0%  0.87%
//   CT head ct-skin -90,-15,180 512^2  max 0.688 mean 4.30/255  26.8% 17.9%  3.10%
//   MRI mri -90,-15,180 512^2          max 0.327 mean 4.05/255  25.9% 17.9%  2.39%
//   CT head ct-skin 30,20 256^2        max 0.618 mean 5.65/255  26.0% 20.2%  6.11%
//   neghip (tests/volpack/neghip.tf) 30,20 and -135,-10,90, 128^2 and 256^2:
//                                      max 0.632 mean 5.95/255  21.0% 14.0%  7.03%
//   sphere-32 core.tf 30,20 128^2      max 0.014 mean 0.25/255   2.3%  0     0
//   torus-32 core.tf -60,40,15 128^2   max 0.137 mean 3.25/255  36.2% 14.5%  0.21%
// so the bound's fraction has a margin of 8 / 7.03 = 1.14 over the worst frame
// (neghip), its hard limit 0.95 over the worst pixel 0.873 (the CT head's bone).
// Not held to it: dense fields cut by the volume's box (the half-ramp on the
// torus, gyroid and Marschner-Lobb fields; gyroid under ramp), where VolPack's
// one-voxel apron around the box (slices interpolated against empty
// neighbours, and the warp's bilinear filter) and its n slices against the
// reference's n - 1 voxels of path make 8.7-42% of the pixels differ by more
// than 32/255 (max 0.998, mean 9.3-34.8/255).
// Two choices of the row, measured against their alternatives: the opacity
// exponent r that turns VolPack's per-slice correction into the reference's
// (1.026 for the CT head's 1x1x2 mm voxels at -90,-15,180; 1 for cubic voxels)
// moves the CT head's mean difference by -0.06 to +0.09/255 (skin
// -90,-15,180: 4.30/255 with it, 4.21 without): exact in principle, lost among
// the method's differences. Rounding each voxel's 8-bit opacity (VolPack
// truncates) measures slightly worse (skin 4.30 against 4.19/255, torus 3.25
// against 2.77/255, neghip 5.83 against 5.68/255): VolPack is already the
// more opaque (the apron, n slices), and truncation's downward bias happens
// to offset it; the row keeps the opacity nearest the transfer function's.
Tolerance volpack_agree() {
  Tolerance t;
  t.abs = 32.0 / 255;
  t.fraction = 0.92;
  t.hard = 0.95;
  return t;
}

}  // namespace

Family volume_family() {
  Family f = base(vr::Mode::kRaycast);
  f.name = "volume";
  f.what = "volume rendering by V-buffer ray casting (transfer function, front-to-back over)";
  f.algo = "raycast";
  std::vector<TypedImpl<Volume>> impls = {{"reference", ref::volume_raycast, 0, {}, {}, false},
                                          // A volume without a cell on every axis (a slice, a line): the
                                          // reference's arithmetic (optimized/volume_raycast_simd.h); the
                                          // choice is made here, so optimized/ sees no reference.
                                          {"simd", [](const Volume& v, const FrameOptions& o, FrameStats* st) {
                                             return opt::simd::volume_cast_handles(v) ? opt::simd::volume_raycast(v, o, st)
                                                                                      : ref::volume_raycast(v, o, st);
                                           }}};
  // VolPack's shear-warp (optimized/volume_volpack.cpp), only where the build
  // found VolPack: another resampling (classified voxels interpolated
  // bilinearly per slice, one sample per slice, an 8-bit result), so its own
  // agreement with the reference, measured (see volpack_agree below).
  if (opt::volpack::available())
    impls.push_back({"volpack", opt::volpack::volume_raycast, 0, {}, "VolPack 1.0b3 (shear-warp)", false, nullptr,
                     volpack_agree()});
  f.impls = erase_all<Volume, Image>(impls);
  f.peer_rows.push_back(module_peer("volpack", opt::volpack::available(), opt::volpack::version(),
                                    "lockstep_peer_volpack.so", "scripts/setup.sh installs libvolpack1-dev"));
  // error=E (core/volume_render.h choose_for_error): the row itself draws the
  // converged image (step 1/16, eps 0) and the candidates at full size, and the
  // frame returned is the one whose error was measured, so the figure on the
  // stats line is the returned image's own. The search counts as the run's
  // build time; the chosen frame's time is its render time. A row that does
  // not sample every step (volpack: one sample per slice) cannot be held to
  // it and is refused. Not met: refused (InputError, exit 2) with the best
  // error the search reached.
  for (FamilyImpl& impl : f.impls)
    impl.run = [run = impl.run, name = std::string(impl.name)](const Input& in, const FrameOptions& o,
                                                               FrameStats* stats) {
      const std::string error = o.params.get("error");
      if (error.empty()) return run(in, o, stats);
      const Volume& v = input_as<Volume>(in);
      if (name == "volpack")
        throw InputError(v.source, 0,
                         "error " + error + ": the volpack row samples once per slice, not every step, so "
                         "--error cannot choose its step (use --impl simd or reference, or give --step)");
      const double target = vr::settings(o.params, v.source, vr::Mode::kRaycast).error;
      FrameOptions base = o;
      base.params.items.clear();
      for (const auto& [k, val] : o.params.items)
        if (k != "error" && k != "step" && k != "eps") base.params.set(k, val);
      base.progress = nullptr;
      struct Drawn {
        double step, eps, seconds;
        FrameStats stats;
      };
      std::vector<Drawn> drawn;
      const auto t0 = std::chrono::steady_clock::now();
      vr::ErrorChoice c = vr::choose_for_error(target, [&](double step, double eps) {
        FrameOptions fo = base;
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.17g", step);
        fo.params.set("step", buf);
        std::snprintf(buf, sizeof buf, "%.17g", eps);
        fo.params.set("eps", buf);
        // The converged frame is the long one: it shows the progress.
        if (step == vr::kConvergedStep && eps == 0) fo.progress = o.progress;
        Drawn d{step, eps, 0, {}};
        const auto r0 = std::chrono::steady_clock::now();
        Output out = run(in, fo, &d.stats);
        d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - r0).count();
        drawn.push_back(std::move(d));
        return take_output<Image>(std::move(out));
      });
      const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      char what[400];
      std::snprintf(what, sizeof what,
                    "step %s voxel, eps %s: mean error %.3g per channel over %llu covered pixels "
                    "(converged alpha > 0) against step 1/16 without early termination",
                    vr::fraction_text(c.step).c_str(), vr::fraction_text(c.eps).c_str(), c.error.mean,
                    (unsigned long long)c.error.covered);
      if (!c.met) {
        char least[40];
        std::snprintf(least, sizeof least, "%.3g", c.error.mean);
        throw InputError(v.source, 0,
                         "error " + error + " cannot be met: the best the search reaches is " + what +
                             "; ask for at least " + least + ", or give --step and --eps");
      }
      if (stats) {
        for (const Drawn& d : drawn)
          if (d.step == c.step && d.eps == c.eps) {
            *stats = d.stats;
            // The search (every other frame, the converged one included) is a one-shot cost, shown apart.
            stats->build_seconds += total - d.seconds;
            break;
          }
        char head[120];
        std::snprintf(head, sizeof head, "step %s voxel, eps %s for error %s: ", vr::fraction_text(c.step).c_str(),
                      vr::fraction_text(c.eps).c_str(), error.c_str());
        char tail[200];
        std::snprintf(tail, sizeof tail,
                      "mean error %.3g per channel over %llu covered pixels (converged alpha > 0) against step "
                      "1/16 without early termination",
                      c.error.mean, (unsigned long long)c.error.covered);
        stats->chosen = std::string(head) + tail;
      }
      return make_output<Image>(std::move(c.image));
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
  const TypedImpl<Volume> impls[] = {{"reference", ref::volume_splat, 0, {}, {}, false},
                                      // A footprint wider than 4096 pixels (a few voxels in a large
                                      // frame): the reference (optimized/volume_splat_simd.h).
                                      {"simd", [](const Volume& v, const FrameOptions& o, FrameStats* st) {
                                         return opt::simd::volume_splat_handles(v, o) ? opt::simd::volume_splat(v, o, st)
                                                                                      : ref::volume_splat(v, o, st);
                                       }}};
  f.impls = erase_all<Volume, Image>(impls);
  f.default_impl = "simd";
  f.properties = {"agreement", "transparent", "mirror"};
  // simd (optimized/volume_splat_simd.cpp) draws the reference's footprints
  // (the same pixels, the same depth order and sheets) from tables, in float:
  // largest channel difference from the reference, measured --
  //   props/volume Agreement, 10,000 random cases (5 seeds x 2000, 3.3M
  //     pixels): max 2.25e-5, p99 1.2e-6;
  //   corpus sp-bucky, sp-neghip (128^2): max 2.5e-6, 1.8e-6 (mean 9e-8, 3e-8);
  //   CT head ct-bone, ct-skin, MRI mri at -90,-15,180, 512^2, eps 0: max
  //     7.9e-6, 4.4e-6, 2.6e-6 (mean 2e-8 to 7e-8);
  // so 5e-5, 2.2x the largest. Besides, where a pixel's opacity reaches
  // 1 - eps, float and double can stop it one splat apart (as the ray
  // caster's termination flips): up to eps (1/256 by default) on such pixels,
  // both alphas at the threshold -- 1, 2, 7 of the 262,144 pixels of those
  // three frames at eps 1/256 (max 4.5e-4, 1.8e-3, 2.8e-4), 13 of the random
  // cases' 3.3M (props: label termination_flip, explained). They are what the
  // fraction 0.999 allows (0.0027% at most measured).
  f.tol.abs = 5e-5;
  f.tol.fraction = 0.999;
  return f;
}

Family volume_iso_family() {
  Family f = base(vr::Mode::kIso);
  f.name = "volume_iso";
  f.what = "the isosurface of the trilinear interpolant, ray cast (first crossing, bisection, gradient shading)";
  f.algo = "iso";
  const TypedImpl<Volume> impls[] = {{"reference", ref::volume_iso, 0, {}, {}, false},
                                      // As the volume family's simd row: a slice or a line, the reference.
                                      {"simd", [](const Volume& v, const FrameOptions& o, FrameStats* st) {
                                         return opt::simd::volume_cast_handles(v) ? opt::simd::volume_iso(v, o, st)
                                                                                  : ref::volume_iso(v, o, st);
                                       }}};
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
