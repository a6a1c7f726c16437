// lockstep io: reading transfer functions (see io/transfer_function_io.h).
#include "io/transfer_function_io.h"

#include <cmath>
#include <cstdint>
#include <filesystem>

#include "core/error.h"
#include "io/text.h"
#include "io/tokenizer.h"

namespace lockstep {

namespace {

// One number, all of the word, finite (underflow is refused too).
bool number(std::string_view w, double& out) {
  bool range_error = false;
  return text::parse_double(w, out, &range_error) && !range_error && std::isfinite(out);
}

}  // namespace

TransferFunction parse_transfer_function(std::string_view text, const std::string& source) {
  TransferFunction tf;
  tf.source = source;
  text::Tokenizer in(text, source,
                     {.comments = text::Comments::anywhere,
                      .nul = "binary data (NUL byte) in a transfer function"});
  int prev_line = 0;
  while (in.next()) {
    const auto& w = in.words();
    if (w.size() != 5)
      in.fail("a control point is five numbers: value r g b alpha (got " +
              std::to_string(w.size()) + " words)");
    double x[5];
    static const char* const kNames[5] = {"value", "r", "g", "b", "alpha"};
    for (size_t k = 0; k < 5; ++k)
      if (!number(w[k], x[k]))
        in.fail(std::string(kNames[k]) + " is not a finite number: '" + std::string(w[k]) + "'");
    for (size_t k = 1; k < 5; ++k)
      if (x[k] < 0 || x[k] > 1)
        in.fail(std::string(kNames[k]) + " must lie in [0, 1], got " + std::string(w[k]));
    if (!tf.points.empty() && !(x[0] > tf.points.back().value))
      in.fail("values must increase: " + std::string(w[0]) + " is not above the value on line " +
              std::to_string(prev_line));
    if (tf.points.size() == size_t(kMaxControlPoints))
      in.fail("more than " + std::to_string(kMaxControlPoints) + " control points");
    tf.points.push_back({x[0], float(x[1]), float(x[2]), float(x[3]), float(x[4])});
    prev_line = in.line_no();
  }
  if (tf.points.empty())
    throw InputError(source, 0, "no control points (lines of: value r g b alpha)");
  return tf;
}

TransferFunction read_transfer_function(const std::string& spec) {
  TransferFunction p = transfer_preset(spec);
  if (!p.points.empty()) return p;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(spec, ec))
    throw InputError(spec, 0,
                     std::string("not a transfer function preset (") + transfer_presets() +
                         ") nor a readable .tf file");
  constexpr size_t kMaxBytes = size_t(1) << 20;
  const auto size = std::filesystem::file_size(spec, ec);
  if (ec || size > kMaxBytes)
    throw InputError(spec, 0, "unreadable or too large for a .tf file (over 1 MiB)");
  return parse_transfer_function(
      text::read_text_file(spec, {.unreadable = "cannot open", .read_error = "cannot open"},
                           kMaxBytes),
      spec);
}

}  // namespace lockstep
