// lockstep registry: the texture-filtering family's row (see core/texture.h for
// the contract and conventions, props/texture/ for the properties and bounds).
#include "registry/texture_row.h"

#include <memory>
#include <span>

#include "core/error.h"
#include "io/texture_scene.h"
#include "kinds/image_kind.h"
#include "optimized/texture_filter_simd.h"
#include "optimized/texture_oiio.h"
#include "optimized/raster_llvmpipe.h"
#include "reference/texture_filter.h"

namespace lockstep {

namespace {

// Accuracy: not against an oracle of its own (each filter is its own
// approximation of the pixel's box filter, props/texture/ measures how far);
// agreement of the simd row with the reference: the family's tolerance.
constexpr TypedImpl<TextureScene> kImpls[] = {
    {"reference", ref::texture_filter, 0, {}, {}, false},
    {"simd", opt::simd::texture_filter, 0},
    // OpenImageIO's TextureSystem: its own level of detail and anisotropy,
    // and float texture coordinates. Against the reference where it computes
    // the same (point, bilinear; the corpus compares no other filter, the
    // study judges those against the oracle): float s, t move a point near a
    // texel edge into the neighbour, measured 7 pixels of 65536 (0.011%) on
    // the 256^2 zone plate, 4 of them by more than 0.5; bilinear at most
    // 2.1e-4. So: 1/255 on all but 0.1% of the pixels, and no hard limit below
    // a whole texel's contrast.
    {"oiio", opt::oiio::texture_filter, 0, {}, "OpenImageIO TextureSystem", true, opt::oiio::texture_unsupported,
     Tolerance{1.0 / 255, 0.999, 1.0}},
};

Input load(const std::string& path) {
  TextureScene s = read_texture_scene(path);
  const int w = s.width, h = s.height;
  const Vec3 bg = s.background;
  return make_input<TextureScene>(std::move(s), path, w, h, bg);
}

Wrap wrap_named(const std::string& w) {
  if (w == "repeat") return Wrap::repeat;
  if (w == "clamp") return Wrap::clamp;
  if (w == "mirror") return Wrap::mirror;
  throw InputError("settings", 0, "wrap: '" + w + "' is not repeat, clamp or mirror");
}

// The scene with the texture and wrap mode the command line names in place
// of its own (a texture file's path is the caller's, relative to the
// working directory).
Input load_with(const std::string& path, const Params& params) {
  TextureScene s = read_texture_scene(path);
  const Wrap wrap = s.texture.wrap;
  if (params.has("texture")) {
    s.texture = texture_from_words(params.get("texture"), ".", "--texture", 0);
    s.texture.wrap = wrap;
  }
  if (params.has("wrap")) s.texture.wrap = wrap_named(params.get("wrap"));
  const int w = s.width, h = s.height;
  const Vec3 bg = s.background;
  return make_input<TextureScene>(std::move(s), path, w, h, bg);
}

// The receding zone-plate plane of issue #32's peer figures: a 1024^2
// zone plate (K = 1: Nyquist at the edges' midpoints), tiled 16 x 64 times
// over a 40 x 160 plane seen from 1 above it, at 1024^2 pixels.
TextureScene bench_plane() {
  TextureScene s;
  s.texture = procedural_texture("zoneplate 1024", "bench", 0);
  s.origin = {-20, 0, 2};
  s.edge_s = {40, 0, 0};
  s.edge_t = {0, 0, -160};
  s.repeat_u = 16;
  s.repeat_v = 64;
  s.view.from = {0, 1, 3};
  s.view.at = {0, 0.6, 0};
  s.view.up = {0, 1, 0};
  s.view.angle = 60;
  s.view.hither = 1e-3;
  s.background = {0.5, 0.6, 0.8};
  s.width = s.height = 1024;
  s.source = "zoneplate-plane";
  return s;
}

std::vector<BenchInput> bench_inputs() {
  std::vector<BenchInput> out;
  const auto plane = std::make_shared<const TextureScene>(bench_plane());
  for (const char* filter : {"point", "bilinear", "trilinear", "aniso16", "ewa", "super4", "area"}) {
    BenchInput b;
    b.name = std::string("zoneplate-plane-") + filter;
    b.input.value = plane;
    b.input.source = "zoneplate-plane";
    b.input.width = b.input.height = 1024;
    b.input.background = plane->background;
    b.width = b.height = 1024;
    b.params.set("filter", filter);
    b.heavy_for_reference = true;
    out.push_back(std::move(b));
  }
  return out;
}

}  // namespace

Family texture_family() {
  Family f;
  f.name = "texture";
  f.what = "texture filtering on a plane under perspective: point, bilinear, area, supersampling, mipmaps, anisotropic, EWA";
  f.input = "a texture scene (.texscene)";
  f.unit = "lookups";
  f.verb = "filter";
  f.extension = ".texscene";
  f.algo = "texture";  // `lockstep texture` (app/texture.cpp)
  f.default_impl = "simd";
  f.kind = &image_kind();
  // Agreement of a row with the reference, per channel: the simd row computes
  // in float where the reference computes in double (props/texture/ bounds it
  // per filter).
  f.tol.abs = 1.0 / 255;
  f.tol.fraction = 0.999;
  f.load = load;
  f.load_with = load_with;
  f.impls = erase_all<TextureScene>(kImpls);
  // OpenImageIO keeps its made texture and TextureSystem across the frames of
  // a session (the benchmarks' warm frames), as an application does.
  for (FamilyImpl& impl : f.impls)
    if (impl.name == "oiio")
      impl.session = [](const Input& in, const FrameOptions&, RunResources&) {
        auto run = opt::oiio::texture_session(input_as<TextureScene>(in));
        return [run](const Input& in, const FrameOptions& o, FrameStats* st) mutable {
          return make_output<Image>(run(input_as<TextureScene>(in), o, st));
        };
      };
  // Mesa's llvmpipe (OSMesa), where its module was built: GL's own sampler.
  // Against the reference where both compute the same (point, bilinear):
  // its texture coordinates are interpolated in float per fragment (point:
  // 8 of 65536 pixels of the 256^2 zone plate in the neighbouring texel) and
  // its bilinear weights have 8 bits (bilinear: 105 pixels, 0.16%, over
  // 1/255, at most 0.012). So: 1/255 on all but 0.4% (verify measured 0.26%), no hard limit below a
  // texel's contrast. Its mipmapped filters are judged by the oracle.
  if (opt::llvmpipe::available()) {
    const TypedImpl<TextureScene> gl{"llvmpipe", opt::llvmpipe::texture_filter, 0, {}, "Mesa llvmpipe (OSMesa)",
                                     true, opt::llvmpipe::texture_unsupported, Tolerance{1.0 / 255, 0.996, 1.0}};
    f.impls.push_back(erase(gl));
    // A session keeps the context and the uploaded texture, as an application does.
    f.impls.back().session = [](const Input&, const FrameOptions&, RunResources&) {
      auto gl_session = std::make_shared<opt::llvmpipe::TextureSession>();
      return [gl_session](const Input& in, const FrameOptions& o, FrameStats* st) {
        return make_output<Image>(gl_session->frame(input_as<TextureScene>(in), o, st));
      };
    };
  }
  f.peer_rows.push_back(module_peer("llvmpipe", opt::llvmpipe::available(), opt::llvmpipe::version(),
                                    "lockstep_peer_llvmpipe.so",
                                    "install libosmesa6-dev (scripts/setup.sh) and re-run cmake"));
  f.bench = bench_inputs;
  f.params = {{"filter", kTextureFilterNames, "trilinear",
               "the texture filter (superN: N x N samples a pixel; anisoN: at most N probes; ewa: eccentricity 8)"},
              {"texture", "\"checker N CELLS\"|\"zoneplate N [K]\"|\"noise N SEED\"|\"file PATH [srgb|linear]\"", "",
               "the texture in place of the scene's (a .texscene texture line's words)"},
              {"wrap", "repeat|clamp|mirror", "", "the wrap mode in place of the scene's"}};
  f.check_params = [](const Params& p) {
    texture_filter_settings(p, "settings");
    if (p.has("wrap")) wrap_named(p.get("wrap"));
  };
  f.properties = {"pyramid", "constant", "agreement", "oracle", "rotation"};
  return f;
}

}  // namespace lockstep
