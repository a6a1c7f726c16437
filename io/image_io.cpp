// lockstep io: image files, through OpenImageIO in lockstep_oiio.so (io/oiio.h:
// the module is opened by the first image read or written).
#include "io/image_io.h"

#include "io/oiio.h"

namespace lockstep {

Image read_image(const std::string& path) {
  Image img;
  oiio::Error err;
  if (!oiio::api().read_image(path, &img, &err)) oiio::raise(err);
  return img;
}

void write_image(const Image& image, const std::string& path) {
  write_image(image, path, "zips:1");
}

void write_image(const Image& image, const std::string& path, const std::string& exr_compression) {
  oiio::Error err;
  if (!oiio::api().write_image(image, path, exr_compression, &err)) oiio::raise(err);
}

}  // namespace lockstep
