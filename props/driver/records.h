// lockstep props/driver: counterexample files, for every family.
//
// A counterexample file: the driver's header, then the family's case text.
//   family    ray_cast (the default: files from before families had the field) | composite | ...
//   property  <check>.<generator>.<pair>.<impl>
//   check     the Property::check ("all": every property of the family)
//   pair      the typed row; impl the implementation ("all": every implementation)
//   expect    pass | classified <label>
//   seed, note   informational
// Every other line (in order) is the family's case text.
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace lockstep::props::driver {

struct Record {
  std::string family = "ray_cast", property, check, pair, impl, expect = "pass", seed;
  std::vector<std::string> notes;
  std::string text;  // the family's case text
};

// The keys of the driver's header; every other line belongs to the family's text.
const std::set<std::string>& header_keys();
void write_record(const std::filesystem::path& path, const Record& r);
// Throws std::runtime_error on an unreadable file or a missing check/pair/impl.
Record read_record(const std::filesystem::path& path);
// dir/<id>-<n>.txt, n the first free number.
std::filesystem::path next_free(const std::filesystem::path& dir, const std::string& id);

}  // namespace lockstep::props::driver
