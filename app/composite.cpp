// lockstep composite: a stack of layers, one implementation of the compositing
// family, one image (premultiplied RGBA; PNG output is stored straight, as the
// format defines it).
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "app/cli.h"
#include "app/run.h"
#include "io/layers.h"
#include "core/timer.h"

namespace lockstep::cli {

namespace {

void print_help(const Family& f) {
  std::printf(
      "usage: lockstep composite LAYER... | --stack FILE  -o OUT\n"
      "                          [--alpha straight|premultiplied] [--order ftb|btf]\n"
      "                          [--storage float|unorm8] [--no-early-stop] [--impl NAME] [--threads N]\n"
      "\n"
      "Composites RGBA layers with 'over', FRONT FIRST, into one image; the format follows\n"
      "OUT's extension. A PNG (8-bit) layer is straight alpha by its format's definition, an\n"
      "EXR layer premultiplied; --alpha overrides both. A .stack file lists one layer per line\n"
      "(paths relative to it) and may say 'alpha ...', 'order ...', 'storage ...'.\n"
      "\n"
      "  --stack FILE        the layers from a .stack file\n"
      "  --alpha A           every layer is straight or premultiplied (default: by format)\n"
      "  --order O           ftb: front to back, stopping where alpha reaches 1 (default);\n"
      "                      btf: back to front\n"
      "  --storage S         float (default) or unorm8: 8-bit premultiplied arithmetic\n"
      "  --no-early-stop     front to back without early termination\n"
      "  --impl NAME         one of: %s (default: %.*s)\n"
      "  --threads N         worker threads, N >= 1 (default: all cores; the reference is single-threaded)\n"
      "  --repeat N          composite N times in this process (default 1): the summary gives the\n"
      "                      last (warm) and the first\n"
      "  -o, --output F      the image to write (required)\n"
      "\n"
      "Prints one line on stderr: implementation, size, layers, seconds and output Mpix/s\n"
      "(output pixels per second, reading and writing files excluded).\n"
      "Bad input (mismatched sizes, a layer without alpha, NaN or negative values, an\n"
      "unreadable file, an empty stack): one line naming the file, exit 2, nothing written.\n",
      impl_names(f).c_str(), int(f.default_impl.size()), f.default_impl.data());
}

}  // namespace

int composite_main(Args args) {
  const Family& family = find_family("composite");
  std::string stack_path, out_path, impl_name, value;
  std::vector<std::string> layers;
  std::optional<Alpha> alpha;
  std::optional<Order> order;
  std::optional<Storage> storage;
  bool no_early_stop = false;
  int threads = 0, repeat = 1;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string_view a = args[i];
    if (a == "--help" || a == "-h") {
      print_help(family);
      return kExitOk;
    } else if (take_option(args, i, "--stack", value)) {
      stack_path = value;
    } else if (take_option(args, i, "--alpha", value)) {
      alpha = parse_alpha(value);
      if (!alpha) throw UsageError("--alpha must be straight or premultiplied, got '" + value + "'");
    } else if (take_option(args, i, "--order", value)) {
      order = parse_order(value);
      if (!order) throw UsageError("--order must be ftb or btf, got '" + value + "'");
    } else if (take_option(args, i, "--storage", value)) {
      storage = parse_storage(value);
      if (!storage) throw UsageError("--storage must be float or unorm8, got '" + value + "'");
    } else if (a == "--no-early-stop") {
      no_early_stop = true;
    } else if (take_option(args, i, "--impl", value)) {
      impl_name = value;
    } else if (take_option(args, i, "--threads", value)) {
      threads = int(parse_long("--threads", value, 1, 4096));
    } else if (take_option(args, i, "--repeat", value)) {
      repeat = int(parse_long("--repeat", value, 1, 1000));
    } else if (take_option(args, i, "-o", value) || take_option(args, i, "--output", value)) {
      out_path = value;
    } else if (is_option(a)) {
      unknown_option(a);
    } else {
      layers.emplace_back(a);
    }
  }
  if (!stack_path.empty() && !layers.empty()) throw UsageError("give LAYER... or --stack FILE, not both");
  if (stack_path.empty() && layers.empty()) throw UsageError("missing LAYER... or --stack FILE");
  if (out_path.empty()) throw UsageError("missing -o OUT");
  const FamilyImpl& impl = find_impl(family, impl_name.empty() ? family.default_impl : impl_name);

  // Everything that can be wrong with the input is found before compositing, so
  // an error never leaves an output behind.
  family.kind->check_path(out_path);
  const Stopwatch reading;
  LayerStack stack = stack_path.empty() ? read_layers(layers, alpha) : read_stack(stack_path, alpha);
  if (order) stack.order = *order;
  if (no_early_stop) stack.early_stop = false;
  if (storage == Storage::unorm8 && stack.storage != Storage::unorm8) to_unorm8(stack);
  if (storage == Storage::f32) stack.storage = Storage::f32;
  check_stack(stack);
  const double read_s = reading.seconds();
  const int w = stack.width(), h = stack.height();
  const size_t n = stack.layers.size();
  const std::string mode = std::string(name_of(stack.order)) + ", " + name_of(stack.storage) +
                           (stack.order == Order::front_to_back && !stack.early_stop ? ", no early stop" : "");
  const Input input = make_input<LayerStack>(std::move(stack), stack_path.empty() ? layers.front() : stack_path, w, h);

  FrameOptions opts;
  opts.threads = threads;
  Run r = run_for_cli("lockstep composite", family, impl, input, opts);
  const double first_seconds = r.seconds;
  for (int k = 1; k < repeat; ++k) {  // each once the one before is released (render's --repeat)
    r = Run{};
    r = run_for_cli("lockstep composite", family, impl, input, opts);
  }
  const Stopwatch writing;
  family.kind->write(r.out, out_path);
  std::fprintf(stderr,
               "lockstep composite: %s %dx%d, %zu layers (%s), %.3f s, %.1f Mpix/s (read %.3f s, write %.3f s)%s -> %s\n",
               std::string(impl.name).c_str(), w, h, n, mode.c_str(), r.seconds,
               double(w) * double(h) / (r.seconds > 0 ? r.seconds : 1e-9) / 1e6, read_s, writing.seconds(),
               (resource_text(r) + repeat_text(repeat, first_seconds)).c_str(), out_path.c_str());
  return kExitOk;
}

}  // namespace lockstep::cli
