// lockstep io: OpenEXR files through libOpenEXR (see io/image_exr.h).
#include "io/image_exr.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfPartType.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>
#include <ImfThreading.h>

#include <cstdio>
#include <ctime>
#include <exception>
#include <stdexcept>
#include <thread>

namespace lockstep::io {

namespace {

struct Compression {
  Imf::Compression type = Imf::ZIP_COMPRESSION;
  int zip_level = -1;  // -1: OpenEXR's default
};

// "name" or "name:level", as OpenImageIO's OpenEXR writer took it.
std::optional<Compression> parse_compression(const std::string& s) {
  const size_t colon = s.find(':');
  const std::string name = s.substr(0, colon);
  Compression c;
  if (name == "none") {
    c.type = Imf::NO_COMPRESSION;
  } else if (name == "rle") {
    c.type = Imf::RLE_COMPRESSION;
  } else if (name == "zips") {
    c.type = Imf::ZIPS_COMPRESSION;
  } else if (name == "zip") {
    c.type = Imf::ZIP_COMPRESSION;
  } else if (name == "piz") {
    c.type = Imf::PIZ_COMPRESSION;
  } else if (name == "pxr24") {
    c.type = Imf::PXR24_COMPRESSION;
  } else {
    return std::nullopt;
  }
  if (colon == std::string::npos) return c;
  const std::string level = s.substr(colon + 1);
  if ((c.type != Imf::ZIP_COMPRESSION && c.type != Imf::ZIPS_COMPRESSION) || level.size() != 1 ||
      level[0] < '1' || level[0] > '9')
    return std::nullopt;
  c.zip_level = level[0] - '0';
  return c;
}

// OpenImageIO's OpenEXR calls ran on as many threads as the machine has.
int exr_threads() {
  const int n = int(std::thread::hardware_concurrency());
  const int threads = n > 0 ? n : 1;
  if (Imf::globalThreadCount() != threads) Imf::setGlobalThreadCount(threads);
  return threads;
}

// OpenImageIO's DateTime ("YYYY:MM:DD HH:MM:SS", local time), stored as capDate.
std::string date_time_now() {
  const std::time_t now = std::time(nullptr);
  std::tm t{};
  localtime_r(&now, &t);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%04d:%02d:%02d %02d:%02d:%02d", t.tm_year + 1900, t.tm_mon + 1,
                t.tm_mday, t.tm_hour, t.tm_min, t.tm_sec);
  return buf;
}

}  // namespace

bool exr_compression_known(const std::string& compression) {
  return parse_compression(compression).has_value();
}

void write_exr(const Image& image, const std::string& path, const std::string& compression) {
  const std::optional<Compression> c = parse_compression(compression);
  if (!c) throw std::invalid_argument("unknown OpenEXR compression '" + compression + "'");
  Imf::Header header(image.width, image.height);
  header.compression() = c->type;
  if (c->zip_level > 0) header.zipCompressionLevel() = c->zip_level;
  static constexpr const char* kNames[4] = {"R", "G", "B", "A"};
  for (const char* name : kNames) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
  Imf::addCapDate(header, date_time_now());

  Imf::FrameBuffer frame;
  const size_t x_stride = 4 * sizeof(float), y_stride = x_stride * size_t(image.width);
  for (int k = 0; k < 4; ++k) {
    char* base = reinterpret_cast<char*>(const_cast<float*>(image.rgba.data() + k));
    frame.insert(kNames[k], Imf::Slice(Imf::FLOAT, base, x_stride, y_stride));
  }
  Imf::OutputFile file(path.c_str(), header, exr_threads());
  file.setFrameBuffer(frame);
  file.writePixels(image.height);
}

std::optional<ExrPixels> read_exr(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str(), exr_threads());
    const Imf::Header& header = file.header();
    if (!file.isComplete() || (header.hasType() && Imf::isDeepData(header.type())) ||
        header.find("oiio:UnassociatedAlpha") != header.end())
      return std::nullopt;
    static constexpr const char* kNames[4] = {"R", "G", "B", "A"};
    int channels = 0;
    for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
      const Imf::Channel& ch = it.channel();
      if (ch.type == Imf::UINT || ch.xSampling != 1 || ch.ySampling != 1) return std::nullopt;
      ++channels;
    }
    for (int k = 0; k < 4; ++k)
      if ((header.channels().findChannel(kNames[k]) != nullptr) != (k < channels))
        return std::nullopt;
    if (channels < 3) return std::nullopt;

    const Imath::Box2i dw = header.dataWindow();
    ExrPixels px;
    px.width = dw.max.x - dw.min.x + 1;
    px.height = dw.max.y - dw.min.y + 1;
    px.channels = channels;
    if (px.width <= 0 || px.height <= 0) return std::nullopt;
    px.values.resize(size_t(px.width) * size_t(px.height) * size_t(channels));
    Imf::FrameBuffer frame;
    const size_t x_stride = size_t(channels) * sizeof(float);
    for (int k = 0; k < channels; ++k)
      frame.insert(kNames[k], Imf::Slice::Make(Imf::FLOAT, px.values.data() + k, dw, x_stride));
    file.setFrameBuffer(frame);
    file.readPixels(dw.min.y, dw.max.y);
    return px;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

}  // namespace lockstep::io
