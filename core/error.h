// lockstep core: the one error type for bad input.
//
// Everything a user can get wrong (a malformed scene, a missing file, an absurd
// size) is reported as an InputError naming the file and, where there is one,
// the line. The CLI turns it into one line on stderr and exit code 2.
#pragma once

#include <stdexcept>
#include <string>

namespace lockstep {

class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, int line, const std::string& what)
      : std::runtime_error(format(file, line, what)), file_(file), line_(line), message_(what) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }  // 0 when the error is about the whole file
  // The words without file and line (what the constructor was given): an error
  // from a module (io/oiio.h) is thrown again on this side as it was made there.
  const std::string& message() const { return message_; }

 private:
  static std::string format(const std::string& file, int line, const std::string& what) {
    // Appended piece by piece: `":" + std::to_string(line)` trips GCC 12's -Wrestrict (a false positive).
    std::string s = file;
    if (line > 0) {
      s += ':';
      s += std::to_string(line);
    }
    s += ": ";
    // One line, always: libraries' messages (OpenImageIO's) may hold several.
    std::string w = what;
    while (!w.empty() && (w.back() == '\n' || w.back() == '\r')) w.pop_back();
    for (size_t i = 0; (i = w.find('\n', i)) != std::string::npos;) w.replace(i, 1, "; ");
    s += w;
    return s;
  }
  std::string file_;
  int line_;
  std::string message_;
};

}  // namespace lockstep
