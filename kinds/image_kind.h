// lockstep kinds: the image output kind (float RGBA with an optional depth
// plane; core/image.h) -- files through OpenImageIO, comparison with idiff's
// metrics (kinds/image_metrics.h), heat maps, and analytic judges of coverage.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "core/image.h"
#include "kinds/image_metrics.h"
#include "core/output.h"

namespace lockstep {

// The kind every image family names (Family::kind).
const OutputKind& image_kind();

// A Tolerance as idiff's options (fail_percent in percent).
CompareOptions compare_options(const Tolerance& tol);

// ---------------------------------------------------------------- report pictures

// Every kind's pictures for the report are images in the image kind's picture
// format (OutputKind::picture_extension, PNG); the mesh kind draws its own.
// image to path_stem + the extension; returns that file name.
std::string save_picture(const Image& image, const std::string& path_stem);
// The picture file (any format OpenImageIO reads) scaled to width x height (a
// filtered resize, 8 bits) to path_stem + the extension; returns that file name.
std::string save_picture_scaled(const std::string& picture, int width, int height,
                                const std::string& path_stem);

// ---------------------------------------------------------------- coverage judges

// For every pixel, whether it must be covered, computed from the input in
// closed form (never through an implementation).
enum class Cover : uint8_t { kMiss, kHit, kSkip };
using CoverageFn = std::function<std::vector<Cover>(const Input&, int width, int height)>;

// A judge that compares an image's covered pixels (colour differs from the
// input's background) with coverage(): a missing hit (a hole, a leak) or a
// spurious one is wrong; its picture is a mask: green covered as it must, dark
// grey background as it must, red a missing hit, magenta a spurious hit, blue
// on the boundary (skipped). Where the reference is given, colours are compared
// on the pixels both cover.
Judge image_judge(std::string_view name, std::string_view what, std::function<void(const Input&)> check,
                  CoverageFn coverage);

}  // namespace lockstep
