// lockstep optimized: the texture family's oiio row (optimized/texture_oiio.h).
#include "optimized/texture_oiio.h"

#include <vector>

#include "core/error.h"
#include "io/oiio.h"

namespace lockstep::opt::oiio {

std::string texture_unsupported(const Params& params) {
  TextureFilterSettings f;
  if (!parse_texture_filter(params.get("filter", "trilinear"), f)) return "";  // check_params says why
  if (f.filter == TextureFilter::area || f.filter == TextureFilter::super || f.filter == TextureFilter::ewa)
    return "OpenImageIO's TextureSystem has no " + f.name + " filter (closest, bilinear, one level, trilinear, anisotropic)";
  return "";
}

Image texture_filter(const TextureScene& scene, const FrameOptions& opts, FrameStats* stats) {
  const TextureFilterSettings f = texture_filter_settings(opts.params, scene.source);
  if (std::string why = texture_unsupported(opts.params); !why.empty()) throw InputError(scene.source, 0, why);
  const TexelMap map = TexelMap::make(scene, opts.width, opts.height);
  const int w = opts.width, h = opts.height;
  // The footprints, in OpenImageIO's units (texel coordinates over the size).
  std::vector<float> s, t, dsdx, dtdx, dsdy, dtdy;
  std::vector<size_t> where;
  const double iw = 1.0 / scene.texture.width, ih = 1.0 / scene.texture.height;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double a, b;
      if (!map.texel_at(x + 0.5, y + 0.5, a, b) || !map.on_quad(a, b)) continue;
      double dadx, dbdx, dady, dbdy;
      map.derivatives(x + 0.5, y + 0.5, dadx, dbdx, dady, dbdy);
      s.push_back(float(a * iw));
      t.push_back(float(b * ih));
      dsdx.push_back(float(dadx * iw));
      dtdx.push_back(float(dbdx * ih));
      dsdy.push_back(float(dady * iw));
      dtdy.push_back(float(dbdy * ih));
      where.push_back(size_t(y) * size_t(w) + size_t(x));
    }
  lockstep::oiio::TextureLookups in{s.data(), t.data(), dsdx.data(), dtdx.data(), dsdy.data(), dtdy.data(), s.size()};
  using lockstep::oiio::TextureMode;
  const TextureMode mode = f.filter == TextureFilter::point       ? TextureMode::closest
                           : f.filter == TextureFilter::bilinear  ? TextureMode::bilinear
                           : f.filter == TextureFilter::mip_nearest ? TextureMode::one_level
                           : f.filter == TextureFilter::trilinear ? TextureMode::trilinear
                                                                  : TextureMode::aniso;
  std::vector<float> rgba(4 * s.size());
  double make_seconds = 0;
  lockstep::oiio::Error err;
  if (!lockstep::oiio::api().texture(scene.texture, in, mode, f.n, opts.threads, rgba.data(), &make_seconds, &err))
    lockstep::oiio::raise(err);
  Image img = Image::uninitialized(w, h);
  const float bg[4] = {float(scene.background.x), float(scene.background.y), float(scene.background.z), 1};
  for (size_t i = 0; i < size_t(w) * size_t(h); ++i)
    for (int c = 0; c < 4; ++c) img.rgba[4 * i + size_t(c)] = bg[c];
  for (size_t k = 0; k < where.size(); ++k)
    for (int c = 0; c < 4; ++c) img.rgba[4 * where[k] + size_t(c)] = rgba[4 * k + size_t(c)];
  if (opts.progress) opts.progress(1.0);
  if (stats) {
    stats->items = s.size();
    stats->build_seconds = make_seconds;
  }
  return img;
}

}  // namespace lockstep::opt::oiio
