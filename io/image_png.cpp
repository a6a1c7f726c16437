// lockstep io: PNG files through libpng (see io/image_png.h).
//
// libpng reports errors by longjmp from its error callback back to the
// setjmp in the function that called it: the functions holding a setjmp below
// keep every object with a destructor outside their own frame (in the caller's
// structs), so that a jump skips none.
#include "io/image_png.h"

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <stdexcept>

namespace lockstep::io {

namespace {

[[noreturn]] void on_error(png_structp png, png_const_charp) { png_longjmp(png, 1); }
void on_warning(png_structp, png_const_charp) {}  // quiet, as lockstep was through OIIO

// OpenImageIO's float to 8 bits: the float product v * 255, rounded half away
// from zero (its + 0.5 taken exactly, in double), clamped to [0, 255]; NaN is
// 0. A float + 0.5 would round up the products an ulp below a half step (the
// float before 0.5 / 255 became 1, where OIIO wrote 0), and v * 255 + 0.5 in
// double misses the product's own rounding: both made other files
// (tests/io/image_io_parity.cpp, 31 and more of its edge pixels).
uint8_t to_u8(float v) {
  const double s = double(v * 255.0f) + 0.5;
  return s >= 0.0 ? (s <= 255.0 ? uint8_t(s) : uint8_t(255)) : uint8_t(0);
}

struct File {
  std::FILE* f = nullptr;
  explicit File(const std::string& path, const char* mode) : f(std::fopen(path.c_str(), mode)) {}
  ~File() {
    if (f) std::fclose(f);
  }
};

struct Writer {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~Writer() { png_destroy_write_struct(&png, &info); }
};

// The rows are written; false when libpng reported an error.
bool write_rows(Writer& w, std::FILE* f, int width, int height, png_bytepp rows) {
  if (setjmp(png_jmpbuf(w.png))) return false;
  png_init_io(w.png, f);
  png_set_compression_level(w.png, 6);
  png_set_compression_strategy(w.png, 0 /* Z_DEFAULT_STRATEGY */);
  png_set_filter(w.png, 0, PNG_NO_FILTERS);
  png_set_option(w.png, PNG_SKIP_sRGB_CHECK_PROFILE, PNG_OPTION_ON);
  png_set_IHDR(w.png, w.info, png_uint_32(width), png_uint_32(height), 8, PNG_COLOR_TYPE_RGB_ALPHA,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_oFFs(w.png, w.info, 0, 0, PNG_OFFSET_PIXEL);
  png_write_info(w.png, w.info);
  png_write_image(w.png, rows);
  png_write_end(w.png, nullptr);
  return true;
}

struct Reader {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~Reader() { png_destroy_read_struct(&png, &info, nullptr); }
};

// The header: false when libpng reported an error.
bool read_header(Reader& r, std::FILE* f, png_uint_32* w, png_uint_32* h, int* depth, int* type,
                 int* interlace) {
  if (setjmp(png_jmpbuf(r.png))) return false;
  png_init_io(r.png, f);
  png_set_sig_bytes(r.png, 8);
  png_read_info(r.png, r.info);
  png_get_IHDR(r.png, r.info, w, h, depth, type, interlace, nullptr, nullptr);
  return true;
}

bool read_rows(Reader& r, png_bytepp rows) {
  if (setjmp(png_jmpbuf(r.png))) return false;
  png_read_image(r.png, rows);
  return true;
}

}  // namespace

void write_png(const Image& image, const std::string& path) {
  const size_t w = size_t(image.width), h = size_t(image.height);
  std::vector<uint8_t> q(w * h * 4);
  for (size_t p = 0; p < w * h; ++p) {
    const float* s = &image.rgba[p * 4];
    uint8_t* d = &q[p * 4];
    for (int c = 0; c < 4; ++c) d[c] = to_u8(s[c]);
    // PNG holds straight colour: OIIO un-premultiplied the 8-bit values.
    if (const unsigned a = d[3]; a != 0)
      for (int c = 0; c < 3; ++c) {
        const unsigned f = unsigned(d[c]) * 255u / a;
        d[c] = uint8_t(f < 255u ? f : 255u);
      }
  }
  std::vector<png_bytep> rows(h);
  for (size_t y = 0; y < h; ++y) rows[y] = q.data() + y * w * 4;

  File file(path, "wb");
  if (!file.f) throw std::runtime_error("cannot open " + path);
  Writer wr;
  wr.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, on_error, on_warning);
  if (wr.png) wr.info = png_create_info_struct(wr.png);
  if (!wr.png || !wr.info) throw std::runtime_error("libpng: cannot start a writer");
  if (!write_rows(wr, file.f, image.width, image.height, rows.data()))
    throw std::runtime_error("libpng: cannot write " + path);
  const int closed = std::fclose(file.f);
  file.f = nullptr;
  if (closed != 0) throw std::runtime_error("cannot write " + path);
}

std::optional<Png8> read_png(const std::string& path) {
  File file(path, "rb");
  if (!file.f) return std::nullopt;
  png_byte sig[8];
  if (std::fread(sig, 1, 8, file.f) != 8 || png_sig_cmp(sig, 0, 8) != 0) return std::nullopt;
  Reader rd;
  rd.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, on_error, on_warning);
  if (rd.png) rd.info = png_create_info_struct(rd.png);
  if (!rd.png || !rd.info) return std::nullopt;
  png_uint_32 w = 0, h = 0;
  int depth = 0, type = 0, interlace = 0;
  if (!read_header(rd, file.f, &w, &h, &depth, &type, &interlace)) return std::nullopt;
  Png8 out;
  switch (type) {
    case PNG_COLOR_TYPE_GRAY:
      out.channels = 1;
      break;
    case PNG_COLOR_TYPE_GRAY_ALPHA:
      out.channels = 2;
      break;
    case PNG_COLOR_TYPE_RGB:
      out.channels = 3;
      break;
    case PNG_COLOR_TYPE_RGB_ALPHA:
      out.channels = 4;
      break;
    default:
      return std::nullopt;  // palette
  }
  if (depth != 8 || interlace != PNG_INTERLACE_NONE || w == 0 || h == 0 || w > (1u << 16) ||
      h > (1u << 16) ||
      png_get_valid(rd.png, rd.info, PNG_INFO_tRNS | PNG_INFO_gAMA | PNG_INFO_sRGB | PNG_INFO_iCCP))
    return std::nullopt;
  out.width = int(w);
  out.height = int(h);
  const size_t row = size_t(w) * size_t(out.channels);
  out.samples.resize(row * h);
  std::vector<png_bytep> rows(h);
  for (size_t y = 0; y < h; ++y) rows[y] = out.samples.data() + y * row;
  if (!read_rows(rd, rows.data())) return std::nullopt;
  return out;
}

}  // namespace lockstep::io
