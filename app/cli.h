// lockstep CLI: what the subcommands share (argument parsing, validation,
// family and implementation lookup through the registry, the progress line).
//
// Exit codes, for every subcommand:
//   0  ok (images agree, every case passes)
//   1  differences or failures (the answer is "no")
//   2  bad usage or bad input (unknown option, malformed scene, missing file, ...)
//   3  internal error (an implementation threw, out of memory): a bug, not your input
// Bad input is always one line on stderr, "lockstep: FILE[:LINE]: message", and
// never leaves an output file behind.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "io/nff.h"
#include "registry/registry.h"

namespace lockstep::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFail = 1;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitInternal = 3;

// Wrong command line: "lockstep <sub>: <message>", exit 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using Args = std::span<const std::string_view>;

// The subcommands (app/render.cpp, app/diff.cpp, app/verify.cpp,
// app/composite.cpp). args excludes the program and subcommand names.
int render_main(Args args);
// render with the family fixed by its --algo name (forced_algo; "" for the
// extension's first) and `who` on every line it prints (app/render.cpp).
int render_as(const std::string& who, const std::string& forced_algo, Args args);
// The same for a subcommand with a help text of its own: help() on --help or -h.
int render_subcommand(const std::string& who, const std::string& forced_algo, Args args, void (*help)());
int isosurface_main(Args args);
int texture_main(Args args);  // app/texture.cpp
int radiosity_main(Args args);  // app/radiosity.cpp
int volume_main(Args args);
int trace_main(Args args);  // app/trace.cpp: one pixel's ray tree (ray_trace family)
int composite_main(Args args);

struct Run;
// The one-line summary render and composite print on stderr (app/render.cpp).
std::string run_summary(const std::string& who, const Family& f, const FamilyImpl& impl, const Run& r);
// " (N page faults, system S s; the call so far: M, T s)": the frame's and the
// process's so far (core/process_memory.h resource_use).
std::string resource_text(const Run& r);
// "; frame N of N, the first: wall S s" after --repeat N (N > 1), else "".
std::string repeat_text(int repeat, double first_seconds);
// One run for render and composite: progress on stderr, errors propagate (app/render.cpp).
Run run_for_cli(const std::string& who, const Family& family, const FamilyImpl& impl, const Input& input,
                FrameOptions opts);
int diff_main(Args args);
int verify_main(Args args);

// ---------------------------------------------------------------- parsing

// Matches option `name` at args[i], as "--name value" (consumes args[i+1]) or
// "--name=value". Returns false when args[i] is another word.
inline bool take_option(Args args, size_t& i, std::string_view name, std::string& value) {
  const std::string_view a = args[i];
  if (a == name) {
    if (i + 1 >= args.size()) throw UsageError("option " + std::string(name) + " needs a value");
    value = std::string(args[++i]);
    return true;
  }
  if (a.size() > name.size() && a.starts_with(name) && a[name.size()] == '=') {
    value = std::string(a.substr(name.size() + 1));
    return true;
  }
  return false;
}

inline bool is_option(std::string_view a) { return a.size() > 1 && a[0] == '-'; }

[[noreturn]] inline void unknown_option(std::string_view a) {
  throw UsageError("unknown option '" + std::string(a) + "'");
}

inline long parse_long(std::string_view what, std::string_view s, long lo, long hi) {
  long v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size() || s.empty())
    throw UsageError(std::string(what) + ": not an integer: '" + std::string(s) + "'");
  if (v < lo || v > hi)
    throw UsageError(std::string(what) + " must be in " + std::to_string(lo) + " .. " + std::to_string(hi) +
                     ", got " + std::string(s));
  return v;
}

// A number, or a fraction "a/b" (so thresholds can be written 1/255).
inline double parse_number(std::string_view what, std::string_view s, double lo, double hi) {
  const std::string str(s);
  auto one = [&](const std::string& t) {
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (t.empty() || end != t.c_str() + t.size() || !std::isfinite(v))
      throw UsageError(std::string(what) + ": not a finite number: '" + str + "'");
    return v;
  };
  const size_t slash = str.find('/');
  double v;
  if (slash == std::string::npos) {
    v = one(str);
  } else {
    const double den = one(str.substr(slash + 1));
    if (den == 0) throw UsageError(std::string(what) + ": division by zero in '" + str + "'");
    v = one(str.substr(0, slash)) / den;
  }
  if (!(v >= lo && v <= hi))
    throw UsageError(std::string(what) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                     "], got " + str);
  return v;
}

// "WxH", each 1 .. kMaxResolution.
inline void parse_size(std::string_view s, int& w, int& h) {
  const size_t x = s.find_first_of("xX");
  if (x == std::string_view::npos || x == 0 || x + 1 == s.size())
    throw UsageError("--size must be WxH (e.g. 256x256), got '" + std::string(s) + "'");
  w = int(parse_long("--size width", s.substr(0, x), 1, kMaxResolution));
  h = int(parse_long("--size height", s.substr(x + 1), 1, kMaxResolution));
}

// ---------------------------------------------------------------- families and implementations (the registry)

inline const Family& find_family(std::string_view name) {
  if (const Family* f = registry().find(name)) return *f;
  throw UsageError("unknown family '" + std::string(name) + "' (known: " + registry().names() + ")");
}

// The family whose files end in path's extension (".nff": ray_cast).
inline const Family& family_for_path(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  for (const Family& f : registry().families)
    if (f.reads(ext)) return f;
  std::string known;
  for (const Family& f : registry().families)
    if (!f.extension.empty()) known += (known.empty() ? "" : ", ") + std::string(f.extension) + " (" + std::string(f.name) + ")";
  throw InputError(path, 0, "no family reads '" + ext + "' files (known: " + known + ")");
}

// The setting of f that option a ("--shading") names, or null. A setting of
// several words is written with '_' (map_size) or '-' (--map-size).
inline const ParamSpec* find_param(const Family& f, std::string_view a) {
  if (!a.starts_with("--")) return nullptr;
  std::string name(a.substr(2));
  std::replace(name.begin(), name.end(), '-', '_');
  for (const ParamSpec& p : f.params)
    if (name == p.name) return &p;
  return nullptr;
}

// "reference, simd, embree, auto"
inline std::string impl_names(const Family& f, std::string_view sep = ", ") {
  std::string s;
  for (const auto& i : f.impls) {
    if (!s.empty()) s += sep;
    s += i.name;
  }
  return s;
}

inline const FamilyImpl& find_impl(const Family& f, std::string_view name) {
  if (const auto* i = f.find(name)) return *i;
  throw UsageError("unknown implementation '" + std::string(name) + "' of " + std::string(f.name) +
                   " (known: " + impl_names(f) + ")");
}

// Every family's implementations, "ray_cast: reference, simd, ...; composite: ...".
inline std::string all_impl_names() {
  std::string s;
  for (const Family& f : registry().families) {
    if (!s.empty()) s += "; ";
    s += std::string(f.name) + ": " + impl_names(f);
  }
  return s;
}

// "2.41M"
inline std::string rate(double per_second) {
  char buf[32];
  if (per_second >= 1e6) std::snprintf(buf, sizeof buf, "%.2fM", per_second / 1e6);
  else if (per_second >= 1e3) std::snprintf(buf, sizeof buf, "%.1fk", per_second / 1e3);
  else std::snprintf(buf, sizeof buf, "%.0f", per_second);
  return buf;
}

// ---------------------------------------------------------------- progress

// A percentage on stderr, rewritten in place with \r. Shown at once when
// stderr is a terminal, otherwise only once the work has taken more than 2 s
// (then in steps of 10%). Call operator() from any one thread at a time (the
// implementations serialise their progress calls).
class Progress {
 public:
  explicit Progress(std::string label)
      : label_(std::move(label)), tty_(::isatty(2) != 0), start_(std::chrono::steady_clock::now()) {}
  void operator()(double fraction) {
    const int pct = int(std::floor(100.0 * std::clamp(fraction, 0.0, 1.0)));
    if (pct == last_) return;
    if (!tty_) {
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
      if (s < 2.0 || pct / 10 == last_ / 10) return;
    }
    last_ = pct;
    std::fprintf(stderr, "\r%s %3d%%", label_.c_str(), pct);
    std::fflush(stderr);
    shown_ = true;
  }
  // Ends the line, if one was started.
  void finish() {
    if (shown_) std::fputs(tty_ ? "\r\033[K" : "\n", stderr);
    shown_ = false;
  }

 private:
  std::string label_;
  bool tty_;
  bool shown_ = false;
  int last_ = -1;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace lockstep::cli
