// lockstep core: the raster families' settings (core/raster.h),
// read from a family's Params (CLI `--shading phong`, corpus `shading=phong`).
#include <cmath>
#include <cstdlib>
#include <string>

#include "core/error.h"
#include "core/param_values.h"
#include "core/raster.h"

namespace lockstep {

namespace {

constexpr std::string_view kShadings = "flat|gouraud|phong|blinn|toon";
constexpr std::string_view kCulls = "world|projection|none";
constexpr std::string_view kGrids = "regular|rotated";
constexpr std::string_view kDepths = "float|reversed|fixed24|double";
constexpr std::string_view kInterps = "perspective|affine";
constexpr std::string_view kHidden = "skip|draw";
constexpr std::string_view kOrders = "auto|mesh|reverse";
constexpr std::string_view kShadows = "none|map|volume";

}  // namespace

std::vector<ParamSpec> raster_params() {
  return {
      {"shading", kShadings, "phong", "flat: per polygon; gouraud: per vertex; phong/blinn: per sample; toon: bands"},
      {"cull", kCulls, "world", "back-face culling (NFF sidedness: transmissive polygons are two-sided)"},
      {"silhouette", "", "", "draw silhouettes black (|N.V| < 0.2 per sample)", true},
      {"spp", "1, 4, 9, ... 256 (n x n)", "1", "samples per pixel, box filtered"},
      {"grid", kGrids, "regular", "sample pattern for spp > 1"},
      {"split", "", "", "painter: split polygons to resolve cycles and interpenetrations", true},
      {"tess_error", "pixels, 0.01..16", "0.25", "sphere and cone tessellation: silhouette error bound"},
      {"depth", kDepths, "float", "what the z-buffer stores and compares"},
      {"interp", kInterps, "perspective", "attribute interpolation across triangles"},
      {"hidden", kHidden, "skip",
       "simd z-buffer: leave out spheres and triangles provably behind nearer spheres (same image)"},
      {"order", kOrders, "auto",
       "simd z-buffer: tiles draw in mesh order or reversed, ties then winning (auto: front to back "
       "where the mesh comes back to front; same image)"},
      {"shadows", kShadows, "none",
       "shadows of point lights: map (shadow maps, one cube per light; needs shading phong|blinn), "
       "volume (shadow volumes, stencil counts; zbuffer --impl reference only)"},
      {"bias", "world units, 0..1e6", "0", "shadows=map: constant depth bias (distance from the light)"},
      {"slope_bias", "texels, 0..1e3", "1",
       "shadows=map: slope-scaled bias, texel widths times tan(angle between normal and light)"},
      {"map_size", "texels, 16..4096", "1024", "shadows=map: cube-face resolution (--map-size)"},
      {"pcf", "0, 1, 3, 5, 7, 9", "1", "shadows=map: percentage-closer filtering over pcf x pcf texels (0, 1: off)"},
      {"zfail", "", "", "shadows=volume: z-fail with capped volumes (right with the eye in shadow; default z-pass)",
       true},
  };
}

RasterSettings raster_settings(const Params& params, const std::string& source) {
  RasterSettings s;
  for (const auto& [name, value] : params.items) {
    if (name == "shading") {
      s.shading = Shading(param_choice(source, name, value, kShadings));
    } else if (name == "cull") {
      s.cull = CullMode(param_choice(source, name, value, kCulls));
    } else if (name == "silhouette") {
      s.silhouette = param_flag(source, name, value);
    } else if (name == "spp") {
      const double spp = param_number(source, name, value, 1, 256);
      const int n = int(std::lround(std::sqrt(spp)));
      if (spp != std::floor(spp) || n * n != int(spp))
        throw InputError(source, 0, "spp: '" + value + "' is not a square (1, 4, 9, 16, ... 256: an n x n grid)");
      s.spp = int(spp);
    } else if (name == "grid") {
      s.grid = SampleGrid(param_choice(source, name, value, kGrids));
    } else if (name == "split") {
      s.split = param_flag(source, name, value);
    } else if (name == "tess_error") {
      s.tess_error = param_number(source, name, value, 0.01, 16);
    } else if (name == "depth") {
      s.depth = DepthFormat(param_choice(source, name, value, kDepths));
    } else if (name == "interp") {
      s.perspective = param_choice(source, name, value, kInterps) == 0;
    } else if (name == "order") {
      s.order = DrawOrder(param_choice(source, name, value, kOrders));
    } else if (name == "hidden") {
      s.skip_hidden = param_choice(source, name, value, kHidden) == 0;
    } else if (name == "shadows") {
      s.shadows = ShadowMode(param_choice(source, name, value, kShadows));
    } else if (name == "zfail") {
      s.zfail = param_flag(source, name, value);
    } else if (name == "bias") {
      s.bias = param_number(source, name, value, 0, 1e6);
    } else if (name == "slope_bias") {
      s.slope_bias = param_number(source, name, value, 0, 1e3);
    } else if (name == "map_size") {
      const double n = param_number(source, name, value, 16, 4096);
      if (n != std::floor(n)) throw InputError(source, 0, "map_size: '" + value + "' is not a whole number of texels");
      s.map_size = int(n);
    } else if (name == "pcf") {
      s.pcf = param_choice(source, name, value, "0|1|2|3|4|5|6|7|8|9");
      if (s.pcf > 1 && s.pcf % 2 == 0)
        throw InputError(source, 0, "pcf: '" + value + "' is not 0, 1 (off) or an odd kernel width 3, 5, 7, 9");
    } else {
      std::string known;
      for (const ParamSpec& p : raster_params()) known += (known.empty() ? "" : ", ") + std::string(p.name);
      throw InputError(source, 0, "unknown setting '" + name + "' (known: " + known + ")");
    }
  }
  return s;
}

RasterSettings frame_settings(const Scene& scene, const FrameOptions& opts) {
  const RasterSettings s = raster_settings(opts.params, scene.source);
  const double samples = double(opts.width) * opts.height * s.spp;
  if (samples > double(1 << 25))
    throw InputError(scene.source, 0,
                     "size x spp is " + std::to_string(int64_t(samples)) + " samples; at most 33554432 (2^25)");
  return s;
}

}  // namespace lockstep
