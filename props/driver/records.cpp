// lockstep props/driver: counterexample files (see records.h).
#include "props/driver/records.h"

#include <fstream>
#include <stdexcept>

namespace lockstep::props::driver {

namespace fs = std::filesystem;


const std::set<std::string>& header_keys() {
  static const std::set<std::string> k = {"family", "property", "check", "pair", "impl", "expect", "seed", "note"};
  return k;
}

void write_record(const fs::path& path, const Record& r) {
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  std::ofstream out(path);
  out << "# lockstep counterexample (props/). Floats are C99 hexfloats (%a): the case replays bit for bit.\n";
  out << "# Format: corpus/counterexamples/README.md\n";
  out << "family " << r.family << "\n";
  out << "property " << r.property << "\n";
  out << "check " << r.check << "\n";
  out << "pair " << r.pair << "\n";
  out << "impl " << r.impl << "\n";
  out << "expect " << r.expect << "\n";
  if (!r.seed.empty()) out << "seed " << r.seed << "\n";
  for (const auto& n : r.notes) {
    std::string line = n;
    for (char& ch : line)
      if (ch == '\n') ch = ' ';
    out << "note " << line << "\n";
  }
  out << r.text;
}

Record read_record(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot read");
  Record r;
  for (std::string line; std::getline(in, line);) {
    const size_t sp = line.find(' ');
    const std::string key = line.substr(0, sp);
    const std::string rest = sp == std::string::npos ? "" : line.substr(sp + 1);
    if (!header_keys().count(key)) {
      r.text += line + "\n";
      continue;
    }
    if (key == "family") r.family = rest;
    else if (key == "property") r.property = rest;
    else if (key == "check") r.check = rest;
    else if (key == "pair") r.pair = rest;
    else if (key == "impl") r.impl = rest;
    else if (key == "expect") r.expect = rest;
    else if (key == "seed") r.seed = rest;
    else r.notes.push_back(rest);
  }
  if (r.check.empty() || r.pair.empty() || r.impl.empty())
    throw std::runtime_error(path.string() + ": check, pair and impl are required");
  return r;
}

fs::path next_free(const fs::path& dir, const std::string& id) {
  for (int n = 1;; ++n) {
    fs::path p = dir / (id + "-" + std::to_string(n) + ".txt");
    if (!fs::exists(p)) return p;
  }
}

}  // namespace lockstep::props::driver
