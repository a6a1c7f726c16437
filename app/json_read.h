// A small JSON reader for the files lockstep writes itself (report.json,
// lockstep-report/1), read back by `lockstep merge-reports`. Strict RFC 8259
// (no comments, no trailing commas); errors name the file and line.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace lockstep::cli {

struct JsonValue {
  enum class Type { kNull, kBool, kNumber, kString, kArray, kObject } type = Type::kNull;
  bool boolean = false;
  double number = 0;
  bool integer = false;  // the number was written without fraction or exponent
  std::string string;
  std::vector<JsonValue> array;
  std::vector<std::pair<std::string, JsonValue>> object;  // in file order
  int line = 0;                                           // where the value starts

  const JsonValue* find(const std::string& key) const {
    for (const auto& [k, v] : object)
      if (k == key) return &v;
    return nullptr;
  }
};

// Parses the whole text; throws InputError(path, line, what) when it is not JSON.
JsonValue parse_json(const std::string& text, const std::string& path);
// Reads and parses a file (InputError naming it when it cannot be read).
JsonValue read_json_file(const std::string& path);
// Writes a value back as JSON (one line; numbers as json_number, integers as integers).
std::string to_json(const JsonValue& v);

}  // namespace lockstep::cli
