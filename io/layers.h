// lockstep io: layer stacks, the input of the compositing family.
//
// A stack is an ordered list of RGBA layers of one size, FRONT FIRST, each
// marked straight or premultiplied alpha. It is read from image files (any
// format OpenImageIO reads) or from a `.stack` file:
//
//   # comment
//   alpha straight|premultiplied     optional: overrides every layer's own marking
//   order ftb|btf                    optional: front-to-back (default) or back-to-front
//   storage float|unorm8             optional: composite in float (default) or 8 bits
//   early_stop on|off                optional: front-to-back stops where alpha reaches 1 (default on)
//   front.png                        one layer per line, front first; paths are
//   back.exr                         relative to the .stack file
//
// Without an override a PNG (or any 8-bit integer format) layer is straight
// alpha (its format's definition) and an EXR layer premultiplied (OpenEXR's).
//
// Storage: with unorm8 every layer is also held as 8-bit RGBA (rgba8,
// quantised once by to_unorm8) in the layer's own representation; straight
// layers are premultiplied in 8 bits (ref::premultiply8) when composited, the
// way 8-bit compositors do it. The float pixels are then ignored by the
// implementations (image.width/height still give the size).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"

namespace lockstep {

enum class Alpha : uint8_t { straight, premultiplied };
enum class Order : uint8_t { front_to_back, back_to_front };
enum class Storage : uint8_t { f32, unorm8 };

struct Layer {
  Image image;                 // float RGBA as the file holds it (straight or premultiplied per `alpha`)
  Alpha alpha = Alpha::premultiplied;
  // Storage::unorm8 only: 8-bit RGBA in this layer's `alpha` representation (Image's
  // allocator: large buffers page-aligned and a page apart, see core/image.h)
  std::vector<uint8_t, NoInitAllocator<uint8_t>> rgba8;
  std::string source;          // file name, for messages
};

struct LayerStack {
  std::vector<Layer> layers;  // front first
  Order order = Order::front_to_back;
  Storage storage = Storage::f32;
  bool early_stop = true;     // front-to-back: stop where the accumulated alpha reaches 1
  std::string source;         // the .stack file, or the first layer's file
  int width() const { return layers.empty() ? 0 : layers.front().image.width; }
  int height() const { return layers.empty() ? 0 : layers.front().image.height; }
};

// Reads one layer. Throws InputError (naming the file) when it is unreadable or
// truncated, or has no alpha channel ("say so; don't guess"), or holds NaN or
// negative values.
Layer read_layer(const std::string& path, std::optional<Alpha> alpha_override);
// Reads a .stack file (format above). Throws InputError naming file:line.
LayerStack read_stack(const std::string& path, std::optional<Alpha> alpha_override);
// Layers given one by one, front first.
LayerStack read_layers(const std::vector<std::string>& paths, std::optional<Alpha> alpha_override);
// Throws InputError when the stack is empty or its layers differ in size.
void check_stack(const LayerStack& stack);
// Fills every layer's rgba8 (round(v * 255) of the clamped value) and sets storage = unorm8.
void to_unorm8(LayerStack& stack);

// Parses "straight" / "premultiplied", "ftb" / "btf", "float" / "unorm8"; nullopt otherwise.
std::optional<Alpha> parse_alpha(const std::string& s);
std::optional<Order> parse_order(const std::string& s);
std::optional<Storage> parse_storage(const std::string& s);
const char* name_of(Alpha a);
const char* name_of(Order o);
const char* name_of(Storage s);

}  // namespace lockstep
