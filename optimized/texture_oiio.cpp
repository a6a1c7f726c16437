// lockstep optimized: the texture family's oiio row (optimized/texture_oiio.h).
#include "optimized/texture_oiio.h"

#include <functional>
#include <memory>
#include <vector>

#include "core/error.h"
#include "core/timer.h"
#include "io/oiio.h"

namespace lockstep::opt::oiio {

std::string texture_unsupported(const Params& params) {
  TextureFilterSettings f;
  if (!parse_texture_filter(params.get("filter", "trilinear"), f)) return "";  // check_params says why
  if (f.filter == TextureFilter::area || f.filter == TextureFilter::super || f.filter == TextureFilter::ewa)
    return "OpenImageIO's TextureSystem has no " + f.name + " filter (closest, bilinear, one level, trilinear, anisotropic)";
  return "";
}

namespace {

// The module's texture handle, closed with it.
struct Handle {
  void* h = nullptr;
  ~Handle() {
    if (h) lockstep::oiio::api().texture_close(h);
  }
};

std::shared_ptr<Handle> open_texture(const Texture& tex) {
  auto handle = std::make_shared<Handle>();
  lockstep::oiio::Error err;
  handle->h = lockstep::oiio::api().texture_open(tex, &err);
  if (!handle->h) lockstep::oiio::raise(err);
  return handle;
}

// One frame through an open texture.
Image frame(const Handle& handle, const TextureScene& scene, const FrameOptions& opts, FrameStats* stats) {
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
  const TextureMode mode = f.filter == TextureFilter::point         ? TextureMode::closest
                           : f.filter == TextureFilter::bilinear    ? TextureMode::bilinear
                           : f.filter == TextureFilter::mip_nearest ? TextureMode::one_level
                           : f.filter == TextureFilter::trilinear   ? TextureMode::trilinear
                                                                    : TextureMode::aniso;
  std::vector<float> rgba(4 * s.size());
  lockstep::oiio::Error err;
  if (!lockstep::oiio::api().texture_lookups(handle.h, in, mode, f.n, opts.threads, rgba.data(), &err))
    lockstep::oiio::raise(err);
  Image img = Image::uninitialized(w, h);
  const float bg[4] = {float(scene.background.x), float(scene.background.y), float(scene.background.z), 1};
  for (size_t i = 0; i < size_t(w) * size_t(h); ++i)
    for (int c = 0; c < 4; ++c) img.rgba[4 * i + size_t(c)] = bg[c];
  for (size_t k = 0; k < where.size(); ++k)
    for (int c = 0; c < 4; ++c) img.rgba[4 * where[k] + size_t(c)] = rgba[4 * k + size_t(c)];
  if (opts.progress) opts.progress(1.0);
  if (stats) stats->items = s.size();
  return img;
}

}  // namespace

Image texture_filter(const TextureScene& scene, const FrameOptions& opts, FrameStats* stats) {
  if (std::string why = texture_unsupported(opts.params); !why.empty()) throw InputError(scene.source, 0, why);
  texture_filter_settings(opts.params, scene.source);
  const Stopwatch clock;
  const std::shared_ptr<Handle> handle = open_texture(scene.texture);
  const double made = clock.seconds();
  Image img = frame(*handle, scene, opts, stats);
  if (stats) stats->build_seconds = made;
  return img;
}

std::function<Image(const TextureScene&, const FrameOptions&, FrameStats*)> texture_session(const TextureScene& scene) {
  // The texture made once, on the session's first frame (its build_seconds),
  // as an application makes its .tx once and samples it frame after frame.
  auto handle = std::make_shared<std::shared_ptr<Handle>>();
  const Texture* made_for = &scene.texture;
  return [handle, made_for](const TextureScene& sc, const FrameOptions& o, FrameStats* st) {
    double made = 0;
    if (!*handle || made_for != &sc.texture) {
      if (std::string why = texture_unsupported(o.params); !why.empty()) throw InputError(sc.source, 0, why);
      const Stopwatch clock;
      *handle = open_texture(sc.texture);
      made = clock.seconds();
    }
    Image img = frame(**handle, sc, o, st);
    if (st) st->build_seconds = made;
    return img;
  };
}

}  // namespace lockstep::opt::oiio
