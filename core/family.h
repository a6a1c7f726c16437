// lockstep core: the registry's row types (types only; the rows live in registry/).
//
// A *family* is one algorithm with one input type and one output kind, e.g.
// ray_cast (NFF scene -> image), composite (layer stack -> image), later
// marching cubes (volume -> mesh). Every family is a value of one type,
// Family, listed by registry/registry.h; its first implementation is always the
// reference. What depends on the output (files, comparison, diagnostics,
// counts) lives in the family's output kind (core/output.h), so props/,
// bench/, the corpus (`lockstep verify`) and the CLI (`render --impl`, `verify
// --impl/--filter`) iterate over the registry, call the kind, and never name a
// family's functions or its output type.
//
// Typed entry points become rows through erase<In, Out>(): every
// implementation of a family takes the same `const In&` and returns the same
// Out, checked by the compiler; the row stores them behind a type-erased Input
// and Output. Stages of a family (one primitive against many rays, marching
// cubes' cell kernel) are typed KernelRow<Fn>s; the family hands them to the
// benchmarks as KernelBench hooks.
#pragma once

#include <any>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/image.h"
#include "core/output.h"
#include "core/run_resources.h"

namespace lockstep {

// ---------------------------------------------------------------- one run

// A family's own settings for one frame, as name=value strings (e.g. the
// raster families' shading=phong, spp=4). The family lists the names it knows
// (Family::params); the CLI turns `--NAME VALUE` into one, the corpus a
// `name=value` field. A flag without a value is "1".
struct Params {
  std::vector<std::pair<std::string, std::string>> items;

  // The value of name, or def when it is not set.
  std::string get(std::string_view name, std::string_view def = {}) const {
    for (auto it = items.rbegin(); it != items.rend(); ++it)
      if (it->first == name) return it->second;
    return std::string(def);
  }
  bool has(std::string_view name) const {
    for (const auto& item : items)
      if (item.first == name) return true;
    return false;
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
  Params params;                          // the family's own settings (checked by Family::check_params)
  // Side outputs asked for, by name (Family::sides: the radiosity family's
  // "patches"); a row builds only these, into FrameStats::sides.
  std::vector<std::string> sides;
  bool wants(std::string_view side) const {
    for (const std::string& s : sides)
      if (s == side) return true;
    return false;
  }
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
  // Items by kind, where the family counts them apart (ray tracing: primary,
  // shadow, reflect, refract rays; they add up to items); the benchmarks show
  // each as a rate (<kind>_per_s).
  std::vector<std::pair<std::string, uint64_t>> counts;
  // Primitives the run could not draw and left out, by reason ("coordinates
  // beyond float range: |x| > 2^40 in the camera frame" -> 3): never silently
  // (issue #22). The CLI's stats line and the verify report carry them; an
  // image may differ from the oracle only where a run says it dropped something.
  std::map<std::string, uint64_t> dropped;
  // The side outputs FrameOptions::sides asked for, by name; the family's
  // SideOutput of that name writes each.
  std::vector<std::pair<std::string, Output>> sides;
  void drop(const std::string& reason, uint64_t n = 1) {
    if (n != 0) dropped[reason] += n;
  }
  uint64_t dropped_count() const {
    uint64_t n = 0;
    for (const auto& [reason, k] : dropped) n += k;
    return n;
  }
  // "2 dropped (coordinates beyond float range ...); 1 dropped (...)", or "".
  std::string dropped_text() const {
    std::string s;
    for (const auto& [reason, k] : dropped) s += (s.empty() ? "" : "; ") + std::to_string(k) + " dropped (" + reason + ")";
    return s;
  }
};

// ---------------------------------------------------------------- known failures

// An implementation's documented failure that we report but do not fix here
// (a third-party library's, or a textbook method's). The properties classify
// exactly this label as explained, at most max_rate of the cases of its class
// (e.g. rays through a shared mesh vertex); a run over the rate fails.
struct KnownFailure {
  std::string_view label;  // empty: none
  double max_rate = 0;     // per case of its class, measured with margin (a binomial test at 1e-6 enforces it)
  std::string_view per;    // the class the rate divides by, e.g. "shared-vertex ray"
};

// ---------------------------------------------------------------- kernel rows

// One implementation of a typed entry point Fn: a stage of a family (one
// primitive against many rays, a cell kernel), or the typed rows a family is
// built from.
template <class Fn>
struct Impl {
  std::string_view name;
  Fn fn;
  double accuracy;   // bound against the oracle on well-conditioned input, in the family's unit
  double agree = 0;  // agreement with the reference when the row's default does not fit (0: the default)
  KnownFailure known = {};
  // Unit roundoff of the arithmetic that decides (hit/miss, which primitive) when
  // the result is then refined in a wider type (0: inferred from accuracy).
  double decide_eps = 0;
};

// Agreement tolerances of a kernel row against its reference.
struct KernelTolerance {
  double t_rel = 0;           // relative error of the row's result (ray casting: t)
  double color_abs = 0;       // per-channel absolute colour error of a pixel (rows that draw)
  double pixel_fraction = 1;  // share of pixels that must be within color_abs
};

// A typed row: every implementation of one stage, the reference first. The
// family's properties (props/<family>/) read these rows; its benchmarks reach
// them through Family::kernels.
template <class Fn>
struct KernelRow {
  std::string_view name;       // "ray_sphere"
  std::string_view generator;  // props/gen name of the input generator
  KernelTolerance tol;
  std::span<const Impl<Fn>> impls;
  const Impl<Fn>* find(std::string_view n) const {
    for (const auto& i : impls)
      if (i.name == n) return &i;
    return nullptr;
  }
};

// A stage benchmark (bench/ registers one benchmark per implementation, named
// "<name>/<impl>"): prepare() builds the input once and returns the timed call,
// which returns how many items it processed.
struct KernelBench {
  std::string name;  // "kernel/ray_sphere", "throughput/spheres"
  int threads = 1;   // the TBB threads the timed call may use
  bool microseconds = false;  // report in us (default ns)
  struct Run {
    std::function<int64_t()> once;  // one timed call: items processed
    // Counters shown beside the rate, read after the timed loop (may be empty).
    std::function<std::vector<std::pair<std::string, double>>()> counters;
  };
  struct Entry {
    std::string_view impl;
    std::function<Run()> prepare;
  };
  std::vector<Entry> impls;
};

// ---------------------------------------------------------------- families

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

struct FamilyImpl {
  using RunFn = std::function<Output(const Input&, const FrameOptions&, FrameStats*)>;
  std::string_view name;
  std::function<Output(const Input&, const FrameOptions&, FrameStats*)> run;
  double accuracy = 0;   // bound against the oracle, in the family's unit (stated in its row)
  KnownFailure known;
  std::string_view peer; // non-empty: a production library's implementation (e.g. "OpenImageIO 2.4")
  bool threaded = true;  // false: single-threaded by design (the reference)
  // Settings the implementation cannot draw (a peer's limits, e.g. llvmpipe: flat
  // and Gouraud only): the reason, or "" when it can. Null: every setting the
  // family allows. `verify` and the benchmarks skip such cases, saying why; a
  // direct render throws InputError with the same reason.
  std::string (*unsupported)(const Params&) = nullptr;
  // The row's own agreement with the reference, when the family's tolerance
  // cannot fit it (a peer of another method, e.g. VolPack's shear-warp against
  // ray casting): measured, stated in the row, and used instead of Family::tol
  // by `lockstep verify` (unless the manifest's line sets fail/failpercent);
  // properties that compare a row with the reference should hold it to
  // tolerance() too (none does yet). Empty: Family::tol.
  std::optional<Tolerance> agree;

  // A run that keeps its state across frames, as the library's users keep it:
  // session(input, opts) starts one for frames of that input at opts' size and
  // returns a run whose closure owns a fresh state, reused frame after frame.
  // What it keeps is made when it starts (composite's simd row: its frame
  // buffer, allocated and touched once, as an application allocates its
  // framebuffer once) or on its first frame (llvmpipe: its GL context and
  // compiled shaders). A frame the caller still holds is never written again:
  // such a run hands back its own buffer only while the caller holds no other
  // frame of it. The benchmarks time a session's start (session_ms), its first
  // frame (first_ms) and its later frames apart. Empty: run keeps nothing, use it.
  // The third argument is the caller's run (core/run_resources.h): what the
  // session may share with the other rows of the same run (the embree rows:
  // one Embree device per process) it takes from there, never from a global.
  std::function<std::function<Output(const Input&, const FrameOptions&, FrameStats*)>(
      const Input&, const FrameOptions&, RunResources&)>
      session;
  // True when a session's state serves any input at any size (the embree rows:
  // an Embree device): `lockstep verify` then starts one session per row for
  // the whole run rather than making that state again for every frame.
  bool session_any_input = false;
  // True when each frame runs another program (the povray row: a process a
  // frame, about 0.7 s, most of it POV-Ray's own 50 ms polling between its
  // threads). Property sweeps that draw every row in every case may check such
  // a row on a stated sample of their cases (props/dropped/range.cpp: one case
  // in four, every case in deep mode); they say so in their tally.
  bool frame_is_process = false;

  // The tolerance this row is held to against the reference.
  const Tolerance& tolerance(const Tolerance& family_tol) const { return agree ? *agree : family_tol; }

  // The run's output as the family's own type (family-specific code: props/).
  template <class Out>
  Out run_as(const Input& in, const FrameOptions& o, FrameStats* s) const {
    return take_output<Out>(run(in, o, s));
  }
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
  bool reference = true;             // false: the reference is not timed on it (it would take minutes)
};

// A production library's row this family may have, built or not: what
// `lockstep --version` says of it. The row is in Family::impls only when built
// (its library was found at configure time); this entry is there either way.
struct PeerRow {
  std::string row;      // "llvmpipe"
  bool built = false;
  std::string version;  // built: "OSMesa: 23.2.1"
  std::string runs_as;  // built: "module lockstep_peer_llvmpipe.so"
  std::string missing;  // not built: why, and how to get it
};

// A peer row that lives in a module beside the binary (optimized/peer_module.h):
// built where cmake found its library; `install` says how to get it.
inline PeerRow module_peer(std::string row, bool built, std::string version, const std::string& module,
                           const std::string& install) {
  PeerRow p;
  p.row = std::move(row);
  p.built = built;
  if (built) {
    p.version = std::move(version);
    p.runs_as = "module " + module;
  } else {
    p.missing = "no " + module + " found beside the binary: built only where cmake found its library; " + install;
  }
  return p;
}

// A second thing a run can write beside its output, on request (the CLI's
// --NAME FILE): the radiosity family's patches as PLY. Its value is
// family-specific data, not an output kind's: nothing compares it.
struct SideOutput {
  std::string_view name;  // "patches": the option --patches and the FrameOptions::sides name
  std::string_view help;  // one line for --help
  void (*check_path)(const std::string& path);  // throws InputError before any work
  void (*write)(const Output& value, const std::string& path);  // atomically; throws InputError
};

struct Family {
  std::string_view name;     // "ray_cast"
  std::string_view what;     // one line for --help
  std::string_view input;    // what load() reads, e.g. "an NFF scene (.nff)"
  std::string_view unit;     // "rays" or "pixels": what FrameStats::items counts
  std::string_view verb;     // what a run does, for the CLI's line: "trace", "composite"
  std::string_view extension;     // files `lockstep render` hands to this family (".nff"; several: ".nrrd .nhdr")
  std::string_view default_impl;  // `lockstep render` without --impl
  std::string_view algo;          // `lockstep render --algo NAME` picks this family among those of one extension
  bool sized = true;         // --size applies (false: the size is the input's)
  const OutputKind* kind = nullptr;  // what a run produces (core/output.h); never null in a row
  Tolerance tol;             // agreement with the reference, per frame
  std::function<Input(const std::string& path)> load;  // throws InputError
  // May be empty: load() then the settings among params that replace part of
  // the input (the texture family's texture and wrap), for the CLI; frames
  // never see those settings. Throws InputError.
  std::function<Input(const std::string& path, const Params& params)> load_with;
  std::vector<FamilyImpl> impls;  // impls.front() is the reference
  std::vector<Judge> judges;
  std::function<std::vector<BenchInput>()> bench;  // frames to time; may be empty
  std::function<std::vector<KernelBench>()> kernels;  // stages to time; may be empty
  // The parts of the family's property provider (props/<family>/) that apply
  // to it, by name; the provider rejects a name it does not know.
  std::vector<std::string_view> properties;
  std::vector<ParamSpec> params;  // settings the family understands (FrameOptions::params)
  // Throws InputError(source, 0, ...) naming the bad setting; may be empty when params is.
  std::function<void(const Params&)> check_params;
  std::vector<PeerRow> peer_rows;  // the peers above, built or not (--version)
  std::vector<SideOutput> sides;   // may be empty

  const FamilyImpl& reference() const { return impls.front(); }
  const FamilyImpl* find(std::string_view n) const {
    for (const auto& i : impls)
      if (i.name == n) return &i;
    return nullptr;
  }
  const Judge* find_judge(std::string_view n) const {
    for (const auto& j : judges)
      if (j.name == n) return &j;
    return nullptr;
  }
  // Whether `lockstep render` hands files ending in ext (".nhdr") to this family.
  bool reads(std::string_view ext) const {
    for (size_t s = 0; s < extension.size();) {
      size_t e = extension.find(' ', s);
      if (e == std::string_view::npos) e = extension.size();
      if (e > s && extension.substr(s, e - s) == ext) return true;
      s = e + 1;
    }
    return false;
  }
  bool has_property(std::string_view part) const {
    for (const auto& p : properties)
      if (p == part) return true;
    return false;
  }
};

// ---------------------------------------------------------------- typed adapter

template <class In, class Out = Image>
using RenderOf = Out (*)(const In&, const FrameOptions&, FrameStats*);

template <class In, class Out = Image>
struct TypedImpl {
  std::string_view name;
  RenderOf<In, Out> render;
  double accuracy = 0;
  KnownFailure known = {};
  std::string_view peer = {};
  bool threaded = true;
  std::string (*unsupported)(const Params&) = nullptr;  // see FamilyImpl::unsupported
  std::optional<Tolerance> agree = {};                   // see FamilyImpl::agree
  bool frame_is_process = false;                         // see FamilyImpl::frame_is_process
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

template <class In, class Out>
FamilyImpl erase(const TypedImpl<In, Out>& t) {
  FamilyImpl i;
  i.name = t.name;
  i.run = [fn = t.render](const Input& in, const FrameOptions& o, FrameStats* s) {
    return make_output<Out>(fn(input_as<In>(in), o, s));
  };
  i.accuracy = t.accuracy;
  i.known = t.known;
  i.peer = t.peer;
  i.threaded = t.threaded;
  i.unsupported = t.unsupported;
  i.agree = t.agree;
  i.frame_is_process = t.frame_is_process;
  return i;
}

// Every implementation of one family takes the same input type In.
template <class In, class Out = Image>
std::vector<FamilyImpl> erase_all(std::span<const std::type_identity_t<TypedImpl<In, Out>>> impls) {
  std::vector<FamilyImpl> out;
  for (const auto& t : impls) out.push_back(erase(t));
  return out;
}

}  // namespace lockstep
