// lockstep registry: the texture-filtering family's row (see core/texture.h for
// the contract and conventions, props/texture/ for the properties and bounds).
#include "registry/texture_row.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>
#include <span>

#include "core/error.h"
#include "core/timer.h"
#include "io/texture_scene.h"
#include "kinds/image_kind.h"
#include "optimized/texture_filter_simd.h"
#include "optimized/tiling.h"
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

double error_target(const Params& p) {
  const std::string s = p.get("error");
  char* end = nullptr;
  const double e = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != 0 || !(e > 0 && e <= 1))
    throw InputError("settings", 0, "error: '" + s + "' is not a number in (0, 1]");
  return e;
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

// error=E: per tile, the cheapest filter whose error stays under E, measured
// on the frame itself. The ladder, cheapest first (the simd row's ns a
// lookup on the study's zone plate; bilinear, mip_nearest, superN and EWA are
// each slower than a ladder filter at least as accurate there, BENCHMARKS.md):
constexpr const char* kErrorLadder[] = {"point", "trilinear", "aniso2", "aniso4", "aniso8", "aniso16"};

// Sample pixels a tile: a grid of kSamplesX x kSamplesY.
constexpr int kSamplesX = 6, kSamplesY = 3;

struct FilterChoice {
  std::string names;             // filter_tiles
  std::map<std::string, int> tiles_of;  // tiles per filter
  int tiles = 0;
  double worst = 0;              // the largest error at a sample among the chosen filters
};

// The error of a value against the yardstick: RMS over R, G and B.
double rgb_rms(const ref::Rgba& a, const ref::Rgba& b) {
  double s = 0;
  for (int c = 0; c < 3; ++c) s += (a[size_t(c)] - b[size_t(c)]) * (a[size_t(c)] - b[size_t(c)]);
  return std::sqrt(s / 3);
}

// Per tile of core/texture.h's plan: 18 sample pixels (a 6 x 3 grid over
// the tile; where some miss the quad, 18 of the tile's pixels that see it,
// evenly spread), the yardstick at each -- area sampling (the simd row's), the average of the
// texels over the pixel's footprint (within the bound props/texture states of
// the pixel's exact box filter: 0.0014 RMS on the study's zone plate) -- and
// each ladder filter's value there by the reference's lookups; the tile gets
// the first filter whose largest sample error is at most E, else area
// sampling itself.
FilterChoice choose_filters(const TextureScene& scene, int width, int height, double target, int threads,
                            const std::function<void(double)>& progress) {
  const TexelMap map = TexelMap::make(scene, width, height);
  const std::vector<Texture> pyramid = ref::build_pyramid(scene.texture);
  const ref::Rgba bg{scene.background.x, scene.background.y, scene.background.z, 1};
  std::vector<TextureFilterSettings> ladder;
  for (const char* name : kErrorLadder) {
    TextureFilterSettings f;
    parse_texture_filter(name, f);
    ladder.push_back(f);
  }
  // Area sampling by the simd row (its interior texels summed unclipped:
  // about 3x the reference's speed; the two agree within 2.4e-7).
  const opt::simd::AreaSampler yardstick(scene, width, height);
  auto sees = [&](int x, int y) {
    double a, b;
    return map.texel_at(x + 0.5, y + 0.5, a, b) && map.on_quad(a, b);
  };
  const int tiles_x = (width + kFilterTileW - 1) / kFilterTileW, tiles_y = (height + kFilterTileH - 1) / kFilterTileH;
  std::vector<const char*> picks(size_t(tiles_x) * size_t(tiles_y));
  std::vector<double> errors(picks.size());
  std::vector<uint8_t> sampled(picks.size());
  opt::parallel_tiles(width, height, kFilterTileW, kFilterTileH, threads, progress, [&](int x0, int y0, int x1, int y1) {
      std::vector<std::pair<int, int>> samples;
      for (int j = 0; j < kSamplesY; ++j)
        for (int i = 0; i < kSamplesX; ++i) {
          const int x = x0 + (2 * i + 1) * (x1 - x0) / (2 * kSamplesX);
          const int y = y0 + (2 * j + 1) * (y1 - y0) / (2 * kSamplesY);
          if (sees(x, y)) samples.emplace_back(x, y);
        }
      if (samples.size() < size_t(kSamplesX * kSamplesY)) {
        std::vector<std::pair<int, int>> all;
        for (int y = y0; y < y1; ++y)
          for (int x = x0; x < x1; ++x)
            if (sees(x, y)) all.emplace_back(x, y);
        if (all.size() > samples.size()) {
          samples.clear();
          const size_t n = std::min<size_t>(kSamplesX * kSamplesY, all.size());
          for (size_t k = 0; k < n; ++k) samples.push_back(all[(2 * k + 1) * all.size() / (2 * n)]);
        }
      }
      const char* pick = samples.empty() ? "point" : "area";  // no pixel sees the quad: nothing to filter
      double err_of_pick = 0;
      if (!samples.empty()) {
        std::vector<ref::Rgba> yard(samples.size());
        for (size_t k = 0; k < samples.size(); ++k) {
          const std::array<float, 4> v = yardstick.at(samples[k].first, samples[k].second);
          yard[k] = {v[0], v[1], v[2], v[3]};
        }
        for (size_t l = 0; l < ladder.size(); ++l) {
          double worst = 0;
          for (size_t k = 0; k < samples.size() && worst <= target; ++k) {
            ref::Rgba c;
            ref::filter_pixel(scene.texture, pyramid, map, ladder[l], samples[k].first, samples[k].second, bg, c);
            worst = std::max(worst, rgb_rms(c, yard[k]));
          }
          if (worst <= target) {
            pick = kErrorLadder[l];
            err_of_pick = worst;
            break;
          }
        }
      }
      const size_t tile = size_t(y0 / kFilterTileH) * size_t(tiles_x) + size_t(x0 / kFilterTileW);
      picks[tile] = pick;
      errors[tile] = err_of_pick;
      sampled[tile] = !samples.empty();
  });
  FilterChoice out;
  for (size_t tile = 0; tile < picks.size(); ++tile) {
    out.names += (out.names.empty() ? "" : " ") + std::string(picks[tile]);
    ++out.tiles;
    if (!sampled[tile]) continue;
    ++out.tiles_of[picks[tile]];
    out.worst = std::max(out.worst, errors[tile]);
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
  f.params.push_back({"error", "E in (0, 1]", "",
                      "instead of filter: per 64x16 tile the cheapest of point, trilinear, aniso2..16 whose error "
                      "(RGB RMS against area sampling) at 9 sample pixels is at most E, else area"});
  f.check_params = [](const Params& p) {
    texture_filter_settings(p, "settings");
    if (p.has("wrap")) wrap_named(p.get("wrap"));
    if (p.has("error")) {
      error_target(p);
      if (p.has("filter")) throw InputError("settings", 0, "error: give filter or error, not both");
    }
  };
  // error=E (choose_filters above): the search is the run's one-shot cost
  // (build time); the frame drawn is the row's own with a filter per tile.
  // The peers cannot take a filter per tile: refused.
  for (FamilyImpl& impl : f.impls)
    impl.run = [run = impl.run, peer = !impl.peer.empty(), name = std::string(impl.name)](
                   const Input& in, const FrameOptions& o, FrameStats* stats) {
      if (!o.params.has("error")) return run(in, o, stats);
      const TextureScene& scene = input_as<TextureScene>(in);
      if (peer)
        throw InputError(scene.source, 0,
                         "error: the " + name + " row cannot draw a filter per tile (use --impl simd or reference)");
      const double target = error_target(o.params);
      const Stopwatch clock;
      // Progress: the search the first half, the frame the second.
      auto half = [&o](double from) {
        return o.progress ? std::function<void(double)>([&o, from](double f) { o.progress(from + f / 2); })
                          : std::function<void(double)>();
      };
      const FilterChoice choice = choose_filters(scene, o.width, o.height, target, o.threads, half(0));
      const double search = clock.seconds();
      FrameOptions fo = o;
      fo.progress = half(0.5);
      fo.params.items.clear();
      for (const auto& [k, v] : o.params.items)
        if (k != "error") fo.params.set(k, v);
      fo.params.set("filter_tiles", choice.names);
      Output out = run(in, fo, stats);
      if (stats) {
        stats->build_seconds += search;
        std::string share;
        for (const char* name : kErrorLadder)
          if (auto it = choice.tiles_of.find(name); it != choice.tiles_of.end())
            share += (share.empty() ? "" : ", ") + std::string(name) + " " + std::to_string(it->second);
        if (auto it = choice.tiles_of.find("area"); it != choice.tiles_of.end())
          share += (share.empty() ? "" : ", ") + std::string("area ") + std::to_string(it->second);
        int sampled = 0;
        for (const auto& [name, n] : choice.tiles_of) sampled += n;
        char tail[200];
        std::snprintf(tail, sizeof tail,
                      " of %d tiles (%d see no quad); largest sample error %.3g (RGB RMS against area sampling)",
                      choice.tiles, choice.tiles - sampled, choice.worst);
        stats->chosen = "filters for error " + o.params.get("error") + ": " + share + tail;
      }
      return out;
    };
  f.properties = {"pyramid", "constant", "agreement", "oracle", "rotation", "tiles"};
  return f;
}

}  // namespace lockstep
