// lockstep core: keep libraries' own chatter off stderr while reading a file.
//
// libpng and OpenImageIO's PNG reader print their own lines ("libpng error:
// ...") on stderr before OIIO returns the error, which lockstep then reports as
// its one line naming the file. While a QuietStderr is alive, file descriptor 2
// points at /dev/null. Only for the CLI's single-threaded reading of inputs.
#pragma once

#include <fcntl.h>
#include <unistd.h>

namespace lockstep {

class QuietStderr {
 public:
  QuietStderr() {
    saved_ = ::dup(2);
    const int null = ::open("/dev/null", O_WRONLY);
    if (saved_ >= 0 && null >= 0) ::dup2(null, 2);
    if (null >= 0) ::close(null);
  }
  ~QuietStderr() {
    if (saved_ >= 0) {
      ::dup2(saved_, 2);
      ::close(saved_);
    }
  }
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

 private:
  int saved_ = -1;
};

}  // namespace lockstep
