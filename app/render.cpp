// lockstep render: one input, one implementation, one output (an image, for
// every family so far; written by the family's output kind). The family is
// the one whose files end in the input's extension (registry/registry.h).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <future>
#include <optional>
#include <string>
#include <vector>

#include "app/cli.h"
#include "app/run.h"
#include "optimized/tiling.h"

namespace lockstep::cli {

namespace {

void print_help() {
  std::printf(
      "usage: lockstep render INPUT [--algo NAME] [SETTINGS] [--impl NAME] [--size WxH] [--threads N] -o OUT\n"
      "\n"
      "Renders INPUT with one implementation of the family that reads it and writes the\n"
      "image; the format follows OUT's extension (.exr and .tif keep float values, .png\n"
      "clamps to 8 bits). .exr is written lossless with fast zlib (OpenEXR \"zips\", level 1).\n"
      "\n");
  for (const Family& f : registry().families)
    std::printf("  %-10s %s from %s; --impl %s (default: %.*s)\n", std::string(f.name).c_str(),
                std::string(f.what).c_str(), std::string(f.input).c_str(), impl_names(f, "|").c_str(),
                int(f.default_impl.size()), f.default_impl.data());
  std::printf("\n  --algo NAME     which family draws an input of a shared extension (default: the first):\n");
  std::vector<std::string_view> exts;
  for (const Family& f : registry().families)
    if (!f.algo.empty() && std::find(exts.begin(), exts.end(), f.extension) == exts.end()) exts.push_back(f.extension);
  for (const std::string_view ext : exts) {
    std::printf("                  %.*s:", int(ext.size()), ext.data());
    for (const Family& f : registry().families)
      if (f.extension == ext && !f.algo.empty()) std::printf(" %s", std::string(f.algo).c_str());
    std::printf("\n");
  }
  for (const Alias& a : registry().aliases)
    std::printf("                  %.*s: the old name of %.*s, still accepted\n",
                int(a.old_name.size()), a.old_name.data(), int(a.name.size()), a.name.data());
  // Families with the same settings (the raster families) are listed together.
  std::vector<const Family*> done;
  for (const Family& f : registry().families) {
    if (f.params.empty()) continue;
    auto same = [&f](const Family& g) {
      if (g.params.size() != f.params.size()) return false;
      for (size_t k = 0; k < g.params.size(); ++k)
        if (g.params[k].name != f.params[k].name) return false;
      return true;
    };
    bool seen = false;
    for (const Family* d : done) seen = seen || same(*d);
    if (seen) continue;
    done.push_back(&f);
    std::string names;
    for (const Family& g : registry().families)
      if (same(g)) {
        if (!names.empty()) names += ", ";
        names += g.name;
      }
    std::printf("\n  settings of %s:\n", names.c_str());
    for (const ParamSpec& p : f.params) {
      std::string left = "--";
      left += p.name;
      if (!p.flag) {
        left += ' ';
        left += p.values;
      }
      std::printf("    %-44s %s%s%s\n", left.c_str(), std::string(p.help).c_str(), p.def.empty() ? "" : "; default ",
                  std::string(p.def).c_str());
    }
  }
  for (const Family& f : registry().families) {
    if (f.sides.empty()) continue;
    std::printf("\n  files %s also writes, on request:\n", std::string(f.name).c_str());
    for (const SideOutput& side : f.sides)
      std::printf("    %-44s %s\n", ("--" + std::string(side.name) + " FILE").c_str(), std::string(side.help).c_str());
  }
  std::printf(
      "\n"
      "  --impl NAME     implementation (default: the family's, above)\n"
      "  --size WxH      image size, 1..%d each (default: the input's own; ray_cast: 'resolution')\n"
      "  --threads N     worker threads, N >= 1 (default: all cores; the reference is single-threaded)\n"
      "  --repeat N      draw the frame N times in this process, 1..1000 (default 1): the summary\n"
      "                  gives the last frame (warm: the memory of the frames before) and the first\n"
      "  -o, --output F  the image to write (required)\n"
      "\n"
      "Prints one summary line (implementation, size, build and run seconds, rate, the frame's\n"
      "page faults and system time and the call's so far, and which implementation 'auto'\n"
      "chose) on stderr.\n"
      "Exit codes: 0 ok, 2 bad usage or bad input (nothing written), 3 internal error.\n",
      kMaxResolution);
}

}  // namespace

// The summary line of render and composite: "lockstep render: simd 512x512 build
// 0.000 s, trace 0.010 s, 26.21M rays/s, wall 0.010 s".
std::string run_summary(const std::string& who, const Family& f, const FamilyImpl& impl, const Run& r) {
  const double run_s = r.seconds - r.stats.build_seconds;
  char buf[200];
  std::snprintf(buf, sizeof buf, " %s build %.3f s, %.*s %.3f s, %s %.*s/s, wall %.3f s",
                f.kind->shape(r.out).c_str(), r.stats.build_seconds, int(f.verb.size()), f.verb.data(), run_s,
                rate(double(r.stats.items) / (run_s > 0 ? run_s : 1e-9)).c_str(), int(f.unit.size()), f.unit.data(),
                r.seconds);
  std::string line = who + ": " + std::string(impl.name) + buf + resource_text(r);
  if (!r.stats.chosen.empty()) line += ", chose " + r.stats.chosen;
  if (r.stats.skipped != 0)
    line += ", " + std::to_string(r.stats.skipped) + " " + std::string(f.unit) + " hidden (skipped)";
  // What the run could not draw, with why (issue #22: nothing dropped silently).
  if (!r.stats.dropped.empty()) line += ", " + r.stats.dropped_text();
  return line;
}

std::string resource_text(const Run& r) {
  // Issue #35: a one-shot call's cost is largely first touch of fresh pages.
  const ResourceUse call = resource_use();
  char buf[200];
  std::snprintf(buf, sizeof buf, " (%ld page faults, system %.3f s; the call so far: %ld, %.3f s)",
                r.used.minor_faults + r.used.major_faults, r.used.system_seconds,
                call.minor_faults + call.major_faults, call.system_seconds);
  return buf;
}

std::string repeat_text(int repeat, double first_seconds) {
  if (repeat <= 1) return "";
  char buf[120];
  std::snprintf(buf, sizeof buf, "; frame %d of %d, the first: wall %.3f s", repeat, repeat, first_seconds);
  return buf;
}

Run run_for_cli(const std::string& who, const Family& family, const FamilyImpl& impl, const Input& input,
                FrameOptions opts) {
  Progress progress(who + ": " + std::string(impl.name));
  opts.progress = [&progress](double f) { progress(f); };
  Run r;
  const ResourceUse before = resource_use();
  try {
    r = run_frame(family, impl, input, opts, false);
  } catch (...) {
    progress.finish();
    throw;
  }
  const ResourceUse after = resource_use();
  r.used.minor_faults = after.minor_faults - before.minor_faults;
  r.used.major_faults = after.major_faults - before.major_faults;
  r.used.system_seconds = after.system_seconds - before.system_seconds;
  r.used.user_seconds = after.user_seconds - before.user_seconds;
  progress.finish();
  if (!r.ok) throw std::runtime_error(std::string(impl.name) + " " + r.error);
  return r;
}

// The family that draws in_path: the one of that extension whose algo is
// `algo` ("raycast" is ray_cast; an old spelling of a family's name, the
// registry's aliases, counts as that name), or the first of that extension.
const Family& family_for(const std::string& in_path, const std::string& algo) {
  const Family& first = family_for_path(in_path);
  if (algo.empty()) return first;
  const std::string_view want = registry().canonical(algo);
  // An algorithm only other extensions' families have: say which files they read.
  std::string readers;
  bool here = false;
  for (const Family& f : registry().families) {
    if (f.algo != want) continue;
    here = here || f.extension == first.extension;
    if (!readers.empty()) readers += " or ";
    readers += f.input;
  }
  if (!here && !readers.empty())
    throw UsageError("'" + in_path + "' is not " + readers + ": what " + std::string(want) + " draws");
  std::string known;
  for (const Family& f : registry().families) {
    if (f.extension != first.extension || f.algo.empty()) continue;
    if (f.algo == want) return f;
    // Appended piece by piece: `"|" + std::string(...)` trips GCC 12's -Wrestrict (a false positive).
    if (!known.empty()) known += '|';
    known += f.algo;
  }
  throw UsageError("--algo: '" + algo + "' is not one of " + known + " for " + std::string(first.extension) + " files");
}

const SideOutput* find_side(const Family& f, std::string_view option) {
  for (const SideOutput& side : f.sides)
    if (option.size() > 2 && option.substr(0, 2) == "--" && (option.substr(2) == side.name ||
                                                             option.substr(2).starts_with(std::string(side.name) + "=")))
      return &side;
  return nullptr;
}

// The side outputs after the output: each written atomically; when one
// fails, the files written before it (the output too) are removed, so a
// call leaves all of its files or none.
void write_sides(const std::vector<std::pair<const SideOutput*, std::string>>& side_paths, const FrameStats& stats,
                 const std::string& out_path) {
  std::vector<std::string> written = {out_path};
  try {
    for (const auto& [side, path] : side_paths) {
      const Output* value = nullptr;
      for (const auto& [name, v] : stats.sides)
        if (name == side->name) value = &v;
      if (!value) throw std::runtime_error("the run made no " + std::string(side->name) + " for --" + std::string(side->name));
      side->write(*value, path);
      written.push_back(path);
    }
  } catch (...) {
    std::error_code ec;
    for (const std::string& w : written) std::filesystem::remove(w, ec);
    throw;
  }
}

int render_main(Args args) { return render_as("lockstep render", "", args); }

int render_subcommand(const std::string& who, const std::string& forced_algo, Args args, void (*help)()) {
  for (const std::string_view a : args)
    if (a == "--help" || a == "-h") {
      help();
      return kExitOk;
    }
  return render_as(who, forced_algo, args);
}

int render_as(const std::string& who, const std::string& forced_algo, Args args) {
  std::string in_path, out_path, impl_name, value, algo = forced_algo;
  std::vector<std::pair<const SideOutput*, std::string>> side_paths;  // --patches OUT.ply
  int width = 0, height = 0, threads = 0, repeat = 1;
  // --algo and the input first: they decide which family's settings the other
  // options may name. Every option but --help and the families' flags takes a
  // value, which is not the input.
  auto takes_value = [](std::string_view a) {
    if (a == "--help" || a == "-h" || a.find('=') != std::string_view::npos) return false;
    for (const Family& f : registry().families)
      if (const ParamSpec* p = find_param(f, a); p && p->flag) return false;
    return true;
  };
  for (size_t i = 0; i < args.size(); ++i)
    if (take_option(args, i, "--algo", value)) algo = value;
    else if (is_option(args[i])) i += takes_value(args[i]) ? 1 : 0;
    else if (in_path.empty()) in_path = std::string(args[i]);
  const Family* chosen = nullptr;
  if (!in_path.empty()) chosen = &family_for(in_path, algo);
  in_path.clear();
  Params params;
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
    } else if (take_option(args, i, "--repeat", value)) {
      repeat = int(parse_long("--repeat", value, 1, 1000));
    } else if (take_option(args, i, "-o", value) || take_option(args, i, "--output", value)) {
      out_path = value;
    } else if (take_option(args, i, "--algo", value)) {
      // read above
    } else if (const SideOutput* side = chosen ? find_side(*chosen, a) : nullptr) {
      if (take_option(args, i, a, value)) side_paths.emplace_back(side, value);
    } else if (const ParamSpec* p = chosen ? find_param(*chosen, a) : nullptr) {
      if (p->flag) params.set(std::string(p->name), "1");
      else if (take_option(args, i, a, value)) params.set(std::string(p->name), value);
    } else if (is_option(a)) {
      unknown_option(a);
    } else if (in_path.empty()) {
      in_path = std::string(a);
    } else {
      throw UsageError("unexpected argument '" + std::string(a) + "' (one input per call)");
    }
  }
  if (in_path.empty()) throw UsageError("missing INPUT");
  if (out_path.empty()) throw UsageError("missing -o OUT");
  const Family& family = *chosen;
  if (!params.items.empty()) {
    try {
      family.check_params(params);
    } catch (const InputError& e) {
      // A file a setting names (a transfer function) reports its own file and line.
      if (e.file() != "settings") throw;
      throw UsageError(std::string(e.what()).substr(std::string("settings: ").size()));
    }
  }
  const FamilyImpl& impl = find_impl(family, impl_name.empty() ? family.default_impl : impl_name);
  if (!family.sized && width > 0) throw UsageError("--size does not apply to " + std::string(family.name));

  // The output path is checked beside the work, on a thread of its own: for an
  // image in a format other than .exr and .png that check opens OpenImageIO
  // (lockstep_oiio.so, ~250 libraries, about 0.2 s), which then overlaps
  // loading and rendering instead of coming before them. What the check finds at once (no such folder, no extension)
  // is reported before rendering (it has thrown by the time the input is
  // loaded); an unknown format may be reported after it. Either way nothing is
  // written: the check is joined before the output is.
  for (const auto& [side, path] : side_paths) {
    side->check_path(path);
    if (path == out_path) throw UsageError("--" + std::string(side->name) + " and -o name one file: " + path);
  }
  std::future<void> path_checked =
      std::async(std::launch::async, [&] { family.kind->check_path(out_path); });
  // TBB starts while the input loads (our rows run on it; a peer's own
  // threads do not, and it costs them only a spare thread for a few ms).
  std::optional<opt::ThreadPoolStart> pool;
  if (impl.peer.empty()) pool.emplace();
  const Input input = family.load_with ? family.load_with(in_path, params) : family.load(in_path);
  pool.reset();
  if (path_checked.wait_for(std::chrono::seconds(0)) == std::future_status::ready) path_checked.get();

  FrameOptions opts;
  opts.width = width > 0 ? width : input.width;
  opts.height = height > 0 ? height : input.height;
  opts.threads = threads;
  opts.params = params;
  for (const auto& [side, path] : side_paths) opts.sides.emplace_back(side->name);
  Run r = run_for_cli(who, family, impl, input, opts);
  // --repeat: the frames after the first, each drawn once the one before is
  // released (as the benchmarks' frames are: its memory is the next one's).
  const double first_seconds = r.seconds;
  for (int k = 1; k < repeat; ++k) {
    r = Run{};
    r = run_for_cli(who, family, impl, input, opts);
  }
  if (path_checked.valid()) path_checked.get();
  family.kind->write(r.out, out_path);
  write_sides(side_paths, r.stats, out_path);
  for (const std::string& note : r.stats.notes) std::fprintf(stderr, "%s: %s\n", who.c_str(), note.c_str());
  std::fprintf(stderr, "%s%s -> %s\n", run_summary(who, family, impl, r).c_str(),
               repeat_text(repeat, first_seconds).c_str(), out_path.c_str());
  return kExitOk;
}

}  // namespace lockstep::cli
