#include "core/image.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "core/error.h"
#include "core/quiet_stderr.h"

namespace lockstep {

Image read_image(const std::string& path) {
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

void write_image(const Image& image, const std::string& path) { write_image(image, path, "zips:1"); }

void write_image(const Image& image, const std::string& path, const std::string& exr_compression) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  // Keep the extension on the temporary name: OIIO picks the format from it.
  const fs::path tmp = target.parent_path() /
                       (".tmp-" + std::to_string(::getpid()) + "-" + target.filename().string());
  auto out = OIIO::ImageOutput::create(path);
  if (!out) throw InputError(path, 0, "cannot write image: unknown format (" + OIIO::geterror() + ")");
  // 8-bit formats get the values clamped by OIIO; float formats keep them.
  OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::FLOAT);
  const std::string ext = target.extension().string();
  if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp" || ext == ".ppm")
    spec.set_format(OIIO::TypeDesc::UINT8);
  if (ext == ".exr") spec.attribute("compression", exr_compression);
  bool ok = out->open(tmp.string(), spec) && out->write_image(OIIO::TypeDesc::FLOAT, image.rgba.data());
  ok = out->close() && ok;
  std::string why = out->geterror();
  std::error_code ec;
  if (ok) fs::rename(tmp, target, ec);
  if (!ok || ec) {
    fs::remove(tmp, ec);
    throw InputError(path, 0, "cannot write image: " + (why.empty() ? ec.message() : why));
  }
}

}  // namespace lockstep
