// lockstep spd: Eric Haines' Standard Procedural Databases, generated.
//
// The SPD (public domain; spd/README.md) is a set of small C programs that
// write classic ray-tracing benchmark scenes at a size factor. lockstep's
// benchmarks and tests use their NFF output; this library writes the same
// files from the same definitions, so a clone of the repository needs no
// copies beside it (`lockstep spd`, registry/loaders.h).
//
//   generate("balls", 3, false)   the text of `balls -s 3 -r 1`
//   generate("tree", 2, true)     the text of `tree -s 2 -r 1 -t`
#pragma once

#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace lockstep::spd {

struct SceneSpec {
  std::string_view name;
  int default_size;   // the SPD program's own default
  int max_size;       // the largest size allowed here (beyond: absurd output or the SPD's limits)
  int max_size_tess;  // the same, tessellated (a sphere becomes 6*2*U*V patches)
  bool curved;        // has spheres, cones or cylinders that tess polygonalizes
  std::string_view what;
};

// Every scene, alphabetically.
std::span<const SceneSpec> scenes();
const SceneSpec* find(std::string_view name);
// "balls, gears, ..." for messages.
std::string names();

// A request outside what a scene allows (unknown name, size out of range).
class SpdError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// The NFF text of scene `name` at size factor `size` (the SPD's -s),
// tessellated when `tess` (the SPD's -t), as the SPD's -r 1 writes it.
// Throws SpdError for an unknown name or a size outside 1 .. max_size
// (max_size_tess when tess).
std::string generate(std::string_view name, int size, bool tess);

// A file name stem as ../shared/spd names its files, "balls-3" or
// "tree-2-tess", taken apart; nothing when it is not of that form or names
// no scene.
struct Request {
  std::string name;
  int size = 0;
  bool tess = false;
};
std::optional<Request> parse_stem(std::string_view stem);

}  // namespace lockstep::spd
