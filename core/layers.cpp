// lockstep core: layer stacks -- the .stack reader and layer loading.
//
// Layers go through OpenImageIO. Integer formats (PNG, 8-bit TIFF, ...) are
// read with the `oiio:UnassociatedAlpha` config so that OIIO hands back the
// file's straight values instead of premultiplying them on the way in; float
// formats (EXR) are premultiplied by OpenEXR's definition. An explicit override
// (`--alpha`, or a .stack file's `alpha` line) wins over both.
//
// Every error is an InputError naming the file (and the line of a .stack file):
// we say what is wrong rather than guess (e.g. an RGB file is not given an alpha
// of 1: compositing it would silently hide everything behind it).
#include "core/layers.h"

#include "core/quiet_stderr.h"

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace lockstep {

namespace {

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

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const size_t e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

// Size mismatch message naming both files.
void check_same_size(const Layer& first, const Layer& l, const std::string& file, int line) {
  if (l.image.width == first.image.width && l.image.height == first.image.height) return;
  throw InputError(file, line,
                   "layer '" + l.source + "' is " + std::to_string(l.image.width) + "x" +
                       std::to_string(l.image.height) + " but layer '" + first.source + "' is " +
                       std::to_string(first.image.width) + "x" +
                       std::to_string(first.image.height) +
                       "; every layer of a stack must have the same size");
}

}  // namespace

Layer read_layer(const std::string& path, std::optional<Alpha> alpha_override) {
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

LayerStack read_stack(const std::string& path, std::optional<Alpha> alpha_override) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, 0, "cannot read stack: no such file");
  if (fs::is_directory(path, ec)) throw InputError(path, 0, "cannot read stack: is a directory");
  std::ifstream f(path);
  if (!f) throw InputError(path, 0, "cannot read stack: cannot open file");
  const fs::path folder = fs::path(path).parent_path();

  LayerStack stack;
  stack.source = path;
  std::optional<Alpha> stack_alpha;
  std::optional<Storage> storage;
  struct Entry {
    std::string file;
    int line;
  };
  std::vector<Entry> entries;
  std::string raw;
  int line = 0;
  while (std::getline(f, raw)) {
    ++line;
    const std::string s = trim(raw);
    if (s.empty() || s[0] == '#') continue;
    const size_t sp = s.find_first_of(" \t");
    if (sp == std::string::npos) {
      // One word: a layer's file name. File names need an extension (OIIO picks
      // the format from it), so a bare word is a misspelt keyword.
      if (s.find('.') == std::string::npos && s.find('/') == std::string::npos)
        throw InputError(path, line,
                         "unknown keyword '" + s + "' (or a layer file without an extension)");
      entries.push_back({s, line});
      continue;
    }
    const std::string key = s.substr(0, sp);
    const std::string value = trim(s.substr(sp));
    if (key == "alpha") {
      stack_alpha = parse_alpha(value);
      if (!stack_alpha)
        throw InputError(path, line,
                         "alpha must be 'straight' or 'premultiplied', not '" + value + "'");
    } else if (key == "order") {
      const auto o = parse_order(value);
      if (!o) throw InputError(path, line, "order must be 'ftb' or 'btf', not '" + value + "'");
      stack.order = *o;
    } else if (key == "storage") {
      storage = parse_storage(value);
      if (!storage)
        throw InputError(path, line, "storage must be 'float' or 'unorm8', not '" + value + "'");
    } else if (key == "early_stop") {
      if (value == "on" || value == "yes" || value == "1") {
        stack.early_stop = true;
      } else if (value == "off" || value == "no" || value == "0") {
        stack.early_stop = false;
      } else {
        throw InputError(path, line, "early_stop must be 'on' or 'off', not '" + value + "'");
      }
    } else {
      throw InputError(
          path, line,
          "unknown keyword '" + key +
              "' (expected alpha, order, storage, early_stop, or one layer file per line)");
    }
  }
  if (f.bad()) throw InputError(path, 0, "cannot read stack: read error");
  if (entries.empty()) throw InputError(path, 0, "stack has no layers");

  const std::optional<Alpha> alpha = alpha_override ? alpha_override : stack_alpha;
  for (const Entry& e : entries) {
    const fs::path p = fs::path(e.file).is_absolute() ? fs::path(e.file) : folder / e.file;
    try {
      stack.layers.push_back(read_layer(p.string(), alpha));
    } catch (const InputError& err) {
      // The layer's own message (naming the layer file) at the .stack line that names it.
      throw InputError(path, e.line, err.what());
    }
    check_same_size(stack.layers.front(), stack.layers.back(), path, e.line);
  }
  if (storage == Storage::unorm8) to_unorm8(stack);
  return stack;
}

LayerStack read_layers(const std::vector<std::string>& paths, std::optional<Alpha> alpha_override) {
  LayerStack stack;
  if (paths.empty()) throw InputError("(no layers)", 0, "stack has no layers");
  stack.source = paths.front();
  for (const std::string& p : paths) {
    stack.layers.push_back(read_layer(p, alpha_override));
    check_same_size(stack.layers.front(), stack.layers.back(), p, 0);
  }
  return stack;
}

void check_stack(const LayerStack& stack) {
  const std::string& src = stack.source.empty() ? std::string("(stack)") : stack.source;
  if (stack.layers.empty()) throw InputError(src, 0, "stack has no layers");
  const Layer& first = stack.layers.front();
  if (first.image.width <= 0 || first.image.height <= 0)
    throw InputError(src, 0, "layer '" + first.source + "' has no pixels");
  const size_t n = size_t(first.image.width) * size_t(first.image.height) * 4;
  for (const Layer& l : stack.layers) {
    check_same_size(first, l, src, 0);
    if (stack.storage == Storage::unorm8) {
      if (l.rgba8.size() != n)
        throw InputError(
            src, 0,
            "layer '" + l.source + "' has no 8-bit pixels (storage unorm8 needs to_unorm8)");
    } else if (l.image.rgba.size() != n) {
      throw InputError(src, 0,
                       "layer '" + l.source + "' holds " + std::to_string(l.image.rgba.size()) +
                           " floats, not width * height * 4 = " + std::to_string(n));
    }
  }
}

void to_unorm8(LayerStack& stack) {
  for (Layer& l : stack.layers) {
    l.rgba8.resize(l.image.rgba.size());
    for (size_t i = 0; i < l.image.rgba.size(); ++i) {
      const float v = l.image.rgba[i];
      // Clamp first (NaN -> 0), then round half away from zero: v * 255 >= 0 here.
      const float c = v > 0 ? (v < 1 ? v : 1.0f) : 0.0f;
      l.rgba8[i] = uint8_t(std::lround(c * 255.0f));
    }
  }
  stack.storage = Storage::unorm8;
}

std::optional<Alpha> parse_alpha(const std::string& s) {
  if (s == "straight") return Alpha::straight;
  if (s == "premultiplied") return Alpha::premultiplied;
  return std::nullopt;
}
std::optional<Order> parse_order(const std::string& s) {
  if (s == "ftb") return Order::front_to_back;
  if (s == "btf") return Order::back_to_front;
  return std::nullopt;
}
std::optional<Storage> parse_storage(const std::string& s) {
  if (s == "float") return Storage::f32;
  if (s == "unorm8") return Storage::unorm8;
  return std::nullopt;
}
const char* name_of(Alpha a) { return a == Alpha::straight ? "straight" : "premultiplied"; }
const char* name_of(Order o) { return o == Order::front_to_back ? "ftb" : "btf"; }
const char* name_of(Storage s) { return s == Storage::f32 ? "float" : "unorm8"; }

}  // namespace lockstep
