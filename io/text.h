// lockstep io: the small text steps the file readers share (with their tokenizer,
// io/tokenizer.h): trimming, splitting into words, quoting a word for a message,
// numbers parsed whole or refused, and the guarded first read of a file.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace lockstep::text {

// s without leading and trailing white space.
std::string_view trim(std::string_view s);
// s split at white space.
std::vector<std::string_view> words(std::string_view s);
// s in single quotes for a message: at most 40 characters, non-printable bytes as \xNN.
std::string quoted(std::string_view s);
std::string lower(std::string s);
// ".nrrd" of "a/b.NRRD" (lower case; "" without one).
std::string extension_of(const std::string& path);
// "a" of "a/b.nrrd" ("." without a folder).
std::string directory_of(const std::string& path);
// The size of a regular file; InputError(report_as, line, what ...) when path is
// missing, unreadable or not a regular file (a FIFO or device would hang or never end).
size_t regular_file_size(const std::string& path, const std::string& report_as, int line, const char* what);
// Up to max_bytes of a file (the whole file when it is shorter); InputError(path, 0, ...)
// when it cannot be opened or read.
std::string read_prefix(const std::string& path, size_t max_bytes);
// Strict decimals: parse_size no sign and no spaces, parse_long within long's range;
// false on anything else or on overflow.
bool parse_size(std::string_view s, size_t& out);
bool parse_long(std::string_view s, long& out);
// strtod over all of s: false when s is empty or not all of it is the number
// (NaN and Inf pass: check isfinite). range_error: strtod set ERANGE (overflow,
// or underflow to a denormal or 0).
bool parse_double(std::string_view s, double& out, bool* range_error = nullptr);

}  // namespace lockstep::text
