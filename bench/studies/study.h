// What the study programs share (bench/studies/*_study.cpp):
// programs that measure for BENCHMARKS.md (a CSV on stdout, charted by
// bench/scripts/*_chart.py) and check the claims the chart's note makes, so that a
// ctest (STUDY.quick) keeps them true.
#pragma once

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <string>
#include <utility>

#include "core/family.h"
#include "core/math.h"
#include "core/scene.h"
#include "core/timer.h"

namespace lockstep::study {

// The claims a study checks: one that does not hold is said on stderr, with the
// program's name, and counted; exit_code() is then 1.
struct Claims {
  const char* program;
  int failures = 0;
  void check(bool ok, const std::string& what) {
    if (ok) return;
    std::fprintf(stderr, "%s: claim does not hold: %s\n", program, what.c_str());
    ++failures;
  }
  int exit_code() const { return failures ? 1 : 0; }
};

// Best of `runs` calls of f, seconds (the machine is shared: the best is the
// least disturbed).
template <class F>
double best_time(int runs, F&& f) {
  double best = kInfinity;
  for (int k = 0; k < runs; ++k) {
    const Stopwatch w;
    f();
    best = std::min(best, w.seconds());
  }
  return best;
}

// A scene as a family's input, at its own resolution and background.
inline Input scene_input(Scene s, const std::string& name) {
  const int w = s.view.xres, h = s.view.yres;
  const Vec3 bg = s.background;
  return make_input<Scene>(std::move(s), name, w, h, bg);
}

// Flags without values ("--quick", "--mutant"): each one given sets its bool.
// Anything else: usage on stderr and false (the caller exits 2).
inline bool parse_flags(int argc, char** argv,
                        std::initializer_list<std::pair<const char*, bool*>> flags,
                        const char* usage) {
  for (int a = 1; a < argc; ++a) {
    bool known = false;
    for (const auto& [name, value] : flags)
      if (std::strcmp(argv[a], name) == 0) *value = known = true;
    if (!known) {
      std::fprintf(stderr, "usage: %s\n", usage);
      return false;
    }
  }
  return true;
}

}  // namespace lockstep::study
