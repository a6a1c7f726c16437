// PLACEHOLDER (being written): replaced before the first commit.
#include <stdexcept>
#include "core/ray_cast.h"
namespace lockstep::opt::autosel {
bool prefers_embree(const Scene&) { return false; }
void trace(const Scene& s, std::span<const Ray> r, std::span<Hit> h, RenderStats* st) { simd::trace(s, r, h, st); }
Image render(const Scene& s, const RenderOptions& o, RenderStats* st) { return simd::render(s, o, st); }
}
