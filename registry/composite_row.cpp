// lockstep registry: the compositing family's row (see reference/composite.h for
// the contract, props/composite/ for the properties and their bounds).
#include "registry/composite_row.h"

#include <algorithm>
#include <memory>
#include <span>

#include "io/layers.h"
#include "kinds/image_kind.h"
#include "optimized/composite_simd.h"
#include "optimized/composite_oiio.h"
#include "reference/composite.h"
#include "reference/synthetic_stack.h"

namespace lockstep {

namespace {

// Accuracy against the exact (rational) oracle, for float stacks: ulps per
// over, of the result's largest term (a stack of N layers is held to
// 1/2 + accuracy (N - 1) ulps). Premultiplied over rounds 1 - a, the product and
// the sum: 1.5; the reference's straight formula two products, a sum and a
// division, and converts between representations: 3. props/composite/README.md
// derives every bound; 8-bit stacks are judged in levels there.
constexpr TypedImpl<LayerStack> kImpls[] = {
    {"reference", ref::composite, 3, {}, {}, false},
    {"simd", opt::simd::composite, 1.5},
    {"oiio", opt::oiio::composite, 1.5, {}, "OpenImageIO ImageBufAlgo::over"},
};

Input load_stack(const std::string& path) {
  LayerStack s = read_stack(path, std::nullopt);
  const int w = s.width(), h = s.height();
  return make_input<LayerStack>(std::move(s), path, w, h);
}

// Benchmarks at 4096^2: 2 layers (float and 8-bit, premultiplied and straight),
// 8 and 32 layers that become opaque from layer 2 on (front-to-back can stop
// early) and that never do. bytes = every layer read once + the output written
// (for the opaque-early stacks a nominal figure: early termination reads less).
// The memcpy yardstick only for the 2-layer inputs: that is where the bytes
// are what every implementation moves, and a yardstick for a 32-layer stack
// would copy 4.4 GB into another 4.4 GB beside the 8 GB stack.
std::vector<BenchInput> bench_stacks() {
  struct Spec {
    const char* name;
    int layers, opaque_from;
    Alpha alpha;
    Storage storage;
  };
  const Spec specs[] = {
      {"2-layers", 2, -1, Alpha::premultiplied, Storage::f32},
      {"2-layers-straight", 2, -1, Alpha::straight, Storage::f32},
      {"2-layers-unorm8", 2, -1, Alpha::premultiplied, Storage::unorm8},
      {"8-layers-opaque-early", 8, 2, Alpha::premultiplied, Storage::f32},
      {"8-layers", 8, -1, Alpha::premultiplied, Storage::f32},
      {"32-layers-opaque-early", 32, 2, Alpha::premultiplied, Storage::f32},
      {"32-layers", 32, -1, Alpha::premultiplied, Storage::f32},
  };
  constexpr int kSize = 4096;
  std::vector<BenchInput> out;
  for (const Spec& s : specs) {
    BenchInput b;
    b.name = s.name;
    b.width = b.height = kSize;
    b.make = [s] {
      return make_input<LayerStack>(synthetic_stack(kSize, kSize, s.layers, s.opaque_from, s.alpha, s.storage, 7),
                                    s.name, kSize, kSize);
    };
    const double px = double(kSize) * kSize;
    const double in_bytes = s.storage == Storage::unorm8 ? 4 : 16;
    b.bytes = px * (in_bytes * s.layers + 16);  // the output is float RGBA
    b.yardstick = s.layers == 2;
    b.counters = {{"layers", double(s.layers)}};
    out.push_back(std::move(b));
  }
  return out;
}

}  // namespace

Family composite_family() {
  Family f;
  f.name = "composite";
  f.what = "alpha compositing of layer stacks (over: straight/premultiplied, front-to-back/back-to-front)";
  f.input = "a layer stack (.stack)";
  f.unit = "pixels";
  f.verb = "composite";
  f.extension = ".stack";
  f.default_impl = "simd";
  f.sized = false;
  f.kind = &image_kind();
  // Agreement with the reference: within one 8-bit level on every pixel (the
  // float cases in corpus/manifest.txt set their own, tighter threshold).
  f.tol.abs = 1.0 / 255 + 1e-6;
  f.tol.fraction = 1.0;
  f.load = load_stack;
  f.impls = erase_all<LayerStack>(kImpls);
  // The simd row keeps its frame buffer across frames, as an application
  // keeps its framebuffer: allocated and touched once when the session starts
  // (the benchmarks' session_ms), then composited into (composite_into) frame
  // after frame. A fresh 4096^2 float output is 256 MiB of first-touch page
  // faults, which on the 2-core VM cost 450-650 ms on one thread with 4 KiB
  // pages (huge pages: 130 ms where the host has the memory at hand, 1-2.6 s
  // where it must fetch it first) against a warm frame's 37 ms: no first frame
  // that allocates its output can be within 2x of warm (issue #21, "One-shot
  // cost"). `render` and `verify` composite one frame into a fresh Image (run).
  for (FamilyImpl& impl : f.impls)
    if (impl.name == "simd")
      impl.session = [](const Input& in, const FrameOptions&, RunResources&) {
        const LayerStack& stack = input_as<LayerStack>(in);
        auto frame = std::make_shared<Image>(Image::uninitialized(stack.width(), stack.height()));
        std::fill(frame->rgba.begin(), frame->rgba.end(), 0.0f);  // first touch, here
        return [frame](const Input& in, const FrameOptions& o, FrameStats* stats) mutable {
          const LayerStack& stack = input_as<LayerStack>(in);
          // A frame the caller still holds is not written: a new buffer then.
          if (frame.use_count() > 1 || frame->width != stack.width() ||
              frame->height != stack.height())
            frame = std::make_shared<Image>(Image::uninitialized(stack.width(), stack.height()));
          opt::simd::composite_into(stack, o, frame->rgba.data(), stats);
          Output out;
          out.value = frame;  // shared with the session: take_output copies it
          return out;
        };
      };
  f.bench = bench_stacks;
  return f;
}

}  // namespace lockstep
