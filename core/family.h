// lockstep core: the registry's row types (types only; the rows live in pairs/).
//
// A *family* is one algorithm with one input type and one output kind, e.g.
// ray_cast (NFF scene -> image) or composite (layer stack -> image). Each
// family is a value of one iterable type per output kind (ImageFamily now;
// mesh families come with marching cubes), listed by pairs/registry.h. Its
// first implementation is always the reference. props/, bench/, the corpus
// (`lockstep verify`) and the CLI (`render --impl`, `verify --impl/--filter`)
// iterate over the registry and never name a family's functions.
//
// Typed entry points become rows through image_family<In>(): every
// implementation of a family takes the same `const In&`, checked by the
// compiler; the row stores them behind a type-erased Input.
#pragma once

#include <any>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/image.h"

namespace lockstep {

// ---------------------------------------------------------------- one run

// A family's own settings for one frame, as name=value strings (e.g. the
// raster families' shading=phong, spp=4). The family lists the names it knows
// (ImageFamily::params); the CLI turns `--NAME VALUE` into one, the corpus a
// `name=value` field. A flag without a value is "1".
struct Params {
  std::vector<std::pair<std::string, std::string>> items;

  // The value of name, or def when it is not set.
  std::string get(std::string_view name, std::string_view def = {}) const {
    for (auto it = items.rbegin(); it != items.rend(); ++it)
      if (it->first == name) return it->second;
    return std::string(def);
  }
  void set(std::string name, std::string value) { items.emplace_back(std::move(name), std::move(value)); }
  // "shading=phong spp=4"
  std::string str() const {
    std::string s;
    for (const auto& [k, v] : items) s += (s.empty() ? "" : " ") + k + "=" + v;
    return s;
  }
};

// One setting a family understands, for --help and for checking.
struct ParamSpec {
  std::string_view name;    // "shading"
  std::string_view values;  // "flat|gouraud|phong|blinn|toon", or a description such as "N >= 1"
  std::string_view def;     // the default, as text; "" for flags that are off
  std::string_view help;    // one line
  bool flag = false;        // takes no value on the command line (--split)
};

// What the harness asks of one frame. threads = 0: all cores.
struct FrameOptions {
  int width = 256;
  int height = 256;
  int threads = 0;
  std::function<void(double)> progress;  // fraction done, may be empty; called from one thread at a time
  Params params;                          // the family's own settings (checked by ImageFamily::check_params)
};

// What an implementation reports about its own run. The harness times the run
// (core/timer.h); an implementation only reports what the harness cannot see.
struct FrameStats {
  double build_seconds = 0;  // acceleration structure (Embree BVH), inside the run; 0 when none
  uint64_t items = 0;        // rays traced, or pixels composited
  std::string chosen;        // for auto: which implementation it picked and why
  uint64_t skipped = 0;      // items left out as provably invisible (z-buffer: hidden triangles)
  // What the run found that the user must hear about, one finding per line
  // (painter: the cycles and interpenetrations it could not order); the CLI
  // prints each on stderr, the corpus report beside the case.
  std::vector<std::string> notes;
};

// ---------------------------------------------------------------- tolerances

// An implementation's documented failure that we report but do not fix here
// (a third-party library's, or a textbook method's). The properties classify
// exactly this label as explained, at most max_rate of the cases of its class
// (e.g. rays through a shared mesh vertex); a run over the rate fails.
struct KnownFailure {
  std::string_view label;  // empty: none
  double max_rate = 0;     // per case of its class, measured with margin (a binomial test at 1e-6 enforces it)
  std::string_view per;    // the class the rate divides by, e.g. "shared-vertex ray"
};

// Agreement of two images of a family: a pixel fails when its largest channel
// differs by more than color_abs; at most 1 - pixel_fraction of the pixels may
// fail, and no pixel may ever differ by more than hard_abs (or be NaN), whatever
// the budget says. depth_abs < 0: depth planes are not compared.
struct ImageTolerance {
  double color_abs = 1.0 / 255;
  double pixel_fraction = 0.999;
  double hard_abs = 0.5;
  double depth_abs = -1;
};

// One implementation of a typed entry point Fn (kernel rows, and the typed rows
// an image family is built from).
template <class Fn>
struct Impl {
  std::string_view name;
  Fn fn;
  double accuracy;   // bound against the oracle on well-conditioned input, in the family's unit
  double agree = 0;  // agreement with the reference when the family's default does not fit (0: the default)
  KnownFailure known = {};
  // Unit roundoff of the arithmetic that decides (hit/miss, which primitive) when
  // the result is then refined in a wider type (0: inferred from accuracy).
  double decide_eps = 0;
};

// ---------------------------------------------------------------- image families

// A family's input, loaded from a file by the family's loader. value holds a
// std::shared_ptr<const In> of the family's input type.
struct Input {
  std::any value;
  std::string source;        // the file it came from (for messages and reports)
  int width = 0, height = 0; // its natural frame size (0: none; then the caller must give one)
  Vec3 background;           // what an empty pixel shows (for analytic judges)
};

template <class In>
const In& input_as(const Input& in) {
  return *std::any_cast<const std::shared_ptr<const In>&>(in.value);
}

struct ImageImpl {
  std::string_view name;
  std::function<Image(const Input&, const FrameOptions&, FrameStats*)> render;
  double accuracy = 0;   // bound against the oracle, in the family's unit (stated in its row)
  KnownFailure known;
  std::string_view peer; // non-empty: a production library's implementation (e.g. "OpenImageIO 2.4")
  bool threaded = true;  // false: single-threaded by design (the reference)
  // Settings the implementation cannot draw (a peer's limits, e.g. llvmpipe: flat
  // and Gouraud only): the reason, or "" when it can. Null: every setting the
  // family allows. `verify` and the benchmarks skip such cases, saying why; a
  // direct render throws InputError with the same reason.
  std::string (*unsupported)(const Params&) = nullptr;
};

// An analytic judge: for every pixel, whether it must be covered, computed from
// the input in closed form (never through an implementation). Cases name it in
// corpus/manifest.txt.
enum class Cover : uint8_t { kMiss, kHit, kSkip };
struct ImageJudge {
  std::string_view name;
  std::string_view what;
  // Throws InputError when the input is not what the judge needs.
  std::function<void(const Input&)> check;
  std::function<std::vector<Cover>(const Input&, int width, int height)> coverage;
};

// An input for benchmarks: built by the family (deterministic), timed by bench/.
struct BenchInput {
  std::string name;      // e.g. "balls-3", "2-layers"
  Input input;           // ready, or empty when make is set
  std::function<Input()> make;  // builds a large input only while its benchmarks run
  int width = 0, height = 0;
  double bytes = 0;      // > 0: bytes a run must move (reads + writes): bytes_per_second
  bool yardstick = true; // with bytes > 0: bench adds a memcpy yardstick moving the same bytes
  std::vector<std::pair<std::string, double>> counters;  // shown beside the rate
  bool heavy_for_reference = false;  // the reference runs this at a quarter of the size per side
  Params params;                     // the family's settings for this input (e.g. shading=flat)
};

struct ImageFamily {
  std::string_view name;     // "ray_cast"
  std::string_view what;     // one line for --help
  std::string_view input;    // what load() reads, e.g. "an NFF scene (.nff)"
  std::string_view unit;     // "rays" or "pixels": what FrameStats::items counts
  std::string_view verb;     // what a run does, for the CLI's line: "trace", "composite"
  std::string_view extension;     // files `lockstep render` hands to this family (".nff")
  std::string_view default_impl;  // `lockstep render` without --impl
  std::string_view algo;          // `lockstep render --algo NAME` picks this family among those of one extension
  bool sized = true;         // --size applies (false: the size is the input's)
  ImageTolerance tol;        // agreement with the reference, per frame
  std::function<Input(const std::string& path)> load;  // throws InputError
  std::vector<ImageImpl> impls;  // impls.front() is the reference
  std::vector<ImageJudge> judges;
  std::function<std::vector<BenchInput>()> bench;  // may be empty
  std::vector<ParamSpec> params;  // settings the family understands (FrameOptions::params)
  // Throws InputError(source, 0, ...) naming the bad setting; may be empty when params is.
  std::function<void(const Params&)> check_params;

  const ImageImpl& reference() const { return impls.front(); }
  const ImageImpl* find(std::string_view n) const {
    for (const auto& i : impls)
      if (i.name == n) return &i;
    return nullptr;
  }
  const ImageJudge* find_judge(std::string_view n) const {
    for (const auto& j : judges)
      if (j.name == n) return &j;
    return nullptr;
  }
};

// ---------------------------------------------------------------- typed adapter

template <class In>
using RenderOf = Image (*)(const In&, const FrameOptions&, FrameStats*);

template <class In>
struct TypedImpl {
  std::string_view name;
  RenderOf<In> render;
  double accuracy = 0;
  KnownFailure known = {};
  std::string_view peer = {};
  bool threaded = true;
  std::string (*unsupported)(const Params&) = nullptr;  // see ImageImpl::unsupported
};

template <class In>
Input make_input(In value, std::string source, int width, int height, Vec3 background = {}) {
  Input in;
  in.value = std::shared_ptr<const In>(std::make_shared<In>(std::move(value)));
  in.source = std::move(source);
  in.width = width;
  in.height = height;
  in.background = background;
  return in;
}

template <class In>
ImageImpl erase(const TypedImpl<In>& t) {
  ImageImpl i;
  i.name = t.name;
  i.render = [fn = t.render](const Input& in, const FrameOptions& o, FrameStats* s) { return fn(input_as<In>(in), o, s); };
  i.accuracy = t.accuracy;
  i.known = t.known;
  i.peer = t.peer;
  i.threaded = t.threaded;
  i.unsupported = t.unsupported;
  return i;
}

// Every implementation of one family takes the same input type In.
template <class In>
std::vector<ImageImpl> erase_all(std::span<const TypedImpl<In>> impls) {
  std::vector<ImageImpl> out;
  for (const auto& t : impls) out.push_back(erase(t));
  return out;
}

}  // namespace lockstep
