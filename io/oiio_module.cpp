// lockstep io: every OpenImageIO call, built as the module lockstep_oiio.so
// (see io/oiio.h: why, and the table it exports). The code is what
// io/image_io.cpp, io/layers.cpp, kinds/image_metrics.cpp, kinds/image_kind.cpp,
// app/verify_case.cpp and optimized/composite_oiio.cpp ran before they opened
// it, unchanged but for how errors leave: each table function catches what its
// body throws and hands it back as an oiio::Error. Nothing here calls into
// lockstep's libraries (linked with --no-undefined against OpenImageIO only):
// what it uses of core is header-only (Image, Layer, InputError).
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/oiioversion.h>
#include <OpenImageIO/texture.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <new>
#include <sstream>
#include <thread>
#include <vector>

#include "core/error.h"
#include "io/oiio.h"
#include "core/quiet_stderr.h"

namespace lockstep::oiio {

namespace {

// Runs body; false with *err filled when it throws.
template <class Body>
bool guarded(Error* err, Body&& body) {
  try {
    body();
    return true;
  } catch (const InputError& e) {
    *err = {Error::Kind::input, e.file(), e.line(), e.message()};
  } catch (const std::bad_alloc&) {
    *err = {Error::Kind::out_of_memory, {}, 0, "out of memory"};
  } catch (const std::exception& e) {
    *err = {Error::Kind::other, {}, 0, e.what()};
  }
  return false;
}

// ---------------------------------------------------------------- images (io/image_io.cpp)

Image read_image_body(const std::string& path) {
  const QuietStderr quiet;  // libpng's own lines; the error comes back through OIIO
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    std::string why = OIIO::geterror();
    if (!std::filesystem::exists(path)) why = "no such file";
    throw InputError(path, 0, "cannot read image: " + why);
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw InputError(path, 0, "image has no pixels");
  const int nc = spec.nchannels;
  std::vector<float> buf(size_t(spec.width) * size_t(spec.height) * size_t(nc));
  if (!in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, buf.data()))
    throw InputError(path, 0, "cannot read image: " + in->geterror());
  Image img(spec.width, spec.height);
  for (size_t i = 0; i < size_t(spec.width) * size_t(spec.height); ++i) {
    const float* s = &buf[i * size_t(nc)];
    float* d = &img.rgba[i * 4];
    d[0] = s[0];
    d[1] = nc >= 3 ? s[1] : s[0];
    d[2] = nc >= 3 ? s[2] : s[0];
    d[3] = nc == 4 ? s[3] : (nc == 2 ? s[1] : 1.0f);
  }
  return img;
}

void write_image_body(const Image& image, const std::string& path,
                      const std::string& exr_compression) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  // Keep the extension on the temporary name: OIIO picks the format from it.
  const fs::path tmp = target.parent_path() /
                       (".tmp-" + std::to_string(::getpid()) + "-" + target.filename().string());
  auto out = OIIO::ImageOutput::create(path);
  if (!out)
    throw InputError(path, 0, "cannot write image: unknown format (" + OIIO::geterror() + ")");
  // 8-bit formats get the values clamped by OIIO; float formats keep them.
  OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::FLOAT);
  const std::string ext = target.extension().string();
  if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".ppm")
    spec.set_format(OIIO::TypeDesc::UINT8);
  if (ext == ".exr") spec.attribute("compression", exr_compression);
  bool ok =
      out->open(tmp.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, image.rgba.data());
  ok = out->close() && ok;
  std::string why = out->geterror();
  std::error_code ec;
  if (ok) fs::rename(tmp, target, ec);
  if (!ok || ec) {
    fs::remove(tmp, ec);
    throw InputError(path, 0, "cannot write image: " + (why.empty() ? ec.message() : why));
  }
}

// ---------------------------------------------------------------- layers (io/layers.cpp)

std::string channel_list(const OIIO::ImageSpec& spec) {
  std::string s;
  for (int c = 0; c < spec.nchannels; ++c) {
    if (c) s += ',';
    s += c < int(spec.channelnames.size()) ? spec.channelnames[size_t(c)] : "?";
  }
  return s;
}

// The index of the channel called `name` (case-insensitive), or -1.
int find_channel(const OIIO::ImageSpec& spec, const char* name) {
  for (int c = 0; c < int(spec.channelnames.size()); ++c)
    if (OIIO::Strutil::iequals(spec.channelnames[size_t(c)], name)) return c;
  return -1;
}

const char* channel_name(int c) {
  static constexpr const char* kNames[4] = {"R", "G", "B", "A"};
  return c >= 0 && c < 4 ? kNames[c] : "?";
}

Layer read_layer_body(const std::string& path, std::optional<Alpha> alpha_override) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, 0, "cannot read layer: no such file");
  if (fs::is_directory(path, ec)) throw InputError(path, 0, "cannot read layer: is a directory");
  // Ask OIIO for the file's own values: without this config it premultiplies
  // straight-alpha files (PNG, unassociated TIFF) while reading them.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  const QuietStderr quiet;  // libpng's own lines; the error comes back through OIIO
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) throw InputError(path, 0, "cannot read layer: " + OIIO::geterror());
  const OIIO::ImageSpec spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
    throw InputError(path, 0, "layer has no pixels");
  if (int64_t(spec.width) * int64_t(spec.height) > (int64_t(1) << 28))
    throw InputError(path, 0,
                     "layer is too large (" + std::to_string(spec.width) + "x" +
                         std::to_string(spec.height) + "; at most 2^28 pixels)");
  const int nc = spec.nchannels;
  int ca = spec.alpha_channel;
  if (ca < 0) ca = find_channel(spec, "A");
  if (ca < 0 || nc < 2)
    throw InputError(path, 0,
                     "has no alpha channel (" + std::to_string(nc) + " channel" +
                         (nc == 1 ? "" : "s") + ": " + channel_list(spec) +
                         "); lockstep composite needs RGBA");
  // Colour channels: R, G, B by name, else the non-alpha channels in file order
  // (a grey + alpha file replicates its grey).
  int cc[3] = {find_channel(spec, "R"), find_channel(spec, "G"), find_channel(spec, "B")};
  if (cc[0] < 0 || cc[1] < 0 || cc[2] < 0) {
    std::vector<int> others;
    for (int c = 0; c < nc; ++c)
      if (c != ca) others.push_back(c);
    for (int k = 0; k < 3; ++k) cc[k] = others[std::min<size_t>(size_t(k), others.size() - 1)];
  }

  const size_t values = size_t(spec.width) * size_t(spec.height) * size_t(nc);
  std::vector<float> buf(values);
  bool read_ok;
  if (spec.format == OIIO::TypeDesc::UINT8) {
    // 8-bit q becomes q / 255 divided exactly (OIIO multiplies by 1/255, an ulp
    // off for some q), so that to_unorm8 and 8-bit outputs (q / 255) round-trip.
    std::vector<uint8_t> q(values);
    read_ok = in->read_image(0, 0, 0, nc, OIIO::TypeDesc::UINT8, q.data());
    for (size_t i = 0; i < values; ++i) buf[i] = float(q[i]) / 255.0f;
  } else {
    read_ok = in->read_image(0, 0, 0, nc, OIIO::TypeDesc::FLOAT, buf.data());
  }
  if (!read_ok) {
    std::string why = in->geterror();
    if (why.empty()) why = "read failed (truncated or corrupt file?)";
    throw InputError(path, 0, "cannot read layer: " + why);
  }
  // OIIO can report a truncated file only as an error message while still
  // returning true for some formats; treat any pending error as fatal.
  if (in->has_error()) throw InputError(path, 0, "cannot read layer: " + in->geterror());

  Layer layer;
  layer.source = path;
  const bool is_float = spec.format.basetype == OIIO::TypeDesc::FLOAT ||
                        spec.format.basetype == OIIO::TypeDesc::HALF ||
                        spec.format.basetype == OIIO::TypeDesc::DOUBLE;
  const bool declared_straight = spec.get_int_attribute("oiio:UnassociatedAlpha", 0) != 0;
  layer.alpha = alpha_override
                    ? *alpha_override
                    : (is_float && !declared_straight ? Alpha::premultiplied : Alpha::straight);
  layer.image = Image(spec.width, spec.height);
  const int src_channel[4] = {cc[0], cc[1], cc[2], ca};
  for (int y = 0; y < spec.height; ++y) {
    for (int x = 0; x < spec.width; ++x) {
      const size_t i = size_t(y) * size_t(spec.width) + size_t(x);
      float* d = &layer.image.rgba[i * 4];
      for (int c = 0; c < 4; ++c) {
        const float v = buf[i * size_t(nc) + size_t(src_channel[c])];
        if (std::isnan(v) || v < 0 || std::isinf(v)) {
          std::ostringstream m;
          m << "pixel (" << x << ", " << y << ") channel " << channel_name(c) << " is ";
          if (std::isnan(v)) {
            m << "NaN";
          } else if (std::isinf(v)) {
            m << (v < 0 ? "-inf" : "inf");
          } else {
            m << "negative (" << v << ")";
          }
          m << "; layers must hold finite values >= 0";
          throw InputError(path, 0, m.str());
        }
        d[c] = v;
      }
    }
  }
  return layer;
}

// ---------------------------------------------------------------- metrics (kinds/image_metrics.cpp)

// An ImageBuf over the image's own pixels (no copy; read only).
OIIO::ImageBuf wrap(const Image& img) {
  const OIIO::ImageSpec spec(img.width, img.height, 4, OIIO::TypeDesc::FLOAT);
  return OIIO::ImageBuf(spec, const_cast<float*>(img.rgba.data()));
}

void compare_fn(const Image& a, const Image& b, float fail, float warn, CompareStats* out) {
  const auto r = OIIO::ImageBufAlgo::compare(wrap(a), wrap(b), fail, warn);
  out->max_error = r.maxerror;
  out->max_x = r.maxx;
  out->max_y = r.maxy;
  out->mean_error = r.meanerror;
  out->rms_error = r.rms_error;
  out->psnr = r.PSNR;
  out->failed = long(r.nfail);
  out->warned = long(r.nwarn);
}

void heatmap_body(const Image& a, const Image& b, double scale, Image* out) {
  namespace iba = OIIO::ImageBufAlgo;
  const int w = std::min(a.width, b.width), h = std::min(a.height, b.height);
  const OIIO::ROI roi(0, w, 0, h, 0, 1, 0, 4);
  const OIIO::ImageBuf err = iba::maxchan(iba::absdiff(wrap(a), wrap(b), roi));
  if (scale <= 0) {
    const auto stats = iba::computePixelStats(err);
    scale = !stats.max.empty() && stats.max[0] > 0 ? stats.max[0] : 1;
  }
  // black, blue, green, yellow, red: 0 .. scale
  static constexpr float kKnots[] = {0, 0, 0, 0, 0, 1, 0, 1, 0, 1, 1, 0, 1, 0, 0};
  const OIIO::ImageBuf map =
      iba::color_map(iba::clamp(iba::mul(err, float(1 / scale)), 0.0f, 1.0f), 0, 5, 3, kKnots);
  *out = Image(w, h);
  map.get_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, 3), OIIO::TypeDesc::FLOAT, out->rgba.data(),
                 4 * sizeof(float));
}

// ------------------------------------------------ output paths (kinds/image_kind.cpp)

bool has_writer_fn(const std::string& path) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) (void)OIIO::geterror();
  return bool(out);
}

// ------------------------------------------------ verify's beside picture (app/verify_case.cpp)

void write_resized_body(const std::string& in, const std::string& out, int w, int h) {
  OIIO::ImageBuf src(in);
  if (!src.read(0, 0, true, OIIO::TypeDesc::FLOAT))
    throw InputError(in, 0, "cannot read: " + src.geterror());
  const OIIO::ROI roi(0, w, 0, h, 0, 1, 0, std::min(src.nchannels(), 4));
  OIIO::ImageBuf dst = src.spec().width == w && src.spec().height == h
                           ? src
                           : OIIO::ImageBufAlgo::resize(src, "", 0, roi);
  if (dst.has_error() || !dst.write(out, OIIO::TypeDesc::UINT8))
    throw InputError(out, 0, "cannot write the beside picture: " + dst.geterror());
}

// ---------------------- the composite family's oiio row (optimized/composite_oiio.cpp)

OIIO::ImageSpec rgba_spec(int w, int h, OIIO::TypeDesc type) {
  OIIO::ImageSpec spec(w, h, 4, type);
  spec.alpha_channel = 3;
  return spec;
}

[[noreturn]] void fail(const std::string& what, const std::string& why) {
  // Not the user's input: OIIO refused a well-formed stack.
  throw std::runtime_error("OpenImageIO " + what + " failed: " + why);
}

void over_body(const LayerStack& stack, int nthreads, Image* result_image) {
  const int w = stack.width(), h = stack.height();
  const bool eight = stack.storage == Storage::unorm8;
  const OIIO::TypeDesc type = eight ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
  const OIIO::ImageSpec spec = rgba_spec(w, h, type);
  const size_t L = stack.layers.size();

  // Layer k as a premultiplied ImageBuf: wrapped in place, or premultiplied into a new one.
  std::vector<std::unique_ptr<OIIO::ImageBuf>> layers;
  for (const Layer& l : stack.layers) {
    void* data = eight ? static_cast<void*>(const_cast<uint8_t*>(l.rgba8.data()))
                       : static_cast<void*>(const_cast<float*>(l.image.rgba.data()));
    auto wrapped = std::make_unique<OIIO::ImageBuf>(spec, data);  // read only: never written
    if (l.alpha == Alpha::straight) {
      auto p = std::make_unique<OIIO::ImageBuf>();
      if (!OIIO::ImageBufAlgo::premult(*p, *wrapped, {}, nthreads)) fail("premult", p->geterror());
      layers.push_back(std::move(p));
    } else {
      layers.push_back(std::move(wrapped));
    }
  }

  Image out = Image::uninitialized(w, h);  // ImageBufAlgo::over writes every pixel
  std::vector<uint8_t> out8;
  if (eight) out8.resize(size_t(w) * size_t(h) * 4);
  OIIO::ImageBuf result(
      spec, eight ? static_cast<void*>(out8.data()) : static_cast<void*>(out.rgba.data()));

  if (L == 1) {
    if (!OIIO::ImageBufAlgo::copy(result, *layers[0], OIIO::TypeUnknown, {}, nthreads))
      fail("copy", result.geterror());
  } else {
    // Chain: front to back, acc = acc over next; back to front, acc = next over acc.
    // Intermediate results ping-pong between two buffers; the last over writes
    // straight into the output.
    const bool ftb = stack.order == Order::front_to_back;
    auto at = [&](size_t s) -> const OIIO::ImageBuf& { return *layers[ftb ? s : L - 1 - s]; };
    OIIO::ImageBuf tmp[2] = {OIIO::ImageBuf(spec), OIIO::ImageBuf(spec)};
    const OIIO::ImageBuf* acc = &at(0);
    for (size_t s = 1; s < L; ++s) {
      OIIO::ImageBuf& dst = s + 1 == L ? result : tmp[s % 2];
      const bool ok = ftb ? OIIO::ImageBufAlgo::over(dst, *acc, at(s), {}, nthreads)
                          : OIIO::ImageBufAlgo::over(dst, at(s), *acc, {}, nthreads);
      if (!ok) fail("over", dst.geterror());
      acc = &dst;
    }
  }
  if (eight)
    for (size_t i = 0; i < out8.size(); ++i) out.rgba[i] = float(out8[i]) / 255.0f;
  *result_image = std::move(out);
}


// ---------------------------------------------------------------- texture lookups

// A texture made tiled and mipmapped (a temporary .tx, removed with it) and
// the TextureSystem that reads it: what the oiio row keeps across frames.
struct TexState {
  std::string tx;
  std::shared_ptr<OIIO::TextureSystem> ts;
  Wrap wrap = Wrap::repeat;
  ~TexState() {
    ts.reset();
    std::error_code ec;
    if (!tx.empty()) std::filesystem::remove(tx, ec);
  }
};

OIIO::TextureOpt texture_opt(Wrap wrap, TextureMode mode, int aniso) {
  OIIO::TextureOpt opt;
  const auto w = wrap == Wrap::repeat  ? OIIO::TextureOpt::WrapPeriodic
                 : wrap == Wrap::clamp ? OIIO::TextureOpt::WrapClamp
                                       : OIIO::TextureOpt::WrapMirror;
  opt.swrap = opt.twrap = w;
  opt.interpmode = mode == TextureMode::closest ? OIIO::TextureOpt::InterpClosest : OIIO::TextureOpt::InterpBilinear;
  opt.mipmode = mode == TextureMode::closest || mode == TextureMode::bilinear ? OIIO::TextureOpt::MipModeNoMIP
                : mode == TextureMode::one_level                              ? OIIO::TextureOpt::MipModeOneLevel
                : mode == TextureMode::trilinear                              ? OIIO::TextureOpt::MipModeTrilinear
                                                                              : OIIO::TextureOpt::MipModeAniso;
  opt.anisotropic = std::max(1, aniso);
  return opt;
}

TexState* texture_open_body(const Texture& tex) {
  auto st = std::make_unique<TexState>();
  st->wrap = tex.wrap;
  // The texture as a float RGBA ImageBuf, wrapped without copying.
  const OIIO::ImageSpec spec(tex.width, tex.height, 4, OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf src(spec, const_cast<float*>(tex.rgba.data()));
  // Tiled and mipmapped, as maketx makes it, into a temporary file.
  char name[] = "/tmp/lockstep-texture-XXXXXX";
  const int fd = mkstemp(name);
  if (fd < 0) fail("make_texture", "cannot make a temporary file");
  close(fd);
  st->tx = std::string(name) + ".tx";
  std::filesystem::rename(name, st->tx);
  OIIO::ImageSpec config;
  const char* wrap = tex.wrap == Wrap::repeat ? "periodic" : tex.wrap == Wrap::clamp ? "clamp" : "mirror";
  config.attribute("wrapmodes", std::string(wrap) + "," + wrap);
  config.attribute("maketx:filtername", "box");
  config.attribute("maketx:fixnan", "none");
  config.format = OIIO::TypeDesc::FLOAT;
  if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, src, st->tx, config))
    fail("make_texture", OIIO::geterror());
  st->ts.reset(OIIO::TextureSystem::create(false), [](OIIO::TextureSystem* p) { OIIO::TextureSystem::destroy(p); });
  st->ts->attribute("max_memory_MB", 2048.0f);
  st->ts->attribute("autotile", 0);
  // Open it once here, so the first lookup does not time it.
  OIIO::TextureSystem::Perthread* pt = st->ts->get_perthread_info();
  OIIO::TextureSystem::TextureHandle* h = st->ts->get_texture_handle(OIIO::ustring(st->tx), pt);
  if (!h || st->ts->is_udim(h)) fail("TextureSystem", st->ts->geterror());
  float rgba[4];
  OIIO::TextureOpt opt = texture_opt(st->wrap, TextureMode::trilinear, 1);
  st->ts->texture(h, pt, opt, 0.5f, 0.5f, 0, 0, 0, 0, 4, rgba);
  return st.release();
}

void texture_lookups_body(TexState& st, const TextureLookups& in, TextureMode mode, int aniso, int nthreads,
                          float* out) {
  const OIIO::TextureOpt opt = texture_opt(st.wrap, mode, aniso);
  const OIIO::ustring file(st.tx);
  OIIO::TextureSystem& ts = *st.ts;
  const int n_threads = nthreads > 0 ? nthreads : int(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::string> errors(static_cast<size_t>(n_threads));
  auto slice = [&](int k) {
    OIIO::TextureSystem::Perthread* pt = ts.get_perthread_info();
    OIIO::TextureSystem::TextureHandle* h = ts.get_texture_handle(file, pt);
    OIIO::TextureOpt o = opt;
    // Interleaved chunks of 256 lookups: neighbouring pixels on one thread.
    for (size_t c = size_t(k) * 256; c < in.n; c += size_t(n_threads) * 256)
      for (size_t i = c; i < std::min(in.n, c + 256); ++i)
        if (!ts.texture(h, pt, o, in.s[i], in.t[i], in.dsdx[i], in.dtdx[i], in.dsdy[i], in.dtdy[i], 4, out + 4 * i)) {
          errors[size_t(k)] = ts.geterror();
          return;
        }
  };
  std::vector<std::thread> pool;
  for (int k = 1; k < n_threads; ++k) pool.emplace_back(slice, k);
  slice(0);
  for (auto& t : pool) t.join();
  for (const std::string& e : errors)
    if (!e.empty()) fail("TextureSystem::texture", e);
}

// ---------------------------------------------------------------- the table

constexpr ModuleApi kApi = {
    kAbi,
    [](const std::string& path, Image* out, Error* err) {
      return guarded(err, [&] { *out = read_image_body(path); });
    },
    [](const Image& image, const std::string& path, const std::string& exr_compression,
       Error* err) {
      return guarded(err, [&] { write_image_body(image, path, exr_compression); });
    },
    [](const std::string& path, const Alpha* alpha_override, Layer* out, Error* err) {
      return guarded(err, [&] {
        *out = read_layer_body(
            path, alpha_override ? std::optional<Alpha>(*alpha_override) : std::nullopt);
      });
    },
    has_writer_fn,
    compare_fn,
    [](const Image& a, const Image& b, double scale, Image* out, Error* err) {
      return guarded(err, [&] { heatmap_body(a, b, scale, out); });
    },
    [](const std::string& in, const std::string& out, int w, int h, Error* err) {
      return guarded(err, [&] { write_resized_body(in, out, w, h); });
    },
    [](const LayerStack& stack, int threads, Image* out, Error* err) {
      return guarded(err, [&] { over_body(stack, threads, out); });
    },
    [](const Texture& tex, Error* err) -> void* {
      TexState* st = nullptr;
      guarded(err, [&] { st = texture_open_body(tex); });
      return st;
    },
    [](void* handle, const TextureLookups& in, TextureMode mode, int aniso, int threads, float* out, Error* err) {
      return guarded(err, [&] { texture_lookups_body(*static_cast<TexState*>(handle), in, mode, aniso, threads, out); });
    },
    [](void* handle) { delete static_cast<TexState*>(handle); },
};

}  // namespace
}  // namespace lockstep::oiio

extern "C" __attribute__((visibility("default"))) const void* lockstep_peer_api() {
  return &lockstep::oiio::kApi;
}

// For cmake/peer_version.cpp at build time: the version `lockstep --version`
// prints (the header's, as it printed before the module: e.g. "2.4.7.1").
extern "C" __attribute__((visibility("default"))) void lockstep_peer_version(char* out,
                                                                             unsigned long size) {
  const std::string v = OIIO_VERSION_STRING;
  if (size > 0) out[v.copy(out, size - 1)] = '\0';
}
