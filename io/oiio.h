// lockstep io: every OpenImageIO call, in a module opened on first use.
//
// OpenImageIO pulls in about 250 shared libraries (ffmpeg, OpenCV, OpenVDB,
// GStreamer, ...) that the dynamic loader mapped at every start of every
// binary linking it: about 250 ms before `lockstep --version` printed a line
// (issue #21, one-shot cost). So no binary of ours links it: the calls live in
// io/oiio_module.cpp, built as lockstep_oiio.so beside the lockstep binary
// (found and opened by core/module.h, like the peer rows' modules), and the
// functions that need them (read_image, write_image, read_layer and the
// image output kind's check of an output path for any format but .exr and
// .png, which io/image_io.cpp reads and writes without it; compare_images,
// error_heatmap, the kinds' beside picture, the composite family's oiio row)
// open it the first time one of them runs. `lockstep --version` reads OpenImageIO's
// version from lockstep_oiio.version, written beside the module when it is
// built, so it does not open it.
//
// The module holds no state of ours. Its functions throw nothing: an error
// comes back as an Error and is thrown here (InputError with the file, line
// and words it was made with; std::bad_alloc; std::runtime_error), so the
// messages, exit codes and "nothing half written" rules are the functions'
// own, unchanged by where they run.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/image.h"
#include "core/texture.h"
#include "io/layers.h"

namespace lockstep::oiio {

// The module's file, beside the binary; its version file is lockstep_oiio.version.
inline constexpr const char* kModuleFile = "lockstep_oiio.so";
// Host and module from one build: bump when the table or the types it passes change.
inline constexpr int kAbi = 3;

struct Error {
  enum class Kind : uint8_t { input, out_of_memory, other } kind = Kind::other;
  std::string file;  // Kind::input: InputError's file, line and words
  int line = 0;
  std::string what;
};

// ImageBufAlgo::compare's result (what kinds/image_metrics.cpp uses of it).
struct CompareStats {
  double max_error = 0, mean_error = 0, rms_error = 0, psnr = 0;
  int max_x = -1, max_y = -1;
  long failed = 0, warned = 0;
};

// Texture lookups for the texture family's oiio row (optimized/texture_oiio.cpp):
// n footprints as texture coordinates (s, t) and their derivatives along
// pixel x and y, OpenImageIO's units (1 = the texture's width or height).
struct TextureLookups {
  const float *s, *t, *dsdx, *dtdx, *dsdy, *dtdy;
  size_t n = 0;
};
// OpenImageIO's TextureSystem modes the row uses.
enum class TextureMode : int { closest, bilinear, one_level, trilinear, aniso };

// The module's table (lockstep_peer_api() in lockstep_oiio.so). Every function
// returning bool fills *err when it returns false.
struct ModuleApi {
  int abi;
  // core/image.h's read_image and write_image.
  bool (*read_image)(const std::string& path, Image* out, Error* err);
  bool (*write_image)(const Image& image, const std::string& path,
                      const std::string& exr_compression, Error* err);
  // io/layers.h's read_layer (alpha_override: nullptr for none).
  bool (*read_layer)(const std::string& path, const Alpha* alpha_override, Layer* out, Error* err);
  // Whether OpenImageIO has a writer for path's extension.
  bool (*has_writer)(const std::string& path);
  // ImageBufAlgo::compare of two images of one size, at the two thresholds.
  void (*compare)(const Image& a, const Image& b, float fail, float warn, CompareStats* out);
  // error_heatmap's colours (kinds/image_metrics.h) before NaN pixels are marked.
  bool (*heatmap)(const Image& a, const Image& b, double scale, Image* out, Error* err);
  // `in` scaled to w x h (a filtered resize) and written to `out` as 8 bits.
  bool (*write_resized)(const std::string& in, const std::string& out, int w, int h, Error* err);
  // ImageBufAlgo::over, chained over a checked stack (optimized/composite_oiio.cpp).
  bool (*over)(const LayerStack& stack, int threads, Image* out, Error* err);
  // The texture made tiled and mipmapped by ImageBufAlgo::make_texture (a
  // temporary .tx file, removed by texture_close) and a TextureSystem opened
  // on it: a handle for many frames, or nullptr with err filled.
  void* (*texture_open)(const Texture& tex, Error* err);
  // One TextureSystem::texture call per lookup on `threads` threads (0: all
  // cores): RGBA into out (4 n floats).
  bool (*texture_lookups)(void* handle, const TextureLookups& in, TextureMode mode, int aniso, int threads,
                          float* out, Error* err);
  void (*texture_close)(void* handle);
};

// The module's table, opened on the first call. Throws InputError naming the
// module when it is not found or does not open (exit code 2 in the CLI).
const ModuleApi& api();
// Throws what the module reported in err.
[[noreturn]] void raise(const Error& err);
// OpenImageIO's version as recorded beside the module when it was built
// ("" when lockstep_oiio.version is not found); does not open the module.
std::string recorded_version();

}  // namespace lockstep::oiio
