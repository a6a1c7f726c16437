// lockstep props: the text of a case's volume, shared by the families whose
// cases hold one (props/marching_cubes, props/volume): numbers as hex floats
// (exact), one sample row a line, '#' lines (a counterexample file's own
// comments) not part of the case.
#pragma once

#include <iosfwd>
#include <string>

#include "core/volume.h"

namespace lockstep::props::gen {

// x as a hex float ("%a"): read back exactly.
std::string hex(double x);
// text without its lines that start with '#'.
std::string without_comments(const std::string& text);
// "spacing X Y Z\norigin X Y Z\n".
void write_geometry(std::ostream& s, const Volume& v);
// Reads what write_geometry wrote; InputError(file, 0, ...) when it is not there.
void read_geometry(std::istream& s, Volume& v, const std::string& file);
// The samples, one row of i a line, rows of j, then slices of k.
void write_samples(std::ostream& s, const Volume& v);
// Reads v.nx * v.ny * v.nz samples into v.data; InputError when too few.
void read_samples(std::istream& s, Volume& v, const std::string& file);

}  // namespace lockstep::props::gen
