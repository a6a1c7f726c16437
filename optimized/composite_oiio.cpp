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
//
// The OpenImageIO calls are in io/oiio_module.cpp (the module lockstep_oiio.so,
// opened on first use: io/oiio.h); here the stack is checked and the frame's
// progress and statistics are reported.
#include "core/error.h"
#include "io/oiio.h"
#include "optimized/composite_oiio.h"
#include "optimized/composite_simd.h"

namespace lockstep::opt::oiio {

Image composite(const LayerStack& stack, const FrameOptions& opts, FrameStats* stats) {
  check_stack(stack);
  const int w = stack.width(), h = stack.height();
  Image out;
  lockstep::oiio::Error err;
  // opts.threads 0: OIIO's default, all cores
  if (!lockstep::oiio::api().over(stack, opts.threads, &out, &err)) lockstep::oiio::raise(err);
  if (opts.progress) opts.progress(1.0);
  if (stats) stats->items = uint64_t(w) * uint64_t(h);
  return out;
}

}  // namespace lockstep::opt::oiio
