// lockstep render: one scene, one implementation, one image.
#include <cstdio>
#include <string>

#include "app/cli.h"
#include "core/image.h"
#include "core/nff.h"

namespace lockstep::cli {

namespace {

void print_help() {
  std::printf(
      "usage: lockstep render SCENE.nff [--impl NAME] [--size WxH] [--threads N] -o OUT\n"
      "\n"
      "Ray casts an NFF scene and writes the image; the format follows OUT's extension\n"
      "(.exr and .tif keep float values, .png clamps to 8 bits).\n"
      "\n"
      "  --impl NAME     implementation, one of: %s (default: auto)\n"
      "  --size WxH      image size, 1..%d each (default: the scene's 'resolution')\n"
      "  --threads N     worker threads, N >= 1 (default: all cores; the reference is single-threaded)\n"
      "  -o, --output F  the image to write (required)\n"
      "\n"
      "Prints one summary line (implementation, size, build and trace seconds, rays/s,\n"
      "and which implementation 'auto' chose) on stderr.\n"
      "Exit codes: 0 ok, 2 bad usage or bad scene (nothing written), 3 internal error.\n",
      impl_names().c_str(), kMaxResolution);
}

std::string rate(double per_second) {
  char buf[32];
  if (per_second >= 1e6) std::snprintf(buf, sizeof buf, "%.2fM", per_second / 1e6);
  else if (per_second >= 1e3) std::snprintf(buf, sizeof buf, "%.1fk", per_second / 1e3);
  else std::snprintf(buf, sizeof buf, "%.0f", per_second);
  return buf;
}

}  // namespace

int render_main(Args args) {
  std::string scene_path, out_path, impl_name = "auto", value;
  int width = 0, height = 0, threads = 0;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string_view a = args[i];
    if (a == "--help" || a == "-h") {
      print_help();
      return kExitOk;
    } else if (take_option(args, i, "--impl", value)) {
      impl_name = value;
    } else if (take_option(args, i, "--size", value)) {
      parse_size(value, width, height);
    } else if (take_option(args, i, "--threads", value)) {
      threads = int(parse_long("--threads", value, 1, 4096));
    } else if (take_option(args, i, "-o", value) || take_option(args, i, "--output", value)) {
      out_path = value;
    } else if (is_option(a)) {
      unknown_option(a);
    } else if (scene_path.empty()) {
      scene_path = std::string(a);
    } else {
      throw UsageError("unexpected argument '" + std::string(a) + "' (one scene per call)");
    }
  }
  if (scene_path.empty()) throw UsageError("missing SCENE");
  if (out_path.empty()) throw UsageError("missing -o OUT");
  const Impl<CasterFns>& impl = find_impl(impl_name);

  // Everything that can be wrong with the input is found before rendering, so
  // an error never leaves an output behind.
  check_output_image(out_path);
  const Scene scene = read_nff(scene_path);

  RenderOptions opts;
  opts.width = width > 0 ? width : scene.view.xres;
  opts.height = height > 0 ? height : scene.view.yres;
  opts.threads = threads;
  Progress progress("lockstep render: " + std::string(impl.name));
  opts.progress = [&progress](double f) { progress(f); };

  RenderStats stats;
  const auto start = std::chrono::steady_clock::now();
  Image image;
  try {
    image = impl.fn.render(scene, opts, &stats);
  } catch (...) {
    progress.finish();
    throw;
  }
  const double wall = seconds_since(start);
  progress.finish();
  write_image(image, out_path);

  const double trace_s = stats.trace_seconds > 0 ? stats.trace_seconds : wall;
  std::string line = "lockstep render: " + std::string(impl.name) + " " + std::to_string(opts.width) + "x" +
                     std::to_string(opts.height);
  char buf[160];
  std::snprintf(buf, sizeof buf, " build %.3f s, trace %.3f s, %s rays/s, wall %.3f s", stats.build_seconds,
                stats.trace_seconds, rate(double(stats.rays) / trace_s).c_str(), wall);
  line += buf;
  if (!stats.chosen.empty()) line += ", chose " + stats.chosen;
  line += " -> " + out_path;
  std::fprintf(stderr, "%s\n", line.c_str());
  return kExitOk;
}

}  // namespace lockstep::cli
