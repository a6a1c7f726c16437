// lockstep props/marching_cubes: the case's text form (see case.h).
#include "props/marching_cubes/case.h"

#include <cstdlib>
#include <sstream>

#include "core/error.h"
#include "props/gen/case_text.h"

namespace lockstep::props::marching_cubes {

using gen::hex;

std::string write_case(const McCase& c) {
  const Volume& v = c.volume;
  std::ostringstream s;
  s << "mc_case " << v.nx << " " << v.ny << " " << v.nz << " iso " << hex(c.iso) << "\n";
  gen::write_geometry(s, v);
  gen::write_samples(s, v);
  return s.str();
}

McCase read_case(const std::string& text, const std::string& file) {
  std::istringstream s(gen::without_comments(text));
  std::string word, iso;
  McCase c;
  Volume& v = c.volume;
  if (!(s >> word >> v.nx >> v.ny >> v.nz >> iso >> iso) || word != "mc_case" || v.nx < 2 || v.ny < 2 || v.nz < 2 ||
      v.nx > 64 || v.ny > 64 || v.nz > 64)
    throw InputError(file, 0, "expected 'mc_case NX NY NZ iso ISO'");
  c.iso = std::strtod(iso.c_str(), nullptr);
  gen::read_geometry(s, v, file);
  gen::read_samples(s, v, file);
  v.source = file;
  return c;
}

}  // namespace lockstep::props::marching_cubes
