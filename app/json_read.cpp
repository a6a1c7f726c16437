// A small strict JSON reader (see app/json_read.h).
#include "app/json_read.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "app/verify.h"

namespace lockstep::cli {

namespace {

struct Parser {
  const std::string& s;
  const std::string& path;
  size_t i = 0;
  int line = 1;
  int depth = 0;

  [[noreturn]] void error(const std::string& what) const {
    throw InputError(path, line, "not valid JSON: " + what);
  }

  void space() {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\n' || s[i] == '\r')) {
      if (s[i] == '\n') ++line;
      ++i;
    }
  }
  bool literal(const char* word) {
    const size_t n = std::char_traits<char>::length(word);
    if (s.compare(i, n, word) != 0) return false;
    i += n;
    return true;
  }
  static void utf8(std::string& out, unsigned cp) {
    if (cp < 0x80) {
      out += char(cp);
    } else if (cp < 0x800) {
      out += char(0xC0 | cp >> 6);
      out += char(0x80 | (cp & 63));
    } else if (cp < 0x10000) {
      out += char(0xE0 | cp >> 12);
      out += char(0x80 | (cp >> 6 & 63));
      out += char(0x80 | (cp & 63));
    } else {
      out += char(0xF0 | cp >> 18);
      out += char(0x80 | (cp >> 12 & 63));
      out += char(0x80 | (cp >> 6 & 63));
      out += char(0x80 | (cp & 63));
    }
  }
  unsigned hex4() {
    if (i + 4 > s.size()) error("truncated \\u escape");
    unsigned v = 0;
    for (int k = 0; k < 4; ++k) {
      const char c = s[i++];
      v <<= 4;
      if (c >= '0' && c <= '9')
        v |= unsigned(c - '0');
      else if (c >= 'a' && c <= 'f')
        v |= unsigned(c - 'a' + 10);
      else if (c >= 'A' && c <= 'F')
        v |= unsigned(c - 'A' + 10);
      else
        error("bad \\u escape");
    }
    return v;
  }
  std::string string() {
    ++i;  // the opening quote
    std::string out;
    for (;;) {
      if (i >= s.size()) error("unterminated string");
      const unsigned char c = s[i++];
      if (c == '"') return out;
      if (c < 0x20) error("control character in a string");
      if (c != '\\') {
        out += char(c);
        continue;
      }
      if (i >= s.size()) error("unterminated string");
      switch (s[i++]) {
        case '"':
          out += '"';
          break;
        case '\\':
          out += '\\';
          break;
        case '/':
          out += '/';
          break;
        case 'b':
          out += '\b';
          break;
        case 'f':
          out += '\f';
          break;
        case 'n':
          out += '\n';
          break;
        case 'r':
          out += '\r';
          break;
        case 't':
          out += '\t';
          break;
        case 'u': {
          unsigned cp = hex4();
          if (cp >= 0xD800 && cp < 0xDC00 && s.compare(i, 2, "\\u") == 0) {
            i += 2;
            const unsigned lo = hex4();
            if (lo < 0xDC00 || lo >= 0xE000) error("bad surrogate pair");
            cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
          }
          utf8(out, cp);
          break;
        }
        default:
          error("bad escape in a string");
      }
    }
  }
  JsonValue value() {
    space();
    if (i >= s.size()) error("unexpected end of file");
    if (++depth > 200) error("nested too deeply");
    JsonValue v;
    v.line = line;
    const char c = s[i];
    if (c == '{') {
      v.type = JsonValue::Type::kObject;
      ++i;
      space();
      if (i < s.size() && s[i] == '}') {
        ++i;
      } else {
        for (;;) {
          space();
          if (i >= s.size() || s[i] != '"') error("expected a key in quotes");
          std::string key = string();
          space();
          if (i >= s.size() || s[i] != ':') error("expected ':' after key \"" + key + "\"");
          ++i;
          v.object.emplace_back(std::move(key), value());
          space();
          if (i < s.size() && s[i] == ',') {
            ++i;
          } else if (i < s.size() && s[i] == '}') {
            ++i;
            break;
          } else {
            error("expected ',' or '}' in an object");
          }
        }
      }
    } else if (c == '[') {
      v.type = JsonValue::Type::kArray;
      ++i;
      space();
      if (i < s.size() && s[i] == ']') {
        ++i;
      } else {
        for (;;) {
          v.array.push_back(value());
          space();
          if (i < s.size() && s[i] == ',') {
            ++i;
          } else if (i < s.size() && s[i] == ']') {
            ++i;
            break;
          } else {
            error("expected ',' or ']' in an array");
          }
        }
      }
    } else if (c == '"') {
      v.type = JsonValue::Type::kString;
      v.string = string();
    } else if (literal("true")) {
      v.type = JsonValue::Type::kBool;
      v.boolean = true;
    } else if (literal("false")) {
      v.type = JsonValue::Type::kBool;
    } else if (literal("null")) {
      v.type = JsonValue::Type::kNull;
    } else if (c == '-' || (c >= '0' && c <= '9')) {
      const size_t start = i;
      if (s[i] == '-') ++i;
      auto digits = [&] {
        const size_t d = i;
        while (i < s.size() && s[i] >= '0' && s[i] <= '9') ++i;
        if (i == d) error("bad number");
      };
      digits();
      v.integer = true;
      if (i < s.size() && s[i] == '.') {
        ++i;
        digits();
        v.integer = false;
      }
      if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
        digits();
        v.integer = false;
      }
      v.type = JsonValue::Type::kNumber;
      v.number = std::strtod(s.substr(start, i - start).c_str(), nullptr);
      if (!std::isfinite(v.number)) error("number out of range");
    } else {
      error(std::string("unexpected character '") + c + "'");
    }
    --depth;
    return v;
  }
};

}  // namespace

JsonValue parse_json(const std::string& text, const std::string& path) {
  Parser p{text, path};
  JsonValue v = p.value();
  p.space();
  if (p.i != text.size()) p.error("text after the value");
  return v;
}

JsonValue read_json_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, 0, "cannot read (no such file, or not readable)");
  std::ostringstream s;
  s << f.rdbuf();
  if (f.bad()) throw InputError(path, 0, "cannot read");
  return parse_json(s.str(), path);
}

std::string to_json(const JsonValue& v) {
  switch (v.type) {
    case JsonValue::Type::kNull:
      return "null";
    case JsonValue::Type::kBool:
      return v.boolean ? "true" : "false";
    case JsonValue::Type::kNumber:
      if (v.integer && std::fabs(v.number) < 9e15) return std::to_string((long long)v.number);
      return json_number(v.number);
    case JsonValue::Type::kString:
      return json_string(v.string);
    case JsonValue::Type::kArray: {
      std::string o = "[";
      for (size_t k = 0; k < v.array.size(); ++k) o += (k ? ", " : "") + to_json(v.array[k]);
      return o + "]";
    }
    case JsonValue::Type::kObject: {
      std::string o = "{";
      for (size_t k = 0; k < v.object.size(); ++k)
        o += (k ? ", " : "") + json_string(v.object[k].first) + ": " + to_json(v.object[k].second);
      return o + "}";
    }
  }
  return "null";
}

}  // namespace lockstep::cli
