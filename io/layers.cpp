// lockstep io: layer stacks -- the .stack reader and layer loading.
//
// Layers are read by read_layer (io/image_io.cpp: .exr and .png through
// OpenEXR and libpng, the rest through OpenImageIO, whose body is in
// io/oiio_module.cpp, the module lockstep_oiio.so opened on first use:
// io/oiio.h). Integer
// formats (PNG, 8-bit TIFF, ...) are read with the `oiio:UnassociatedAlpha`
// config so that OIIO hands back the file's straight values instead of premultiplying them on the way in; float
// formats (EXR) are premultiplied by OpenEXR's definition. An explicit override
// (`--alpha`, or a .stack file's `alpha` line) wins over both.
//
// Every error is an InputError naming the file (and the line of a .stack file):
// we say what is wrong rather than guess (e.g. an RGB file is not given an alpha
// of 1: compositing it would silently hide everything behind it).
#include "io/layers.h"

#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "io/tokenizer.h"

namespace lockstep {

namespace {

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

LayerStack read_stack(const std::string& path, std::optional<Alpha> alpha_override) {
  namespace fs = std::filesystem;
  const std::string text = text::read_text_file(path,
                                                {.missing = "cannot read stack: no such file",
                                                 .folder = "cannot read stack: is a directory",
                                                 .unreadable = "cannot read stack: cannot open file",
                                                 .read_error = "cannot read stack: read error"},
                                                text::kMaxListBytes);
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
  text::Tokenizer in(text, path, {.comments = text::Comments::line_start});
  while (in.next()) {
    const auto& w = in.words();
    if (w.size() == 1) {
      // One word: a layer's file name. File names need an extension (OIIO picks
      // the format from it), so a bare word is a misspelt keyword.
      const std::string s(w[0]);
      if (s.find('.') == std::string::npos && s.find('/') == std::string::npos)
        in.fail("unknown keyword '" + s + "' (or a layer file without an extension)");
      entries.push_back({s, in.line_no()});
      continue;
    }
    const std::string key(w[0]);
    const std::string value(in.rest(1));
    if (key == "alpha") {
      stack_alpha = parse_alpha(value);
      if (!stack_alpha) in.fail("alpha must be 'straight' or 'premultiplied', not '" + value + "'");
    } else if (key == "order") {
      const auto o = parse_order(value);
      if (!o) in.fail("order must be 'ftb' or 'btf', not '" + value + "'");
      stack.order = *o;
    } else if (key == "storage") {
      storage = parse_storage(value);
      if (!storage) in.fail("storage must be 'float' or 'unorm8', not '" + value + "'");
    } else if (key == "early_stop") {
      if (value == "on" || value == "yes" || value == "1") {
        stack.early_stop = true;
      } else if (value == "off" || value == "no" || value == "0") {
        stack.early_stop = false;
      } else {
        in.fail("early_stop must be 'on' or 'off', not '" + value + "'");
      }
    } else {
      in.fail("unknown keyword '" + key + "' (expected alpha, order, storage, early_stop, or one layer file per line)");
    }
  }
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
