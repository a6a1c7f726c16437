// Alpha compositing with OpenImageIO: ImageBufAlgo::over, chained.
//
// A production peer for opt::simd: what a pipeline built on OIIO (oiiotool
// --over) does. The layers are wrapped as ImageBufs without copying; straight
// layers are premultiplied first with ImageBufAlgo::premult (over wants
// premultiplied input); then over is applied once per layer, each a full pass
// over the frame (read two images, write one), on opts.threads of OIIO's own
// thread pool. No early termination: every layer is read everywhere, which is
// what the comparison with opt::simd measures.
//
// Storage::unorm8 keeps UINT8 ImageBufs throughout (OIIO computes each over in
// float and rounds to 8 bits on the way out, as an 8-bit OIIO pipeline would);
// the final 8-bit values q become q / 255.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <memory>

#include "core/error.h"
#include "optimized/composite.h"

namespace lockstep::opt::oiio {

namespace {

OIIO::ImageSpec rgba_spec(int w, int h, OIIO::TypeDesc type) {
  OIIO::ImageSpec spec(w, h, 4, type);
  spec.alpha_channel = 3;
  return spec;
}

[[noreturn]] void fail(const std::string& what, const std::string& why) {
  // Not the user's input: OIIO refused a well-formed stack.
  throw std::runtime_error("OpenImageIO " + what + " failed: " + why);
}

}  // namespace

Image composite(const LayerStack& stack, const FrameOptions& opts, FrameStats* stats) {
  check_stack(stack);
  const int w = stack.width(), h = stack.height();
  const bool eight = stack.storage == Storage::unorm8;
  const OIIO::TypeDesc type = eight ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
  const OIIO::ImageSpec spec = rgba_spec(w, h, type);
  const int nthreads = opts.threads;  // 0: OIIO's default, all cores
  const size_t L = stack.layers.size();

  // Layer k as a premultiplied ImageBuf: wrapped in place, or premultiplied into a new one.
  std::vector<std::unique_ptr<OIIO::ImageBuf>> layers;
  for (const Layer& l : stack.layers) {
    void* data = eight ? static_cast<void*>(const_cast<uint8_t*>(l.rgba8.data()))
                       : static_cast<void*>(const_cast<float*>(l.image.rgba.data()));
    auto wrapped = std::make_unique<OIIO::ImageBuf>(spec, data);  // read only: never written
    if (l.alpha == Alpha::straight) {
      auto p = std::make_unique<OIIO::ImageBuf>();
      if (!OIIO::ImageBufAlgo::premult(*p, *wrapped, {}, nthreads)) fail("premult", p->geterror());
      layers.push_back(std::move(p));
    } else {
      layers.push_back(std::move(wrapped));
    }
  }

  Image out = Image::uninitialized(w, h);  // ImageBufAlgo::over writes every pixel
  std::vector<uint8_t> out8;
  if (eight) out8.resize(size_t(w) * size_t(h) * 4);
  OIIO::ImageBuf result(
      spec, eight ? static_cast<void*>(out8.data()) : static_cast<void*>(out.rgba.data()));

  if (L == 1) {
    if (!OIIO::ImageBufAlgo::copy(result, *layers[0], OIIO::TypeUnknown, {}, nthreads))
      fail("copy", result.geterror());
  } else {
    // Chain: front to back, acc = acc over next; back to front, acc = next over acc.
    // Intermediate results ping-pong between two buffers; the last over writes
    // straight into the output.
    const bool ftb = stack.order == Order::front_to_back;
    auto at = [&](size_t s) -> const OIIO::ImageBuf& { return *layers[ftb ? s : L - 1 - s]; };
    OIIO::ImageBuf tmp[2] = {OIIO::ImageBuf(spec), OIIO::ImageBuf(spec)};
    const OIIO::ImageBuf* acc = &at(0);
    for (size_t s = 1; s < L; ++s) {
      OIIO::ImageBuf& dst = s + 1 == L ? result : tmp[s % 2];
      const bool ok = ftb ? OIIO::ImageBufAlgo::over(dst, *acc, at(s), {}, nthreads)
                          : OIIO::ImageBufAlgo::over(dst, at(s), *acc, {}, nthreads);
      if (!ok) fail("over", dst.geterror());
      acc = &dst;
    }
  }
  if (eight)
    for (size_t i = 0; i < out8.size(); ++i) out.rgba[i] = float(out8[i]) / 255.0f;
  if (opts.progress) opts.progress(1.0);
  if (stats) stats->items = uint64_t(w) * uint64_t(h);
  return out;
}

}  // namespace lockstep::opt::oiio
