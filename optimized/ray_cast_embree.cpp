// PLACEHOLDER (being written): replaced before the first commit.
#include <stdexcept>
#include "core/ray_cast.h"
namespace lockstep::opt::embree {
void trace(const Scene&, std::span<const Ray>, std::span<Hit>, RenderStats*) { throw std::logic_error("todo"); }
Image render(const Scene&, const RenderOptions&, RenderStats*) { throw std::logic_error("todo"); }
}
