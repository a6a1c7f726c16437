// lockstep io: the one tokenizer of the line-oriented text readers (NFF scenes,
// .stack layer stacks, .tf transfer functions, .field files, NRRD headers, the
// corpus manifest and costs, diff's pair lists).
//
// A Tokenizer walks text already in memory line by line: each line without its
// '\n' and one '\r' before it, its 1-based number, and its words (split at
// white space, views into the text: no allocation per word or line once the
// word list has grown). Comments are stripped the way the format says
// (Syntax::comments); a NUL byte is an error naming the line (Syntax::nul).
// Every error goes through fail(), InputError(name, line, what), so each names
// the file and the line the tokenizer stands on.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace lockstep::text {

enum class Comments {
  none,        // '#' is an ordinary character (NRRD headers: the reader knows its own)
  line_start,  // a line whose first word starts with '#' is a comment; a later '#' is text
  anywhere,    // a '#' anywhere starts a comment that runs to the end of the line
};

struct Syntax {
  Comments comments = Comments::anywhere;
  // With Comments::anywhere: a line whose first word is exactly this is kept
  // (the word too), up to a further '#' (NFF's "#lockstep" lines). Empty: none.
  std::string_view directive = {};
  // The message for a line holding a NUL byte (nullptr: not checked).
  const char* nul = "binary data (NUL byte) in a text file";
};

class Tokenizer {
 public:
  // text must outlive the tokenizer; name is the file named in errors.
  Tokenizer(std::string_view text, std::string name, Syntax syntax = {});

  // Advances to the next line that holds a word (blank and comment lines are
  // skipped); false at the end of the text.
  bool next();
  // Advances to the next line whatever it holds (blank ones too); false at the end.
  bool next_line();
  // Like next(), but the text must not end here: fail_at_end("file ends early: expected " + what).
  void require_next(const char* what);

  // The current line: no '\n', no '\r' before it, the comment cut off.
  std::string_view line() const { return line_; }
  const std::vector<std::string_view>& words() const { return words_; }
  // The line from word i to its end, white space trimmed ("" past the last word).
  std::string_view rest(size_t i) const;
  int line_no() const { return line_no_; }
  // Whether the current line ended in '\n' (not the end of the text).
  bool terminated() const { return terminated_; }
  // Where the next line starts in the text (its size at the end).
  size_t offset() const { return pos_; }
  const std::string& name() const { return name_; }

  // InputError(name, line_no(), what).
  [[noreturn]] void fail(const std::string& what) const;
  // An error about the end of the text, reported on the line after the last one.
  [[noreturn]] void fail_at_end(const std::string& what);
  // Exactly n words, else "missing fields: what" / "unexpected extra field 'w' after what".
  void expect_count(size_t n, const char* what) const;

 private:
  void split();

  std::string_view text_;
  std::string name_;
  Syntax syntax_;
  size_t pos_ = 0;
  int line_no_ = 0;
  bool terminated_ = false;
  std::string_view line_;
  std::vector<std::string_view> words_;
};

// The whole of a file's text, for a Tokenizer. InputError(path, 0, ...) with
// the reader's own words when it is missing (missing), a folder (folder), or
// cannot be opened or read (unreadable); more than max_bytes: "too large".
struct FileMessages {
  const char* missing = "no such file";
  const char* folder = "is a folder";
  const char* unreadable = "cannot open file";
  const char* read_error = "cannot read file";
};
// The largest list file read (a .stack, a manifest, a pair list): absurd beyond.
inline constexpr size_t kMaxListBytes = size_t(64) << 20;
std::string read_text_file(const std::string& path, const FileMessages& messages, size_t max_bytes);

}  // namespace lockstep::text
