// lockstep core: the one stopwatch.
//
// The harness times every run (app/, bench/, props/); implementations time only
// what the harness cannot see from outside, such as Embree's BVH build inside a
// render (FrameStats::build_seconds). Reference code carries no stopwatch.
#pragma once

#include <chrono>

namespace lockstep {

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  void restart() { start_ = std::chrono::steady_clock::now(); }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace lockstep
