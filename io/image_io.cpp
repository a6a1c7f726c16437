// lockstep io: image files (core/image.h, io/layers.h' read_layer). The two
// formats lockstep itself writes, .exr and .png, go through OpenEXR and libpng
// directly (io/image_exr.h, io/image_png.h): a render to either maps a dozen
// libraries, not the ~300 that OpenImageIO's module lockstep_oiio.so pulls in
// (issue #31: a one-shot 256^2 render to .exr spent 0.4 s of its 0.5 s
// loading them). Every other format goes through the module (io/oiio.h),
// opened on first use, as do the files the direct code declines (the
// readers' notes say which) and every failure: the module then reads or
// writes the file itself, or reports why not in the words it always used, so
// the messages and exit codes are the module's, unchanged.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <new>
#include <optional>
#include <string>

#include "io/image_io.h"
#include "io/layers.h"
#include "io/oiio.h"
#include "io/image_exr.h"
#include "io/image_png.h"

namespace lockstep {

namespace {

// Only these exact (lower-case) extensions: OIIO picked other spellings'
// settings differently (an ".EXR" got its default compression).
bool is_ext(const std::string& path, const char* ext) {
  return std::filesystem::path(path).extension() == ext;
}

// The direct writers write a temporary file in the same folder, renamed into
// place when complete (core/image.h). False, with nothing left behind, when
// they fail: the module then tries and reports.
template <class Write>
bool write_atomically(const std::string& path, Write&& write) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path tmp = target.parent_path() /
                       (".tmp-" + std::to_string(::getpid()) + "-" + target.filename().string());
  std::error_code ec;
  try {
    write(tmp.string());
    fs::rename(tmp, target, ec);
    if (!ec) return true;
  } catch (const std::bad_alloc&) {
    fs::remove(tmp, ec);
    throw;
  } catch (const std::exception&) {
  }
  fs::remove(tmp, ec);
  return false;
}

// read_image's rules on a PNG's 8-bit samples, as OIIO applied them: colour
// premultiplied by alpha in 8 bits ((c * a) / 255, truncated), then q * (1/255).
Image from_png(const io::Png8& png) {
  const int nc = png.channels;
  const int alpha = nc == 2 || nc == 4 ? nc - 1 : -1;
  Image img(png.width, png.height);
  const size_t n = size_t(png.width) * size_t(png.height);
  for (size_t i = 0; i < n; ++i) {
    float v[4] = {};
    const uint8_t* s = &png.samples[i * size_t(nc)];
    for (int c = 0; c < nc; ++c) {
      unsigned q = s[c];
      if (alpha >= 0 && c != alpha) q = q * unsigned(s[alpha]) / 255u;
      v[c] = float(q) * (1.0f / 255.0f);
    }
    float* d = &img.rgba[i * 4];
    d[0] = v[0];
    d[1] = nc >= 3 ? v[1] : v[0];
    d[2] = nc >= 3 ? v[2] : v[0];
    d[3] = nc == 4 ? v[3] : (nc == 2 ? v[1] : 1.0f);
  }
  return img;
}

Image from_exr(const io::ExrPixels& exr) {
  Image img(exr.width, exr.height);
  const size_t n = size_t(exr.width) * size_t(exr.height);
  for (size_t i = 0; i < n; ++i) {
    const float* s = &exr.values[i * size_t(exr.channels)];
    float* d = &img.rgba[i * 4];
    d[0] = s[0];
    d[1] = s[1];
    d[2] = s[2];
    d[3] = exr.channels == 4 ? s[3] : 1.0f;
  }
  return img;
}

// read_layer's rules (io/oiio_module.cpp) on what the direct readers read:
// an RGBA EXR is premultiplied, an 8-bit grey + alpha or RGBA PNG straight,
// its values q / 255 divided exactly. nullopt when the file has no alpha or a
// value that is not finite and >= 0: the module reports those.
std::optional<Layer> direct_layer(const std::string& path, std::optional<Alpha> alpha_override) {
  Layer layer;
  layer.source = path;
  if (is_ext(path, ".exr")) {
    const std::optional<io::ExrPixels> exr = io::read_exr(path);
    if (!exr || exr->channels != 4) return std::nullopt;
    layer.image = from_exr(*exr);
    layer.alpha = alpha_override.value_or(Alpha::premultiplied);
  } else if (is_ext(path, ".png")) {
    const std::optional<io::Png8> png = io::read_png(path);
    if (!png || (png->channels != 2 && png->channels != 4)) return std::nullopt;
    const int nc = png->channels;
    layer.image = Image(png->width, png->height);
    const size_t n = size_t(png->width) * size_t(png->height);
    for (size_t i = 0; i < n; ++i) {
      const uint8_t* s = &png->samples[i * size_t(nc)];
      float* d = &layer.image.rgba[i * 4];
      for (int c = 0; c < 3; ++c) d[c] = float(s[nc == 4 ? c : 0]) / 255.0f;
      d[3] = float(s[nc - 1]) / 255.0f;
    }
    layer.alpha = alpha_override.value_or(Alpha::straight);
  } else {
    return std::nullopt;
  }
  if (int64_t(layer.image.width) * int64_t(layer.image.height) > (int64_t(1) << 28))
    return std::nullopt;
  for (const float v : layer.image.rgba)
    if (!(v >= 0) || std::isinf(v)) return std::nullopt;
  return layer;
}

}  // namespace

Image read_image(const std::string& path) {
  if (is_ext(path, ".exr")) {
    if (const std::optional<io::ExrPixels> exr = io::read_exr(path)) return from_exr(*exr);
  } else if (is_ext(path, ".png")) {
    if (const std::optional<io::Png8> png = io::read_png(path)) return from_png(*png);
  }
  Image img;
  oiio::Error err;
  if (!oiio::api().read_image(path, &img, &err)) oiio::raise(err);
  return img;
}

void write_image(const Image& image, const std::string& path) {
  write_image(image, path, "zips:1");
}

void write_image(const Image& image, const std::string& path, const std::string& exr_compression) {
  if (image.width > 0 && image.height > 0) {
    if (is_ext(path, ".exr") && io::exr_compression_known(exr_compression) &&
        write_atomically(
            path, [&](const std::string& tmp) { io::write_exr(image, tmp, exr_compression); }))
      return;
    if (is_ext(path, ".png") &&
        write_atomically(path, [&](const std::string& tmp) { io::write_png(image, tmp); }))
      return;
  }
  oiio::Error err;
  if (!oiio::api().write_image(image, path, exr_compression, &err)) oiio::raise(err);
}

bool image_has_writer(const std::string& path) {
  return is_ext(path, ".exr") || is_ext(path, ".png") || oiio::api().has_writer(path);
}

Layer read_layer(const std::string& path, std::optional<Alpha> alpha_override) {
  if (std::optional<Layer> direct = direct_layer(path, alpha_override)) return std::move(*direct);
  Layer layer;
  oiio::Error err;
  if (!oiio::api().read_layer(path, alpha_override ? &*alpha_override : nullptr, &layer, &err))
    oiio::raise(err);
  return layer;
}

}  // namespace lockstep
