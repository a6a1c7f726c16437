// lockstep spd: writes one of Eric Haines' SPD scenes, or the Cornell box, as NFF (spd/spd.h).
#include "spd/spd.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "app/cli.h"

namespace lockstep::cli {

namespace {

void print_help() {
  std::printf(
      "usage: lockstep spd NAME [--size N] [--tess] -o FILE.nff\n"
      "\n"
      "Writes one of Eric Haines' Standard Procedural Databases (public domain), generated\n"
      "from the SPD programs' definitions, as the SPD's own `NAME -s N -r 1 [-t]` writes it:\n"
      "the same entities in the same order, numbers printed with %%g (spd/README.md);\n"
      "or the Cornell box, Cornell's measured data with its light an emitter, for radiosity.\n"
      "\n"
      "  NAME            the scene, one of:\n");
  for (const spd::SceneSpec& s : spd::scenes())
    std::printf("    %-10s %s\n    %-10s size 1 .. %d (--tess: 1 .. %d), the SPD's default %d\n",
                std::string(s.name).c_str(), std::string(s.what).c_str(), "", s.max_size,
                s.max_size_tess, s.default_size);
  std::printf(
      "  --size N        the size factor, the SPD's -s (default: the SPD program's default)\n"
      "  --tess          polygonalize spheres, cylinders and cones into `pp` triangle patches\n"
      "                  with vertex normals, the SPD's -t (only the reference ray casters draw cones)\n"
      "  -o, --output F  the file to write (required); written whole, then renamed into place\n"
      "\n"
      "Example: lockstep spd balls --size 3 -o balls-3.nff\n"
      "Exit codes: 0 ok, 2 bad usage (unknown scene, size out of range; nothing written),\n"
      "3 internal error.\n");
}

// Writes text to path through path.tmp, so that a failure leaves no half file.
void write_atomically(const std::string& path, const std::string& text) {
  namespace fs = std::filesystem;
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary);
    if (!f) throw InputError(path, 0, "cannot create '" + tmp + "'");
    f.write(text.data(), std::streamsize(text.size()));
    f.close();
    if (!f) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw InputError(path, 0, "cannot write '" + tmp + "'");
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw InputError(path, 0, "cannot rename '" + tmp + "' into place");
  }
}

}  // namespace

int spd_main(Args args) {
  std::string name, size_text, out;
  bool tess = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string_view a = args[i];
    if (a == "--help" || a == "-h") {
      print_help();
      return kExitOk;
    }
    if (take_option(args, i, "--size", size_text) || take_option(args, i, "-o", out) ||
        take_option(args, i, "--output", out))
      continue;
    if (a == "--tess") {
      tess = true;
    } else if (is_option(a)) {
      unknown_option(a);
    } else if (name.empty()) {
      name = std::string(a);
    } else {
      throw UsageError("one scene at a time: '" + name + "' and '" + std::string(a) + "'");
    }
  }
  if (name.empty()) throw UsageError("missing scene name (" + spd::names() + ")");
  const spd::SceneSpec* spec = spd::find(name);
  if (spec == nullptr)
    throw UsageError("unknown SPD scene '" + name + "' (known: " + spd::names() + ")");
  if (out.empty()) throw UsageError("missing -o FILE");
  const int max = tess ? spec->max_size_tess : spec->max_size;
  const int size =
      size_text.empty()
          ? std::min(spec->default_size, max)
          : int(parse_long(tess ? "--size (with --tess)" : "--size", size_text, 1, max));
  write_atomically(out, spd::generate(name, size, tess));
  return kExitOk;
}

}  // namespace lockstep::cli
