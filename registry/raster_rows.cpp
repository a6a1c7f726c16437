// lockstep registry: the raster families' rows (see registry/raster_rows.h).
#include "registry/raster_rows.h"

#include <algorithm>
#include <string>

#include "core/error.h"
#include "kinds/image_kind.h"
#include "optimized/painter_simd.h"
#include "optimized/zbuffer/zbuffer_simd.h"
#include "optimized/zbuffer/zbuffer_llvmpipe.h"
#include "optimized/raster_llvmpipe.h"
#include "reference/painter.h"
#include "reference/raster.h"
#include "reference/scanline.h"
#include "optimized/scanline_simd.h"
#include "registry/loaders.h"

namespace lockstep {

namespace {

// The SPD scenes of issue #7 that are present, at 1024 x 1024: flat shading
// (what the llvmpipe peer draws too) for every scene, and per-sample Phong for two.
std::vector<BenchInput> spd_frames() {
  std::vector<BenchInput> out;
  auto add = [&](const char* name, const char* shading) {
    std::optional<Input> in = load_spd(name);
    if (!in) return;
    BenchInput b;
    b.name = std::string(name) + "/" + shading;
    b.input = std::move(*in);
    b.params.set("shading", shading);
    const Scene& s = input_as<Scene>(b.input);
    b.width = b.height = 1024;
    b.counters = {{"triangles", double(s.triangle_count())}, {"spheres", double(s.sphere_count())}};
    b.heavy_for_reference = false;  // the reference draws 1024^2 in well under a second: same size, same work
    out.push_back(std::move(b));
  };
  for (const char* name : {"tetra-3", "mount-3", "gears-2", "teapot-2", "sombrero-2", "sombrero-3", "jacks-2-tess", "lattice-2-tess",
                           "tree-2-tess", "rings-1-tess", "balls-3", "shells-1"})
    add(name, "flat");
  for (const char* name : {"sombrero-2", "balls-3"}) add(name, "phong");
  // Shadows (issue #22): Phong with shadow maps (1024^2 cube faces, the
  // default) and with shadow volumes (z-fail), 512 x 512; only the z-buffer's
  // reference and simd rows draw them (the others are skipped, unsupported).
  for (const char* name : {"teapot-2", "gears-2"})
    for (const char* shadows : {"map", "volume"}) {
      const size_t before = out.size();
      add(name, "phong");
      if (out.size() == before) continue;  // the scene is not present
      BenchInput& b = out.back();
      b.name += std::string("-shadows-") + shadows;
      b.params.set("shadows", shadows);
      if (std::string(shadows) == "volume") b.params.set("zfail", "1");
      b.width = b.height = 512;
    }
  return out;
}

// Shadows (issue #22): which rows draw which. The reference and simd z-buffers
// draw shadow maps and shadow volumes; every other row says so (verify and the
// benchmarks skip it, a render exits 2) rather than drawing an unshadowed image.
std::string shadow_why(const Params& params, bool map, bool volume) {
  try {
    const ShadowMode m = raster_settings(params, "settings").shadows;
    if (m == ShadowMode::kMap && !map)
      return "shadows=map: this row draws no shadow maps (zbuffer --impl reference or simd)";
    if (m == ShadowMode::kVolume && !volume)
      return "shadows=volume: only zbuffer --impl reference or simd counts shadow-volume stencils";
  } catch (const InputError&) {
    // bad settings are the family's to report
  }
  return "";
}
std::string draws_no_shadows(const Params& p) { return shadow_why(p, false, false); }
std::string llvmpipe_unsupported(const Params& p) {
  std::string why = draws_no_shadows(p);
  return why.empty() ? opt::llvmpipe::unsupported(p) : why;
}

// Every row of f but the reference and simd z-buffers refuses shadows, through
// unsupported (unless it has its own, which must then say it too) and its run,
// naming the scene.
void refuse_shadows(Family& f) {
  for (FamilyImpl& impl : f.impls) {
    const bool zbuffer = f.name == "zbuffer";
    if (zbuffer && (impl.name == "reference" || impl.name == "simd")) continue;
    auto why = draws_no_shadows;
    if (!impl.unsupported) impl.unsupported = why;
    const std::string who = std::string(f.name) + " --impl " + std::string(impl.name) + ": ";
    impl.run = [run = std::move(impl.run), who, why](const Input& in, const FrameOptions& o, FrameStats* st) {
      if (const std::string w = why(o.params); !w.empty()) throw InputError(input_as<Scene>(in).source, 0, who + w);
      return run(in, o, st);
    };
  }
}

// A raster family over NFF scenes: the shared loader, settings and checks.
Family raster_family(std::string_view name, std::string_view what, std::string_view algo) {
  Family f;
  f.name = name;
  f.what = what;
  f.algo = algo;
  f.input = "an NFF scene (.nff)";
  f.unit = "triangles";
  f.verb = "draw";
  f.extension = ".nff";
  f.default_impl = "simd";
  f.sized = true;
  f.kind = &image_kind();
  f.load = load_nff;
  f.params = raster_params();
  f.check_params = [](const Params& p) { raster_settings(p, "settings"); };
  f.bench = spd_frames;
  return f;
}

}  // namespace

Family zbuffer_family() {
  Family f = raster_family("zbuffer", "z-buffer rasterization (Catmull) with flat/Gouraud/Phong/toon shading",
                                "zbuffer");
  // Colour within 1/255 on 99.9% of the pixels, as ray casting: pixels differ
  // where two surfaces are within the depth format's resolution (the optimized
  // z-buffers compute depth in float) and on silhouettes of supersampled pixels.
  f.tol.abs = 1.0 / 255;
  f.tol.fraction = 0.999;
  std::vector<TypedImpl<Scene>> impls = {
      {"reference", ref::zbuffer, 0, {}, {}, false},
      // Coverage bit-identical to the reference (same snapped mesh, same exact
      // edge functions); depth in float (ties may break the other way where two
      // surfaces are within float resolution), shading in float: accuracy 1/255.
      {"simd", opt::simd::zbuffer, 1.0 / 255},
  };
  // Mesa's llvmpipe through OSMesa (optimized/raster_llvmpipe.cpp), only where
  // the build found OSMesa; flat and Gouraud, one sample per pixel. It draws
  // view_scene's triangles (the same tessellation, culling and lighting) from
  // their world positions through its own float pipeline, 8 subpixel bits and a
  // 24-bit depth buffer, into a float colour buffer. Measured against the
  // reference (bench/timing/llvmpipe_check.cpp agree, tetra-3, mount-3, gears-2,
  // teapot-2, sombrero-2 at 512^2 and 1024^2, flat and Gouraud):
  //   coverage  identical on all 20 frames. On random triangle soups
  //             (LlvmpipeCoverage, 1000 cases) 4 of 367462 pixels differ
  //             (1.1e-5; an earlier generator: 10 of 346047, 2.9e-5, 95% upper
  //             5.3e-5): a vertex whose exact position is within float
  //             rounding of a half-step of the 1/256 px grid snaps to the other
  //             side, and a pixel centre within that step of the edge changes
  //             sides. Measured again (issue #20; deep mode, three seeds):
  //             3 of 362004, 3 of 350035, 6 of 354606 pixels; with the 4 of
  //             367462 above, 16 of 1434107 = 1.1e-5; a 20000-case run
  //             (seed 10361792614855094469) 111 of 7172091 = 1.55e-5; all
  //             together 127 of 8606198 = 1.48e-5. Stated rate: 3e-5 of the
  //             pixels (`coverage`, per pixel), the measured rate with a
  //             margin of 2; the driver fails a run over it, and a long run
  //             whose rate falls below a quarter of it (the cap would hide a
  //             regression: that 20000-case run fails against the old 1e-4,
  //             111 under its floor of 119).
  //   colour    where a pixel centre lies within a snapping step of an edge
  //             between two triangles, the other triangle may win it: up to
  //             2.7e-5 of the covered pixels (sombrero-2 512^2), each off by the
  //             two triangles' difference (up to 1.0 in gears-2 at 1024^2:
  //             over the family's hard_abs 0.5, so a corpus case comparing
  //             llvmpipe there would need its own limit); once (gears-2
  //             1024^2, 0.16) a third triangle, a sliver along the edge, that
  //             no neighbour shows; elsewhere within 2.1e-3 (interpolation in
  //             float, and neighbours' colours within 1/255).
  //   depth     relative eye-z error up to 3.9e-4 (tetra-3 512^2), on slivers
  //             seen nearly edge-on, where each snap moves the plane by dz/dy
  //             times the snap (the exact depth lies between the two); 24-bit
  //             quantisation is far below that.
  //   Tessellated scenes at 512^2 (balls-3, shells-1, jacks-2-tess,
  //   rings-1-tess; sub-pixel triangles): coverage differs on at most 1 pixel
  //   (jacks-2-tess), another triangle wins up to 2.8e-3 of the covered pixels
  //   (jacks-2-tess flat; 7.9e-4 on shells-1), off by up to 0.55 (balls-3
  //   Gouraud, over hard_abs), and depth by up to 2.0e-3 relative.
  if (opt::llvmpipe::available())
    impls.push_back({"llvmpipe", opt::llvmpipe::zbuffer, 0, {"coverage", 3e-5, "pixel"}, "Mesa llvmpipe (OSMesa)",
                     true, llvmpipe_unsupported});
  f.impls = erase_all<Scene>(impls);
  f.peer_rows.push_back(module_peer(
      "llvmpipe", opt::llvmpipe::available(),
      opt::llvmpipe::available() ? "OSMesa: " + opt::llvmpipe::version() : "", "lockstep_peer_llvmpipe.so",
      "scripts/setup.sh installs libosmesa6-dev"));
  refuse_shadows(f);
  // The benchmarks time llvmpipe with its context kept across frames, as an
  // application keeps its GL context (the first frame, context and shader
  // compilation, is their first_ms); `render` and `verify` draw one frame.
  for (FamilyImpl& impl : f.impls)
    if (impl.name == "llvmpipe")
      impl.session = [](const Input&, const FrameOptions&, RunResources&) {
        auto session = std::make_shared<opt::llvmpipe::Session>();
        return [session](const Input& in, const FrameOptions& o, FrameStats* stats) {
          return make_output<Image>(session->zbuffer(input_as<Scene>(in), o, stats));
        };
      };
  // The simd row keeps its frame buffer across frames, as an application
  // keeps its framebuffer: allocated and touched when the session starts (the
  // benchmarks' session_ms), drawn into frame after frame. Its first frame is
  // then the cold first frame of issue #21 without the 20 MiB of first-touch
  // page faults of a fresh 1024^2 frame (7-10 ms on the 2-core VM, against a
  // 2.4 ms warm frame); `render` and `verify` draw one frame into a fresh Image.
  for (FamilyImpl& impl : f.impls)
    if (impl.name == "simd")
      impl.session = [](const Input&, const FrameOptions& o, RunResources&) {
        auto frame = std::make_shared<Image>(opt::simd::new_frame(o.width, o.height));
        return [frame](const Input& in, const FrameOptions& o, FrameStats* stats) mutable {
          // A frame the caller still holds is not written: a new buffer then.
          if (frame.use_count() > 1) frame = std::make_shared<Image>();
          opt::simd::zbuffer_into(input_as<Scene>(in), o, stats, *frame);
          Output out;
          out.value = frame;  // shared with the session: take_output copies it
          return out;
        };
      };
  // props/raster: the parts that test the z-buffer (the other raster families
  // are checked against it).
  f.properties = {"cross_check", "culling", "render_agree", "supersampling", "visibility", "llvmpipe", "hidden",
                  "shadow_volume", "shadow_map", "first_drawn"};
  return f;
}

Family scanline_family() {
  Family f = raster_family("scanline",
                                "scanline z-buffer (Watkins; edge table, active edges, incremental spans), "
                                "flat/Gouraud/Phong/toon shading",
                                "scanline");
  // The same samples and fill rule as the z-buffer (coverage equal sample for
  // sample, props/raster/scanline.cpp); depth and attributes are incremental,
  // so colours differ from the z-buffer's by the drift, and the visible surface
  // only where two surfaces are within the drift of each other.
  f.tol.abs = 1.0 / 255;
  f.tol.fraction = 0.999;
  const TypedImpl<Scene> impls[] = {
      {"reference", ref::scanline, 0, {}, {}, false},
      // Visibility by the same scanlines (coverage identical to the reference's),
      // depth in float lanes; shading by the simd z-buffer's float kernel: 1/255.
      {"simd", opt::simd::scanline, 1.0 / 255},
  };
  f.impls = erase_all<Scene>(impls);
  refuse_shadows(f);
  // The simd row's session keeps its frame and visibility buffers (as the
  // z-buffer's, above).
  for (FamilyImpl& impl : f.impls)
    if (impl.name == "simd")
      impl.session = [](const Input& in, const FrameOptions& o, RunResources&) {
        auto frame = std::make_shared<Image>(opt::simd::new_frame(o.width, o.height));
        auto visible = std::make_shared<opt::simd::VisibleBuffer>(opt::simd::visible_buffer(input_as<Scene>(in), o));
        return [frame, visible](const Input& in, const FrameOptions& o, FrameStats* stats) mutable {
          if (frame.use_count() > 1) frame = std::make_shared<Image>();
          opt::simd::scanline_into(input_as<Scene>(in), o, stats, *frame, *visible);
          Output out;
          out.value = frame;
          return out;
        };
      };
  f.properties = {"cross_check", "supersampling", "scanline", "interpolation", "first_drawn"};
  return f;
}

Family painter_family() {
  Family f = raster_family("painter",
                                "painter's algorithm (depth sort, Newell-Newell-Sancha tests, cycles and "
                                "interpenetrations reported; --split resolves them)",
                                "painter");
  // Judged against the z-buffer's tolerance: where the order is right the
  // painter draws the z-buffer's fragments, bit for bit; simd paints the same
  // plan and agrees with the reference bit for bit (props/raster/painter.cpp).
  f.tol.abs = 1.0 / 255;
  f.tol.fraction = 0.999;
  const TypedImpl<Scene> impls[] = {
      {"reference", ref::painter, 0, {}, {}, false},
      {"simd", opt::simd::painter, 0},
  };
  f.impls = erase_all<Scene>(impls);
  refuse_shadows(f);
  f.properties = {"painter"};
  f.default_impl = "simd";
  return f;
}

}  // namespace lockstep
