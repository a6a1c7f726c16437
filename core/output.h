// lockstep core: output kinds -- what a family's runs produce, and everything
// the harness does with it that depends on what it is.
//
// A family (core/family.h) names one output kind. The drivers -- `lockstep
// render` and `verify`, the benchmarks, the property driver -- hold a run's
// result as an Output and ask the family's kind to write it, read it back,
// compare two of them against a Tolerance, draw diagnostics for the report and
// count what a run produced. None of them names Image (or Mesh): a family with
// a new kind of output costs its kind (one value of OutputKind) and its row,
// not an edit to each driver.
//
//   Output        a run's result, type-erased (an Image, a Mesh, ...)
//   Tolerance     "a sample fails above abs; at most 1 - fraction may fail;
//                 none above hard": the one shape every kind's budget has
//                 (images: per-channel colour of a pixel; meshes: a vertex's
//                 distance to the other surface)
//   Agreement     what a comparison found: pass, the worst error, a summary
//   Judge         an analytic judge: the closed-form answer for one frame,
//                 against which any implementation (the reference too) is judged
//   OutputKind    the functions above, one value per kind (kinds/image_kind.h)
#pragma once

#include <any>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "core/math.h"

namespace lockstep {

struct Input;         // core/family.h
struct FrameOptions;  // core/family.h

// ---------------------------------------------------------------- Output

// A run's result. value holds a std::shared_ptr<T> of the kind's type; a run
// owns it alone, so family-specific code may move the value out (take_output).
struct Output {
  std::any value;
  bool empty() const { return !value.has_value(); }
};

template <class T>
Output make_output(T v) {
  Output o;
  o.value = std::make_shared<T>(std::move(v));
  return o;
}

template <class T>
const T& output_as(const Output& o) {
  return *std::any_cast<const std::shared_ptr<T>&>(o.value);
}

// The value itself: moved out when o is its only owner, copied otherwise.
template <class T>
T take_output(Output&& o) {
  const std::shared_ptr<T> p = std::any_cast<std::shared_ptr<T>>(std::move(o.value));
  o.value.reset();
  if (p.use_count() == 1) return std::move(*p);
  return *p;
}

// ---------------------------------------------------------------- comparison

// Agreement budget of two outputs of one kind (see above). Images: a pixel fails
// when its largest channel differs by more than abs; meshes: a vertex whose
// distance to the other surface is more than abs.
struct Tolerance {
  double abs = 1.0 / 255;
  double fraction = 0.999;  // share of samples that must be within abs
  double hard = 0.5;        // no sample may ever be off by more (or be NaN)
};

struct Agreement {
  bool comparable = true;   // same size (images), same bounds (meshes); false: nothing else holds
  long samples = 0;         // pixels, vertices compared
  long over = 0;            // samples over Tolerance::abs
  long over_hard = 0;       // samples over Tolerance::hard, or NaN
  double worst = 0;         // the largest error
  double score = kInfinity; // the kind's figure of merit (images: PSNR in dB)
  bool pass = true;
  std::string detail;       // a difference the samples do not show, in the kind's words ("" when none)
  double percent_over() const { return samples ? 100.0 * double(over) / double(samples) : 0.0; }
};

// ---------------------------------------------------------------- analytic judges

// One output judged against a closed-form answer.
struct JudgeVerdict {
  long wrong = 0;       // samples that contradict the closed form
  std::string detail;   // in the kind's words: "1258 must hit, 0 skipped" or "12 px differ from analytic (...)"
  Output picture;       // the verdict drawn (images: the judge mask), written by the kind's save_view
  // Against the reference, on the samples both show (images: colour where both
  // cover a pixel); samples == 0 when there was no reference to compare with.
  Agreement with_reference;
};

// A judge of one frame: out is judged; ref, when given, is compared on the
// samples both show, at tol.
using JudgeFrame = std::function<JudgeVerdict(const Output& out, const Output* ref, const Tolerance& tol)>;

struct Judge {
  std::string_view name;
  std::string_view what;
  // Throws InputError when the input is not what the judge needs.
  std::function<void(const Input&)> check;
  // The closed-form answer for one frame, computed once (never through an
  // implementation) and returned as the function that judges its outputs.
  std::function<JudgeFrame(const Input&, const FrameOptions&)> prepare;
};

// ---------------------------------------------------------------- the kind

struct OutputKind {
  std::string_view name;     // "image"
  std::string_view samples;  // what a sample is, plural: "pixels"
  std::string_view sample;   // short, for counts: "px"
  std::string_view score;    // Agreement::score's name: "PSNR dB"
  std::string_view legend;   // what the report's files of this kind show (one line)

  // Files. write: the format follows path's extension; check_path fails
  // (InputError) before any work when path cannot take this kind's output.
  void (*write)(const Output&, const std::string& path);
  void (*check_path)(const std::string& path);
  Output (*read)(const std::string& path);
  // Goldens: written by the reference only, compared within a tolerance.
  std::string_view golden_extension;  // ".exr"
  void (*write_golden)(const Output&, const std::string& path);

  // a against b (the reference first).
  Agreement (*compare)(const Output& a, const Output& b, const Tolerance& tol);
  // "12 px over 0.00392" or "" when nothing is over (for notes).
  std::string (*describe)(const Agreement&, const Tolerance& tol);
  // The tolerance in words, for --help: "0.00392 per channel on >= 99.9% of the pixels, hard limit 0.5".
  std::string (*describe_tolerance)(const Tolerance&);

  // For the report: the output itself as something people look at (images: a
  // PNG), and the difference of b from a (images: a heat map, red at tol.abs).
  // Both write path_stem + the kind's extension and return that file name.
  std::string (*save_view)(const Output&, const std::string& path_stem);
  std::string (*save_difference)(const Output& a, const Output& b, const Tolerance& tol, const std::string& path_stem);
  // Another renderer's picture of the scene (a case's beside=, a file), scaled
  // to width x height to sit beside the outputs; written and named as above.
  std::string (*save_beside)(const std::string& picture, int width, int height, const std::string& path_stem);
  // The pictures the three write: their extension and media type (the report
  // page reads a case's pictures back as data: URIs for its pixel readout).
  std::string_view picture_extension;  // ".png"
  std::string_view picture_type;       // "image/png"

  // What a run produced: its size in words ("512x512") and in samples.
  std::string (*shape)(const Output&);
  uint64_t (*count)(const Output&);
  // "" when out is what opts asked for (images: the frame size), else why not.
  std::string (*check_frame)(const Output& out, const FrameOptions& opts);
  // The address of the output's data, for benchmarks (DoNotOptimize).
  const void* (*data)(const Output&);
};

}  // namespace lockstep
