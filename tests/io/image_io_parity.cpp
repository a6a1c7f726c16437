// .exr and .png through OpenEXR and libpng (io/image_io.cpp) against the
// OpenImageIO module they replaced (io/oiio_module.cpp, lockstep_oiio.so),
// called here side by side through its table (io/oiio.h):
//   - write: an image of edge values (every 8-bit rounding boundary and an ulp
//     either side, colour above, at and below alpha, alpha 0, NaN, +-inf,
//     negatives) and a smooth one, each as .png, .exr (zips:1, the default)
//     and .exr pxr24 (the goldens): the files must be the same bytes but for
//     the EXR capDate (the time of writing);
//   - read: every file named on the command line, the files just written and
//     grey, grey + alpha and RGB PNGs made here, through read_image and
//     read_layer both ways: the same floats bit for bit (and the same alpha
//     kind), or the same error (file, line and words).
//   image_io_parity OUT_DIR [IMAGE...]
#include <png.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/image_io.h"
#include "io/layers.h"
#include "io/oiio.h"

namespace fs = std::filesystem;
using namespace lockstep;

namespace {

int failures = 0;
void fail(const std::string& what) {
  std::printf("FAIL: %s\n", what.c_str());
  ++failures;
}

std::string bytes_of(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// The EXR header's capDate value blanked (the time each file was written).
std::string without_cap_date(std::string b) {
  const std::string key("capDate\0string\0", 15);
  const size_t at = b.find(key);
  if (at != std::string::npos && at + key.size() + 4 <= b.size()) {
    uint32_t n = 0;
    std::memcpy(&n, b.data() + at + key.size(), 4);
    b.replace(at + key.size() + 4, n, std::string(n, '#'));
  }
  return b;
}

Image edge_image() {
  std::vector<float> v;
  for (int k = 0; k <= 256; ++k) {
    const float b = (float(k) - 0.5f) / 255.0f, e = float(k) / 255.0f;
    for (float x : {b, e}) {
      float lo = x, hi = x;
      for (int u = 0; u < 3; ++u) {
        v.push_back(lo);
        v.push_back(hi);
        lo = std::nextafter(lo, -1.0f);
        hi = std::nextafter(hi, 2.0f);
      }
    }
  }
  for (float x : {0.0f, -0.0f, -1e-30f, 1e-30f, -1.0f, 1.0f, 2.0f, 1e30f, -1e30f,
                  std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                  -std::numeric_limits<float>::infinity(), 0.5f, 127.5f / 255.0f})
    v.push_back(x);
  // Pixels: every value as colour against a spread of alphas, and as alpha.
  const std::vector<float> alphas = {0.0f,  1.0f,   0.5f,   1.0f / 255.0f,
                                     0.25f, 0.999f, 0.002f, std::numeric_limits<float>::quiet_NaN(),
                                     1.5f,  -0.5f};
  std::vector<float> px;
  for (size_t i = 0; i < v.size(); ++i)
    for (float a : alphas)
      px.insert(px.end(), {v[i], v[(i * 7 + 3) % v.size()], v[(i * 13 + 5) % v.size()], a});
  for (float a : v) px.insert(px.end(), {0.3f, 0.6f, 0.9f, a});
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> u(-0.1f, 1.1f), ua(0.0f, 1.0f);
  for (int i = 0; i < 4096; ++i) {
    const float a = ua(rng);
    px.insert(px.end(), {u(rng) * a, u(rng) * a, u(rng), a});
  }
  const int w = 97, h = int((px.size() / 4 + w - 1) / w);
  Image img(w, h);
  std::copy(px.begin(), px.end(), img.rgba.begin());
  return img;
}

Image smooth_image() {
  Image img(256, 192);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const float a = x < 32 ? 0.0f : (x > 200 ? 1.0f : float(x) / 256.0f);
      img.set(x, y, {a * x / 255.0, a * y / 191.0, a * 0.5 * (1 + std::sin(x * 0.1 + y * 0.07))},
              a);
    }
  return img;
}

// A PNG of the given channel count (libpng's simplified writer), from an image.
void write_plain_png(const Image& src, int channels, const std::string& path) {
  png_image img;
  std::memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  img.width = png_uint_32(src.width);
  img.height = png_uint_32(src.height);
  img.format = channels == 1   ? PNG_FORMAT_GRAY
               : channels == 2 ? PNG_FORMAT_GA
               : channels == 3 ? PNG_FORMAT_RGB
                               : PNG_FORMAT_RGBA;
  std::vector<uint8_t> q;
  for (size_t i = 0; i < size_t(src.width) * size_t(src.height); ++i)
    for (int c = 0; c < channels; ++c) {
      const float v = src.rgba[i * 4 + size_t(channels == 2 && c == 1 ? 3 : c)];
      q.push_back(uint8_t(std::fmin(std::fmax(v, 0.0f), 1.0f) * 255.0f + 0.5f));
    }
  if (!png_image_write_to_file(&img, path.c_str(), 0, q.data(), 0, nullptr))
    fail("cannot write " + path);
}

bool same_floats(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height && a.rgba.size() == b.rgba.size() &&
         std::memcmp(a.rgba.data(), b.rgba.data(), a.rgba.size() * sizeof(float)) == 0;
}

std::string error_of(const std::exception& e) { return e.what(); }

// read_image and read_layer both ways: the same result or the same error.
void check_read(const std::string& path) {
  std::optional<Image> direct, module;
  std::string direct_err, module_err;
  try {
    direct = read_image(path);
  } catch (const std::exception& e) {
    direct_err = error_of(e);
  }
  oiio::Error err;
  Image m;
  if (oiio::api().read_image(path, &m, &err)) {
    module = std::move(m);
  } else {
    try {
      oiio::raise(err);
    } catch (const std::exception& e) {
      module_err = error_of(e);
    }
  }
  if (direct_err != module_err)
    fail(path + ": read_image error '" + direct_err + "', module '" + module_err + "'");
  if (direct.has_value() != module.has_value() || (direct && !same_floats(*direct, *module)))
    fail(path + ": read_image floats differ from the module's");

  std::optional<Layer> dl, ml;
  direct_err.clear();
  module_err.clear();
  try {
    dl = read_layer(path, std::nullopt);
  } catch (const std::exception& e) {
    direct_err = error_of(e);
  }
  Layer l;
  if (oiio::api().read_layer(path, nullptr, &l, &err)) {
    ml = std::move(l);
  } else {
    try {
      oiio::raise(err);
    } catch (const std::exception& e) {
      module_err = error_of(e);
    }
  }
  if (direct_err != module_err)
    fail(path + ": read_layer error '" + direct_err + "', module '" + module_err + "'");
  if (dl.has_value() != ml.has_value() ||
      (dl &&
       (!same_floats(dl->image, ml->image) || dl->alpha != ml->alpha || dl->source != ml->source)))
    fail(path + ": read_layer differs from the module's");
  std::printf("ok: read %s (%s)\n", path.c_str(),
              direct
                  ? (std::to_string(direct->width) + "x" + std::to_string(direct->height)).c_str()
                  : direct_err.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: image_io_parity OUT_DIR [IMAGE...]\n");
    return 2;
  }
  const fs::path out = argv[1];
  fs::create_directories(out);
  std::vector<std::string> reads(argv + 2, argv + argc);

  const std::pair<const char*, Image> images[] = {{"edge", edge_image()},
                                                  {"smooth", smooth_image()}};
  const std::pair<const char*, const char*> formats[] = {
      {".png", "zips:1"}, {".exr", "zips:1"}, {"-pxr24.exr", "pxr24"}};
  for (const auto& [name, img] : images)
    for (const auto& [suffix, compression] : formats) {
      const std::string direct = (out / (std::string(name) + suffix)).string();
      const std::string module = (out / (std::string(name) + "-oiio" + suffix)).string();
      write_image(img, direct, compression);
      oiio::Error err;
      if (!oiio::api().write_image(img, module, compression, &err)) oiio::raise(err);
      const std::string a = without_cap_date(bytes_of(direct)),
                        b = without_cap_date(bytes_of(module));
      if (a.empty() || a != b)
        fail(direct + ": " + std::to_string(a.size()) + " bytes, not the module's " +
             std::to_string(b.size()) + (a.size() == b.size() ? " (same size, other bytes)" : ""));
      else
        std::printf("ok: %s is the module's file byte for byte (%zu bytes)\n", direct.c_str(),
                    a.size());
      reads.push_back(direct);
    }
  const Image smooth = smooth_image();
  for (int channels : {1, 2, 3, 4}) {
    const std::string p = (out / ("plain-" + std::to_string(channels) + ".png")).string();
    write_plain_png(smooth, channels, p);
    reads.push_back(p);
  }
  for (const std::string& p : reads) check_read(p);
  if (failures) {
    std::printf("%d failure(s)\n", failures);
    return 1;
  }
  std::printf("all %zu files read alike\n", reads.size());
  return 0;
}
