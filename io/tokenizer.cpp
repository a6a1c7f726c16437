// lockstep io: the text readers' tokenizer (see io/tokenizer.h).
#include "io/tokenizer.h"

#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <utility>

#include "core/error.h"

namespace lockstep::text {

namespace {

bool space(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

}  // namespace

Tokenizer::Tokenizer(std::string_view text, std::string name, Syntax syntax)
    : text_(text), name_(std::move(name)), syntax_(syntax) {}

bool Tokenizer::next_line() {
  if (pos_ >= text_.size()) {
    line_ = {};
    words_.clear();
    return false;
  }
  size_t end = text_.find('\n', pos_);
  terminated_ = end != std::string_view::npos;
  if (!terminated_) end = text_.size();
  std::string_view line = text_.substr(pos_, end - pos_);
  pos_ = terminated_ ? end + 1 : end;
  ++line_no_;
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  if (syntax_.nul && line.find('\0') != std::string_view::npos) fail(syntax_.nul);
  size_t first = 0;
  while (first < line.size() && space(line[first])) ++first;
  if (syntax_.comments == Comments::line_start) {
    if (first < line.size() && line[first] == '#') line = line.substr(0, first);
  } else if (syntax_.comments == Comments::anywhere) {
    // A directive line keeps its first word (which starts with '#'), up to a further '#'.
    const std::string_view d = syntax_.directive;
    const bool directive = !d.empty() && line.substr(first).starts_with(d) &&
                           (first + d.size() == line.size() || space(line[first + d.size()]));
    const size_t hash = line.find('#', directive ? first + 1 : 0);
    if (hash != std::string_view::npos) line = line.substr(0, hash);
  }
  line_ = line;
  split();
  return true;
}

bool Tokenizer::next() {
  while (next_line())
    if (!words_.empty()) return true;
  return false;
}

void Tokenizer::require_next(const char* what) {
  if (!next()) fail_at_end(std::string("file ends early: expected ") + what);
}

std::string_view Tokenizer::rest(size_t i) const {
  if (i >= words_.size()) return {};
  const size_t from = size_t(words_[i].data() - line_.data());
  return line_.substr(from, size_t(words_.back().data() + words_.back().size() - words_[i].data()));
}

void Tokenizer::fail(const std::string& what) const { throw InputError(name_, line_no_, what); }

void Tokenizer::fail_at_end(const std::string& what) {
  ++line_no_;
  fail(what);
}

void Tokenizer::expect_count(size_t n, const char* what) const {
  if (words_.size() < n) fail(std::string("missing fields: ") + what);
  if (words_.size() > n)
    fail("unexpected extra field '" + std::string(words_[n]) + "' after " + what);
}

void Tokenizer::split() {
  words_.clear();
  const std::string_view s = line_;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && space(s[i])) ++i;
    size_t j = i;
    while (j < s.size() && !space(s[j])) ++j;
    if (j > i) words_.push_back(s.substr(i, j - i));
    i = j;
  }
}

std::string read_text_file(const std::string& path, const FileMessages& messages,
                           size_t max_bytes) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw InputError(path, 0, messages.folder);
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, 0, fs::exists(path, ec) ? messages.unreadable : messages.missing);
  auto too_large = [&] {
    const bool mib = max_bytes >= (size_t(1) << 20) && max_bytes % (size_t(1) << 20) == 0;
    throw InputError(path, 0,
                     "too large (over " + std::to_string(mib ? max_bytes >> 20 : max_bytes) +
                         (mib ? " MiB)" : " bytes)"));
  };
  std::string text;
  const uintmax_t size = fs::file_size(path, ec);
  if (!ec) {
    if (size > max_bytes) too_large();
    text.resize(size_t(size));
    f.read(text.data(), std::streamsize(size));
    text.resize(size_t(f.gcount()));
  }
  // What is left: all of a pipe or device, or what a growing file gained.
  char buf[1 << 16];
  while (f.read(buf, sizeof buf) || f.gcount() > 0) {
    text.append(buf, size_t(f.gcount()));
    if (text.size() > max_bytes) too_large();
  }
  if (f.bad()) throw InputError(path, 0, messages.read_error);
  return text;
}

}  // namespace lockstep::text
