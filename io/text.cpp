// lockstep io: the readers' shared text steps (see io/text.h).
#include "io/text.h"

#include <sys/stat.h>

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <mutex>
#include <numbers>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.h"

namespace lockstep::text {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> words(std::string_view s) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    size_t j = i;
    while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j]))) ++j;
    if (j > i) out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

// Quoted for messages: at most 40 characters, non-printable bytes as \xNN.
std::string quoted(std::string_view s) {
  std::string out = "'";
  for (size_t i = 0; i < s.size() && i < 40; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c >= 32 && c < 127) {
      out += char(c);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    }
  }
  if (s.size() > 40) out += "...";
  return out + "'";
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string extension_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  return lower(path.substr(dot));
}

std::string directory_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash == 0 ? 1 : slash);
}

// What stat says about a path: an InputError unless it is a regular file.
size_t regular_file_size(const std::string& path, const std::string& report_as, int line, const char* what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw InputError(report_as, line, std::string("cannot open ") + what + ": " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw InputError(report_as, line, std::string(what) + " is not a regular file");
  return size_t(st.st_size);
}

// Up to max_bytes of a file (the whole file when it is shorter).
std::string read_prefix(const std::string& path, size_t max_bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
  std::string s(max_bytes, '\0');
  in.read(s.data(), std::streamsize(max_bytes));
  s.resize(size_t(in.gcount()));
  if (in.bad()) throw InputError(path, 0, "read error");
  return s;
}

// A strict unsigned decimal (no sign, no spaces): false on anything else or overflow.
bool parse_size(std::string_view s, size_t& out) {
  if (s.empty() || s.size() > 19) return false;
  size_t v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
    v = v * 10 + size_t(c - '0');
  }
  out = v;
  return true;
}

namespace {

// s NUL-terminated for strtod and strtol: on the stack when short (numbers are).
class CString {
 public:
  explicit CString(std::string_view s) {
    if (s.size() < sizeof small_) {
      std::memcpy(small_, s.data(), s.size());
      small_[s.size()] = '\0';
    } else {
      large_.assign(s);
      c_ = large_.c_str();
    }
  }
  CString(const CString&) = delete;
  CString& operator=(const CString&) = delete;
  const char* c_str() const { return c_; }

 private:
  char small_[64];
  std::string large_;
  const char* c_ = small_;
};

}  // namespace

// A strict signed decimal within long's range.
bool parse_long(std::string_view s, long& out) {
  if (s.empty()) return false;
  const CString t(s);
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(t.c_str(), &end, 10);
  if (end != t.c_str() + s.size() || errno == ERANGE) return false;
  out = v;
  return true;
}

bool parse_double(std::string_view s, double& out, bool* range_error) {
  if (s.empty()) return false;
  const CString t(s);
  char* end = nullptr;
  errno = 0;
  out = std::strtod(t.c_str(), &end);
  if (range_error) *range_error = errno == ERANGE;
  return end == t.c_str() + s.size();
}

}  // namespace lockstep::text
