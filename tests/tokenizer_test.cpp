// The text readers' tokenizer (io/tokenizer.h) and number parsing (io/text.h).
#include "io/tokenizer.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/text.h"

namespace {

using lockstep::InputError;
using namespace lockstep::text;

// Every line with words: "line_no:word|word".
std::vector<std::string> lines(std::string_view text, Syntax syntax = {}) {
  Tokenizer in(text, "t.txt", syntax);
  std::vector<std::string> out;
  while (in.next()) {
    std::string s = std::to_string(in.line_no()) + ":";
    for (size_t i = 0; i < in.words().size(); ++i) s += (i ? "|" : "") + std::string(in.words()[i]);
    out.push_back(s);
  }
  return out;
}

std::string error_of(std::string_view text, Syntax syntax = {}) {
  try {
    lines(text, syntax);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Tokenizer, LinesWordsAndNumbers) {
  EXPECT_EQ(lines("a b\n\n  c\td \r\n# x\ne"), (std::vector<std::string>{"1:a|b", "3:c|d", "5:e"}));
  EXPECT_TRUE(lines("").empty());
  EXPECT_TRUE(lines("\n\n").empty());
}

TEST(Tokenizer, CommentStyles) {
  const std::string text = "a # b\n  # c\nd#e\n";
  EXPECT_EQ(lines(text, {.comments = Comments::anywhere}),
            (std::vector<std::string>{"1:a", "3:d"}));
  EXPECT_EQ(lines(text, {.comments = Comments::line_start}),
            (std::vector<std::string>{"1:a|#|b", "3:d#e"}));
  EXPECT_EQ(lines(text, {.comments = Comments::none}),
            (std::vector<std::string>{"1:a|#|b", "2:#|c", "3:d#e"}));
}

TEST(Tokenizer, DirectiveLinesAreKept) {
  const Syntax nff{.comments = Comments::anywhere, .directive = "#lockstep"};
  EXPECT_EQ(lines("#lockstep atten 1 0 0 # x\n# lockstep spot\n#lockstepx y\n  #lockstep\n", nff),
            (std::vector<std::string>{"1:#lockstep|atten|1|0|0", "4:#lockstep"}));
}

TEST(Tokenizer, RestAndLine) {
  Tokenizer in("alpha  straight x \r\n", "t.txt", {.comments = Comments::line_start});
  ASSERT_TRUE(in.next());
  EXPECT_EQ(in.line(), "alpha  straight x ");
  EXPECT_EQ(in.rest(1), "straight x");
  EXPECT_EQ(in.rest(3), "");
}

TEST(Tokenizer, ErrorsNameFileAndLine) {
  EXPECT_EQ(error_of(std::string("a\nb\0c\n", 6)),
            "t.txt:2: binary data (NUL byte) in a text file");
  EXPECT_EQ(error_of(std::string("a\nb\0c\n", 6), {.nul = nullptr}), "(no error)");
  Tokenizer in("v\nfrom 1 2\n", "s.nff");
  ASSERT_TRUE(in.next());
  try {
    in.next();
    in.expect_count(4, "from x y z");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "s.nff:2: missing fields: from x y z");
    EXPECT_EQ(e.line(), 2);
  }
  EXPECT_FALSE(in.next());
  try {
    in.require_next("a vertex");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "s.nff:3: file ends early: expected a vertex");
  }
}

TEST(Tokenizer, EveryLineAndWhereItEnds) {
  const std::string text = "NRRD0004\r\ntype: float\n\nDATA";
  Tokenizer in(text, "h.nhdr", {.comments = Comments::none, .nul = nullptr});
  ASSERT_TRUE(in.next_line());
  EXPECT_EQ(in.line(), "NRRD0004");
  ASSERT_TRUE(in.next_line());
  ASSERT_TRUE(in.next_line());
  EXPECT_TRUE(in.line().empty());
  EXPECT_EQ(in.line_no(), 3);
  EXPECT_EQ(text.substr(in.offset()), "DATA");
  ASSERT_TRUE(in.next_line());
  EXPECT_FALSE(in.terminated());
  EXPECT_FALSE(in.next_line());
}

TEST(Tokenizer, ReadTextFile) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "lockstep-tokenizer-test";
  fs::create_directories(dir);
  const std::string file = (dir / "a.txt").string();
  std::ofstream(file) << "one two\n";
  EXPECT_EQ(read_text_file(file, {}, 100), "one two\n");
  auto message = [&](const std::string& path, size_t max) {
    try {
      read_text_file(path, {.missing = "gone", .folder = "a folder"}, max);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(message(file, 4), file + ": too large (over 4 bytes)");
  EXPECT_EQ(message((dir / "none").string(), 100), (dir / "none").string() + ": gone");
  EXPECT_EQ(message(dir.string(), 100), dir.string() + ": a folder");
  fs::remove_all(dir);
}

TEST(Text, NumbersWhole) {
  double x = 0;
  long n = 0;
  bool range = false;
  EXPECT_TRUE(parse_double("-1.5e3", x));
  EXPECT_EQ(x, -1500);
  EXPECT_FALSE(parse_double("1.5x", x));
  EXPECT_FALSE(parse_double("", x));
  EXPECT_TRUE(parse_double("1e-320", x, &range));
  EXPECT_TRUE(range);
  // Longer than the stack buffer.
  EXPECT_TRUE(parse_double("0." + std::string(80, '0') + "1", x));
  EXPECT_GT(x, 0);
  EXPECT_TRUE(parse_long("-42", n));
  EXPECT_EQ(n, -42);
  EXPECT_FALSE(parse_long("42 ", n));
  EXPECT_FALSE(parse_long("99999999999999999999", n));
}

}  // namespace
