// lockstep props: the text of a case's volume (see props/gen/case_text.h).
#include "props/gen/case_text.h"

#include <cstdio>
#include <cstdlib>
#include <istream>
#include <ostream>
#include <sstream>

#include "core/error.h"

namespace lockstep::props::gen {

std::string hex(double x) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}

std::string without_comments(const std::string& text) {
  std::string body;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (line.empty() || line[0] != '#') body += line + "\n";
  return body;
}

void write_geometry(std::ostream& s, const Volume& v) {
  s << "spacing " << hex(v.spacing.x) << " " << hex(v.spacing.y) << " " << hex(v.spacing.z) << "\n";
  s << "origin " << hex(v.origin.x) << " " << hex(v.origin.y) << " " << hex(v.origin.z) << "\n";
}

void read_geometry(std::istream& s, Volume& v, const std::string& file) {
  auto num = [](const std::string& w) { return std::strtod(w.c_str(), nullptr); };
  std::string word, x, y, z;
  if (!(s >> word >> x >> y >> z) || word != "spacing") throw InputError(file, 0, "expected 'spacing X Y Z'");
  v.spacing = {num(x), num(y), num(z)};
  if (!(s >> word >> x >> y >> z) || word != "origin") throw InputError(file, 0, "expected 'origin X Y Z'");
  v.origin = {num(x), num(y), num(z)};
}

void write_samples(std::ostream& s, const Volume& v) {
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j) {
      for (int i = 0; i < v.nx; ++i) s << (i ? " " : "") << hex(v.at(i, j, k));
      s << "\n";
    }
}

void read_samples(std::istream& s, Volume& v, const std::string& file) {
  v.data.resize(size_t(v.nx) * size_t(v.ny) * size_t(v.nz));
  std::string word;
  for (float& x : v.data) {
    if (!(s >> word)) throw InputError(file, 0, "too few samples");
    x = float(std::strtod(word.c_str(), nullptr));
  }
}

}  // namespace lockstep::props::gen
