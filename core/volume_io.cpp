// lockstep core: reading volumes (NRRD through Teem, analytic fields); see core/volume_io.h.
#include "core/volume_io.h"

#include <sys/stat.h>
#include <teem/air.h>
#include <teem/biff.h>
#include <teem/nrrd.h>
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <mutex>
#include <numbers>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.h"

namespace lockstep {

namespace {

// ------------------------------------------------------------------ small text helpers

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> words(std::string_view s) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    size_t j = i;
    while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j]))) ++j;
    if (j > i) out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

// Quoted for messages: at most 40 characters, non-printable bytes as \xNN.
std::string quoted(std::string_view s) {
  std::string out = "'";
  for (size_t i = 0; i < s.size() && i < 40; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c >= 32 && c < 127) {
      out += char(c);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    }
  }
  if (s.size() > 40) out += "...";
  return out + "'";
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string extension_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  return lower(path.substr(dot));
}

std::string directory_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash == 0 ? 1 : slash);
}

// What stat says about a path: an InputError unless it is a regular file.
size_t regular_file_size(const std::string& path, const std::string& report_as, int line, const char* what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw InputError(report_as, line, std::string("cannot open ") + what + ": " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw InputError(report_as, line, std::string(what) + " is not a regular file");
  return size_t(st.st_size);
}

// Up to max_bytes of a file (the whole file when it is shorter).
std::string read_prefix(const std::string& path, size_t max_bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
  std::string s(max_bytes, '\0');
  in.read(s.data(), std::streamsize(max_bytes));
  s.resize(size_t(in.gcount()));
  if (in.bad()) throw InputError(path, 0, "read error");
  return s;
}

// A strict unsigned decimal (no sign, no spaces): false on anything else or overflow.
bool parse_size(std::string_view s, size_t& out) {
  if (s.empty() || s.size() > 19) return false;
  size_t v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
    v = v * 10 + size_t(c - '0');
  }
  out = v;
  return true;
}

// A strict signed decimal within long's range.
bool parse_long(std::string_view s, long& out) {
  const std::string t(s);
  if (t.empty()) return false;
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(t.c_str(), &end, 10);
  if (end == t.c_str() || *end != '\0' || errno == ERANGE) return false;
  out = v;
  return true;
}

// ------------------------------------------------------------------ the NRRD header, read by us before Teem

// What read_volume needs to know about a NRRD header before it hands the file to Teem.
struct NrrdHeader {
  int line_of[nrrdField_last] = {};  // line of each field (0: absent)
  int type = nrrdTypeUnknown;
  std::string type_name;  // as written
  int encoding = nrrdEncodingTypeUnknown;
  size_t sizes[3] = {0, 0, 0};
  std::string data_file;  // as written; empty when the data is attached
  long byte_skip = 0, line_skip = 0;
  size_t data_offset = 0;    // attached: first byte after the blank line
  bool header_ends = false;  // a blank line ends the header (else it ends at end of file)
};

constexpr size_t kMaxHeaderBytes = size_t(1) << 20;

bool supported_type(int t) {
  switch (t) {
    case nrrdTypeChar:
    case nrrdTypeUChar:
    case nrrdTypeShort:
    case nrrdTypeUShort:
    case nrrdTypeInt:
    case nrrdTypeUInt:
    case nrrdTypeFloat:
    case nrrdTypeDouble:
      return true;
    default:
      return false;
  }
}

size_t type_size(int t) {
  switch (t) {
    case nrrdTypeChar:
    case nrrdTypeUChar:
      return 1;
    case nrrdTypeShort:
    case nrrdTypeUShort:
      return 2;
    case nrrdTypeInt:
    case nrrdTypeUInt:
    case nrrdTypeFloat:
      return 4;
    default:
      return 8;
  }
}

// Inflates the gzip stream (members one after another, as Teem reads them)
// that starts at byte `offset` of `file`, up to `need` bytes; an InputError
// unless it yields them.
void check_gzip(const std::string& file, size_t offset, size_t need, const std::string& path, const NrrdHeader& h) {
  std::ifstream in(file, std::ios::binary);
  in.seekg(std::streamoff(offset));
  z_stream z{};
  if (inflateInit2(&z, 15 + 16) != Z_OK) throw InputError(path, 0, "zlib: out of memory");
  std::vector<unsigned char> input(size_t(1) << 16), output(size_t(1) << 16);
  size_t out = 0;
  std::string error;
  bool eof = false, ended = false;
  while (out < need) {
    if (z.avail_in == 0 && !eof) {
      in.read(reinterpret_cast<char*>(input.data()), std::streamsize(input.size()));
      z.next_in = input.data();
      z.avail_in = uInt(std::max<std::streamsize>(in.gcount(), 0));
      eof = z.avail_in == 0;
    }
    if (z.avail_in == 0 && eof) break;
    // No further than the sizes need, as Teem (what lies beyond, it never inflates).
    const size_t room = std::min(output.size(), need - out);
    z.next_out = output.data();
    z.avail_out = uInt(room);
    const int ret = inflate(&z, Z_NO_FLUSH);
    out += room - z.avail_out;
    ended = ret == Z_STREAM_END;
    if (ret == Z_STREAM_END) {
      if (out >= need) break;
      inflateReset(&z);  // another member may follow
      continue;
    }
    if (ret != Z_OK && ret != Z_BUF_ERROR) {
      error = z.msg ? z.msg : "error " + std::to_string(ret);
      break;
    }
  }
  // All bytes out, but the member not finished: Teem goes on reading the
  // stream after its last byte (in the same call) and fails on a stream that
  // stops there, so inflate on with no room for output: it must reach the end
  // of the member, or stop for want of room (more data than needed: fine).
  while (out >= need && error.empty() && !ended) {
    if (z.avail_in == 0 && !eof) {
      in.read(reinterpret_cast<char*>(input.data()), std::streamsize(input.size()));
      z.next_in = input.data();
      z.avail_in = uInt(std::max<std::streamsize>(in.gcount(), 0));
      eof = z.avail_in == 0;
    }
    unsigned char none = 0;
    z.next_out = &none;
    z.avail_out = 0;
    const int ret = inflate(&z, Z_NO_FLUSH);
    if (ret == Z_STREAM_END) {
      ended = true;
    } else if (ret == Z_BUF_ERROR && z.avail_in == 0 && eof) {
      error = "the stream stops before its end";
    } else if (ret == Z_BUF_ERROR && z.avail_in > 0) {
      break;  // wants room for more output: the stream holds more than the sizes need
    } else if (ret != Z_OK && ret != Z_BUF_ERROR) {
      error = z.msg ? z.msg : "error " + std::to_string(ret);
    }
  }
  // When the stream ends with the last byte needed, Teem (zlib's old gzio)
  // looks at what follows: gzip's magic starts another member, whose header
  // must then be sound (deflate, no reserved flags).
  if (out >= need && error.empty() && ended) {
    std::string rest(reinterpret_cast<const char*>(z.next_in), z.avail_in);
    if (rest.size() < 4 && !eof) {
      char more[4];
      in.read(more, 4);
      rest.append(more, size_t(std::max<std::streamsize>(in.gcount(), 0)));
    }
    if (rest.size() >= 2 && rest[0] == '\x1f' && rest[1] == '\x8b' &&
        (rest.size() < 4 || rest[2] != 8 || (static_cast<unsigned char>(rest[3]) & 0xe0) != 0))
      error = "a broken gzip header after the data";
  }
  inflateEnd(&z);
  if (out >= need && error.empty()) return;
  const int line = h.line_of[nrrdField_encoding];
  if (out == 0 && !error.empty())
    throw InputError(path, line, "encoding gzip, but the data is not gzip (zlib: " + error + ")");
  if (!error.empty())
    throw InputError(path, line,
                     "corrupt gzip data after " + std::to_string(out) + " of the " + std::to_string(need) +
                         " bytes the sizes need (zlib: " + error + ")");
  throw InputError(
      path, h.line_of[nrrdField_sizes],
      "sizes need " + std::to_string(need) + " bytes, but the gzip data inflates to " + std::to_string(out));
}

// Reads and checks the header of the NRRD file at path (core/volume_io.h lists the checks).
NrrdHeader scan_nrrd_header(const std::string& path) {
  const size_t file_size = regular_file_size(path, path, 0, "file");
  if (file_size == 0) throw InputError(path, 0, "file is empty");
  const std::string text = read_prefix(path, std::min(file_size, kMaxHeaderBytes));

  NrrdHeader h;
  size_t pos = 0;
  int line_no = 0;
  // The lines, '\n'-terminated ('\r' before it dropped), up to the first empty line.
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    const bool last = end == std::string::npos;
    if (last) {
      if (text.size() == kMaxHeaderBytes && file_size > kMaxHeaderBytes)
        throw InputError(path, line_no + 1, "header longer than 1 MiB (no blank line ends it)");
      end = text.size();
    }
    std::string_view line(text.data() + pos, end - pos);
    pos = last ? end : end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty()) {
      h.header_ends = true;
      h.data_offset = pos;
      break;
    }
    if (line.find('\0') != std::string_view::npos) throw InputError(path, line_no, "NUL byte in the NRRD header");
    if (line_no == 1) {
      if (!(line.size() == 8 && line.substr(0, 7) == "NRRD000" && line[7] >= '1' && line[7] <= '5'))
        throw InputError(path, 1, "not a NRRD file: the first line is " + quoted(line) + ", not NRRD0001..NRRD0005");
      continue;
    }
    if (line.front() == '#') continue;
    if (line.find(":=") != std::string_view::npos && line.find(": ") > line.find(":=")) continue;  // key:=value
    const size_t colon = line.find(':');
    if (colon == std::string_view::npos)
      throw InputError(path, line_no, "not a NRRD field ('name: value'): " + quoted(line));
    const std::string name(trim(line.substr(0, colon)));
    const std::string_view value = trim(line.substr(colon + 1));
    const int field = airEnumVal(nrrdField, name.c_str());
    if (field == nrrdField_unknown || field == nrrdField_comment || field == nrrdField_keyvalue)
      throw InputError(path, line_no, "unknown NRRD field " + quoted(name));
    if (h.line_of[field])
      throw InputError(
          path, line_no,
          "a second '" + name + ":' field (the first is on line " + std::to_string(h.line_of[field]) + ")");
    h.line_of[field] = line_no;
    if (field >= nrrdField_sizes && field <= nrrdField_units && !h.line_of[nrrdField_dimension])
      throw InputError(path, line_no, "'" + name + ":' must come after 'dimension:'");
    if (field == nrrdField_block_size)
      throw InputError(path, line_no, "block size: only for type block, which is not read");
    const std::string v(value);
    switch (field) {
      case nrrdField_dimension: {
        long d = 0;
        if (!parse_long(value, d)) throw InputError(path, line_no, "dimension is not an integer: " + quoted(value));
        if (d != 3) throw InputError(path, line_no, "dimension " + std::to_string(d) + ": only 3-D volumes are read");
        break;
      }
      case nrrdField_sizes: {
        const auto w = words(value);
        if (w.size() != 3)
          throw InputError(path, line_no, "sizes: " + std::to_string(w.size()) + " values, expected 3 (a 3-D volume)");
        size_t total = 1;
        for (int a = 0; a < 3; ++a) {
          size_t n = 0;
          if (!parse_size(w[a], n))
            throw InputError(path, line_no, "sizes: " + quoted(w[a]) + " is not a size (a non-negative integer)");
          if (n < 2)
            throw InputError(
                path, line_no,
                "sizes: axis " + std::to_string(a) + " has " + std::to_string(n) + " sample(s); at least 2 are needed");
          if (n > kMaxVolumeSamples || total > kMaxVolumeSamples / n)
            throw InputError(path, line_no,
                             "sizes " + std::string(w[0]) + " x " + std::string(w[1]) + " x " + std::string(w[2]) +
                                 " exceed " + std::to_string(kMaxVolumeSamples) + " samples");
          total *= n;
          h.sizes[a] = n;
        }
        break;
      }
      case nrrdField_type: {
        h.type = airEnumVal(nrrdType, v.c_str());
        h.type_name = v;
        if (h.type == nrrdTypeUnknown) throw InputError(path, line_no, "unknown type " + quoted(value));
        if (!supported_type(h.type))
          throw InputError(
              path, line_no,
              "type " + quoted(value) + " is not read (uchar, char, ushort, short, uint, int, float, double)");
        break;
      }
      case nrrdField_encoding: {
        h.encoding = airEnumVal(nrrdEncodingType, v.c_str());
        if (h.encoding == nrrdEncodingTypeUnknown) throw InputError(path, line_no, "unknown encoding " + quoted(value));
        if (h.encoding == nrrdEncodingTypeGzip && !nrrdEncodingGzip->available())
          throw InputError(path, line_no, "encoding gzip: this Teem was built without zlib");
        if (h.encoding != nrrdEncodingTypeRaw && h.encoding != nrrdEncodingTypeGzip &&
            h.encoding != nrrdEncodingTypeAscii && h.encoding != nrrdEncodingTypeHex)
          throw InputError(path, line_no, "encoding " + quoted(value) + " is not read (raw, gzip, ascii, hex)");
        break;
      }
      case nrrdField_endian:
        if (airEnumVal(airEndian, v.c_str()) == airEndianUnknown)
          throw InputError(path, line_no, "unknown endian " + quoted(value) + " (little or big)");
        break;
      case nrrdField_data_file:
        if (value.empty()) throw InputError(path, line_no, "data file: no file name");
        if (value.starts_with("LIST") || value.find('%') != std::string_view::npos)
          throw InputError(path, line_no,
                           "data file: lists and numbered sequences of files are not read (one file only)");
        if (value == "-") throw InputError(path, line_no, "data file: standard input is not read");
        h.data_file = v;
        break;
      case nrrdField_byte_skip:
        if (!parse_long(value, h.byte_skip) || h.byte_skip < -1)
          throw InputError(path, line_no, "byte skip must be an integer >= -1, got " + quoted(value));
        break;
      case nrrdField_line_skip:
        if (!parse_long(value, h.line_skip) || h.line_skip < 0)
          throw InputError(path, line_no, "line skip must be an integer >= 0, got " + quoted(value));
        break;
      default:
        break;  // Teem parses the rest (spacings, space directions, origin, kinds, ...)
    }
  }
  const struct {
    int field;
    const char* name;
  } required[] = {{nrrdField_type, "type"},
                  {nrrdField_dimension, "dimension"},
                  {nrrdField_sizes, "sizes"},
                  {nrrdField_encoding, "encoding"}};
  for (const auto& r : required)
    if (!h.line_of[r.field]) throw InputError(path, 0, std::string("the NRRD header has no '") + r.name + ":' field");
  if (h.type != nrrdTypeUChar && h.type != nrrdTypeChar && !h.line_of[nrrdField_endian] &&
      (h.encoding == nrrdEncodingTypeRaw || h.encoding == nrrdEncodingTypeGzip || h.encoding == nrrdEncodingTypeHex))
    throw InputError(path, 0,
                     "the NRRD header has no 'endian:' field (needed for multi-byte " +
                         std::string(airEnumStr(nrrdType, h.type)) + " data)");

  // Is the data there? Teem allocates for the sizes before it reads.
  const size_t samples = h.sizes[0] * h.sizes[1] * h.sizes[2];
  const size_t bytes = samples * type_size(h.type);
  size_t available = 0;
  const int where = h.line_of[nrrdField_sizes];  // the sizes are what claims too much
  std::string data_name = path;
  if (!h.data_file.empty()) {
    data_name = h.data_file.front() == '/' ? h.data_file : directory_of(path) + "/" + h.data_file;
    available = regular_file_size(data_name, path, h.line_of[nrrdField_data_file],
                                  ("data file " + quoted(h.data_file)).c_str());
  } else {
    if (!h.header_ends) throw InputError(path, 0, "no data: neither a 'data file:' field nor a blank line before data");
    available = file_size - h.data_offset;
  }
  if (h.byte_skip > 0) available -= std::min(available, size_t(h.byte_skip));
  const std::string sizes =
      std::to_string(h.sizes[0]) + " x " + std::to_string(h.sizes[1]) + " x " + std::to_string(h.sizes[2]);
  auto too_little = [&](const std::string& need) {
    throw InputError(path, where,
                     "sizes " + sizes + " " + h.type_name + " need " + need + ", but the " +
                         (h.data_file.empty() ? "file holds " : "data file " + quoted(h.data_file) + " holds ") +
                         std::to_string(available) + " byte(s) of data");
  };
  switch (h.encoding) {
    case nrrdEncodingTypeRaw:
      if (available < bytes) too_little(std::to_string(bytes) + " bytes");
      break;
    case nrrdEncodingTypeHex:
      if (available / 2 < bytes)
        too_little(std::to_string(bytes) + " bytes (" + std::to_string(2 * bytes) + " hex digits)");
      break;
    case nrrdEncodingTypeAscii:
      if (available < samples) too_little(std::to_string(samples) + " numbers");
      break;
    case nrrdEncodingTypeGzip:
      if (available == 0 || (bytes - 1) / 1032 >= available)
        too_little(std::to_string(bytes) + " bytes (gzip: at least " + std::to_string(bytes / 1032 + 1) +
                   " compressed)");
      break;
  }
  // gzip: Teem's reader leaks its zlib state on each of its error paths (a
  // corrupt or short stream), and zlib reads data without gzip's magic as it is
  // (raw bytes labelled gzip would pass). So the stream is inflated here first,
  // as far as the sizes need, and Teem only sees streams that hold the data.
  if (h.encoding == nrrdEncodingTypeGzip) {
    if (h.line_skip != 0)
      throw InputError(path, h.line_of[nrrdField_line_skip], "line skip with gzip encoding is not read");
    if (h.byte_skip < 0) throw InputError(path, h.line_of[nrrdField_byte_skip], "byte skip -1 needs raw encoding");
    check_gzip(data_name, (h.data_file.empty() ? h.data_offset : 0) + size_t(h.byte_skip), bytes, path, h);
  }
  return h;
}

// ------------------------------------------------------------------ Teem

std::mutex& teem_mutex() {
  static std::mutex m;
  return m;
}

// Teem's error for what just failed, from biff: its innermost message (without
// the "[nrrd] function: " prefix) and the header line it is about, found from
// the field the parsing functions name ("_nrrdReadNrrdParse_spacings: ...",
// "trouble parsing spacings info ..."); 0 when it names none.
std::pair<int, std::string> teem_error(const NrrdHeader& h) {
  char* err = biffGetDone(NRRD);
  const std::string all = err ? err : "";
  std::free(err);
  std::vector<std::string> lines;
  size_t pos = 0;
  while (pos < all.size()) {
    size_t end = all.find('\n', pos);
    if (end == std::string::npos) end = all.size();
    std::string l(trim(std::string_view(all).substr(pos, end - pos)));
    if (!l.empty()) lines.push_back(l);
    pos = end + 1;
  }
  if (lines.empty()) return {0, "Teem could not read it (no message)"};
  std::string m = lines.back();
  while (m.starts_with("[")) {
    const size_t close = m.find("] ");
    if (close == std::string::npos) break;
    m = m.substr(close + 2);
  }
  const size_t colon = m.find(": ");
  if (colon != std::string::npos && m.find(' ') > colon) m = m.substr(colon + 2);  // "function: " prefix
  for (int f = 1; f < nrrdField_last; ++f) {
    if (!h.line_of[f]) continue;
    const std::string name = airEnumStr(nrrdField, f);
    std::string fn = "_nrrdReadNrrdParse_" + name + ":";
    std::replace(fn.begin(), fn.end(), ' ', '_');
    if (all.find(fn) != std::string::npos || all.find("parsing " + name + " info") != std::string::npos)
      return {h.line_of[f], "Teem: " + name + ": " + m};
  }
  return {0, "Teem: " + m};
}

struct NrrdDeleter {
  void operator()(Nrrd* n) const { nrrdNuke(n); }
};
struct NioDeleter {
  void operator()(NrrdIoState* n) const { nrrdIoStateNix(n); }
};

template <class T>
void convert(const void* data, size_t n, std::vector<float>& out, size_t& bad) {
  const T* p = static_cast<const T*>(data);
  for (size_t i = 0; i < n; ++i) {
    const double v = double(p[i]);
    if (!std::isfinite(v) || std::abs(v) > double(FLT_MAX)) {
      bad = i;
      return;
    }
    out[i] = float(p[i]);
  }
}

// Reverses the samples along axis a (the file stores that axis in the negative direction).
void flip(Volume& v, int a) {
  for (int k = 0; k < v.nz; ++k)
    for (int j = 0; j < v.ny; ++j)
      for (int i = 0; i < v.nx; ++i) {
        int ii = i, jj = j, kk = k;
        if (a == 0) ii = v.nx - 1 - i;
        if (a == 1) jj = v.ny - 1 - j;
        if (a == 2) kk = v.nz - 1 - k;
        const size_t s = v.index(i, j, k), t = v.index(ii, jj, kk);
        if (s < t) std::swap(v.data[s], v.data[t]);
      }
}

Volume read_nrrd(const std::string& path) {
  const NrrdHeader h = scan_nrrd_header(path);
  Volume v;
  v.source = path;
  v.nx = int(h.sizes[0]);
  v.ny = int(h.sizes[1]);
  v.nz = int(h.sizes[2]);
  const size_t n = h.sizes[0] * h.sizes[1] * h.sizes[2];
  double spacing[3] = {1, 1, 1}, origin[3] = {0, 0, 0};
  size_t bad = n;
  double bad_value = 0;
  {
    std::lock_guard<std::mutex> lock(teem_mutex());
    nrrdStateVerboseIO = 0;
    std::unique_ptr<Nrrd, NrrdDeleter> nrrd(nrrdNew());
    std::unique_ptr<NrrdIoState, NioDeleter> nio(nrrdIoStateNew());
    if (!nrrd || !nio) throw InputError(path, 0, "out of memory");
    if (nrrdLoad(nrrd.get(), path.c_str(), nio.get())) {
      const auto [line, message] = teem_error(h);
      throw InputError(path, line, message);
    }
    const Nrrd* r = nrrd.get();
    if (r->dim != 3 || r->type != h.type || r->axis[0].size != h.sizes[0] || r->axis[1].size != h.sizes[1] ||
        r->axis[2].size != h.sizes[2] || !r->data)
      throw InputError(path, 0, "Teem read something other than the header says (dimension, type or sizes)");

    // Geometry.
    const char* axis_name = "xyz";
    for (unsigned a = 0; a < 3; ++a) {
      double s = NAN, dir[NRRD_SPACE_DIM_MAX];
      const int status = nrrdSpacingCalculate(r, a, &s, dir);
      const int line =
          h.line_of[nrrdField_space_directions] ? h.line_of[nrrdField_space_directions] : h.line_of[nrrdField_spacings];
      const std::string ax = "axis " + std::to_string(a) + ": ";
      switch (status) {
        case nrrdSpacingStatusNone:
          s = 1;
          break;
        case nrrdSpacingStatusScalarNoSpace:
        case nrrdSpacingStatusScalarWithSpace:
          break;
        case nrrdSpacingStatusDirection: {
          if (r->spaceDim != 3)
            throw InputError(path, line, ax + "a " + std::to_string(r->spaceDim) + "-D space; only 3-D space is read");
          for (unsigned c = 0; c < 3; ++c)
            if (c != a && dir[c] * s != 0)
              throw InputError(path, line,
                               ax + "space direction (" + std::to_string(dir[0] * s) + ", " +
                                   std::to_string(dir[1] * s) + ", " + std::to_string(dir[2] * s) + ") is not along " +
                                   axis_name[a] + " (oblique and permuted grids are not read)");
          s = dir[a] * s;  // nrrdSpacingCalculate gives the length and a unit vector
          break;
        }
        default:
          throw InputError(path, line, ax + "no usable spacing or space direction");
      }
      if (!std::isfinite(s) || s == 0 || std::abs(s) > 1e30 || std::abs(s) < 1e-30)
        throw InputError(path, line, ax + "spacing " + std::to_string(s) + " is zero, absurd or not finite");
      spacing[a] = s;
    }
    if (r->spaceDim == 3) {
      for (int c = 0; c < 3; ++c)
        if (std::isfinite(r->spaceOrigin[c])) origin[c] = r->spaceOrigin[c];
      for (int c = 0; c < 3; ++c)
        if (std::abs(origin[c]) > 1e30)
          throw InputError(path, h.line_of[nrrdField_space_origin], "space origin is absurd");
    } else if (r->spaceDim != 0) {
      throw InputError(path, h.line_of[nrrdField_space],
                       "a " + std::to_string(r->spaceDim) + "-D space; only 3-D space is read");
    }

    // The samples, as float, each finite.
    v.data.assign(n, 0.0f);
    switch (r->type) {
      case nrrdTypeChar:
        convert<signed char>(r->data, n, v.data, bad);
        break;
      case nrrdTypeUChar:
        convert<unsigned char>(r->data, n, v.data, bad);
        break;
      case nrrdTypeShort:
        convert<int16_t>(r->data, n, v.data, bad);
        break;
      case nrrdTypeUShort:
        convert<uint16_t>(r->data, n, v.data, bad);
        break;
      case nrrdTypeInt:
        convert<int32_t>(r->data, n, v.data, bad);
        break;
      case nrrdTypeUInt:
        convert<uint32_t>(r->data, n, v.data, bad);
        break;
      case nrrdTypeFloat:
        convert<float>(r->data, n, v.data, bad);
        break;
      case nrrdTypeDouble:
        convert<double>(r->data, n, v.data, bad);
        break;
    }
    if (bad < n) bad_value = nrrdDLookup[r->type](r->data, bad);
  }
  if (bad < n) {
    const size_t i = bad % h.sizes[0], j = bad / h.sizes[0] % h.sizes[1], k = bad / h.sizes[0] / h.sizes[1];
    char value[64];
    std::snprintf(value, sizeof value, "%g", bad_value);
    throw InputError(path, 0,
                     "sample (" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) + ") is " +
                         value + (std::isfinite(bad_value) ? " (beyond float's range)" : "") +
                         "; samples must be finite");
  }
  for (int a = 0; a < 3; ++a) {
    const int na = a == 0 ? v.nx : a == 1 ? v.ny : v.nz;
    if (spacing[a] < 0) {
      flip(v, a);
      origin[a] += (na - 1) * spacing[a];
      spacing[a] = -spacing[a];
    }
  }
  v.spacing = {spacing[0], spacing[1], spacing[2]};
  v.origin = {origin[0], origin[1], origin[2]};
  return v;
}

// ------------------------------------------------------------------ analytic fields

// Coordinates and parameters beyond this are absurd (and their sines are noise).
constexpr double kMaxFieldCoordinate = 1e6;

bool valid_parameters(const FieldSpec& f, std::string& why) {
  auto bad = [&](const std::string& w) {
    why = w;
    return false;
  };
  if (f.n < 2 || f.n > kMaxFieldSize)
    return bad("size " + std::to_string(f.n) + " is out of range (2 .. " + std::to_string(kMaxFieldSize) + ")");
  if (!std::isfinite(f.lo) || !std::isfinite(f.hi) || !(f.lo < f.hi) || !std::isfinite(f.hi - f.lo))
    return bad("bounds must be finite with LO < HI");
  if (std::abs(f.lo) > kMaxFieldCoordinate || std::abs(f.hi) > kMaxFieldCoordinate)
    return bad("bounds must lie within [-1e6, 1e6]");
  if (!std::isfinite(f.a) || !std::isfinite(f.b)) return bad("parameters must be finite");
  if (std::abs(f.a) > kMaxFieldCoordinate || std::abs(f.b) > kMaxFieldCoordinate)
    return bad("parameters must lie within [-1e6, 1e6]");
  switch (f.kind) {
    case FieldKind::kSphere:
      if (!(f.a > 0)) return bad("sphere radius must be > 0");
      break;
    case FieldKind::kTorus:
      if (!(f.a > 0 && f.b > 0)) return bad("torus radii must be > 0");
      break;
    case FieldKind::kGyroid:
      if (!(f.a > 0)) return bad("gyroid periods must be > 0");
      break;
    case FieldKind::kMarschnerLobb:
      if (!(f.a >= 0)) return bad("marschner_lobb alpha must be >= 0");
      if (!(f.b > 0)) return bad("marschner_lobb fm must be > 0");
      break;
  }
  return true;
}

}  // namespace

const char* field_name(FieldKind kind) {
  switch (kind) {
    case FieldKind::kSphere:
      return "sphere";
    case FieldKind::kTorus:
      return "torus";
    case FieldKind::kGyroid:
      return "gyroid";
    case FieldKind::kMarschnerLobb:
      return "marschner_lobb";
  }
  return "?";
}

FieldSpec field_defaults(FieldKind kind) {
  FieldSpec f;
  f.kind = kind;
  switch (kind) {
    case FieldKind::kSphere:
      f.a = 0.5;
      break;
    case FieldKind::kTorus:
      f.a = 0.5, f.b = 0.25;
      break;
    case FieldKind::kGyroid:
      f.a = 2;
      break;
    case FieldKind::kMarschnerLobb:
      f.a = 0.25, f.b = 6;
      break;
  }
  return f;
}

double natural_iso(const FieldSpec& f) {
  switch (f.kind) {
    case FieldKind::kSphere:
      return f.a;
    case FieldKind::kTorus:
      return f.b;
    case FieldKind::kGyroid:
      return 0;
    case FieldKind::kMarschnerLobb:
      return 0.5;
  }
  return 0;
}

double field_value(const FieldSpec& f, const Vec3& p) {
  constexpr double pi = std::numbers::pi;
  switch (f.kind) {
    case FieldKind::kSphere:
      return std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
    case FieldKind::kTorus: {
      const double q = std::sqrt(p.x * p.x + p.y * p.y) - f.a;
      return std::sqrt(q * q + p.z * p.z);
    }
    case FieldKind::kGyroid: {
      const double k = 2 * pi * f.a / (f.hi - f.lo);
      const double x = k * p.x, y = k * p.y, z = k * p.z;
      return std::sin(x) * std::cos(y) + std::sin(y) * std::cos(z) + std::sin(z) * std::cos(x);
    }
    case FieldKind::kMarschnerLobb: {
      const double alpha = f.a, fm = f.b;
      const double r = std::sqrt(p.x * p.x + p.y * p.y);
      const double rho_r = std::cos(2 * pi * fm * std::cos(pi * r / 2));
      return (1 - std::sin(pi * p.z / 2) + alpha * (1 + rho_r)) / (2 * (1 + alpha));
    }
  }
  return 0;
}

Volume sample_field(const FieldSpec& f, std::string source) {
  std::string why;
  if (!valid_parameters(f, why)) throw InputError(source, 0, why);
  Volume v;
  v.nx = v.ny = v.nz = f.n;
  const double step = (f.hi - f.lo) / (f.n - 1);
  v.spacing = {step, step, step};
  v.origin = {f.lo, f.lo, f.lo};
  v.source = std::move(source);
  std::vector<double> coord(size_t(f.n));
  for (int i = 0; i < f.n; ++i) coord[size_t(i)] = i == f.n - 1 ? f.hi : f.lo + (f.hi - f.lo) * i / (f.n - 1);
  v.data.resize(size_t(f.n) * size_t(f.n) * size_t(f.n));
  for (int k = 0; k < f.n; ++k)
    for (int j = 0; j < f.n; ++j)
      for (int i = 0; i < f.n; ++i) {
        const Vec3 p{coord[size_t(i)], coord[size_t(j)], coord[size_t(k)]};
        const float x = float(field_value(f, p));
        if (!std::isfinite(x)) {
          char at[96];
          std::snprintf(at, sizeof at, "(%g, %g, %g)", p.x, p.y, p.z);
          throw InputError(v.source, 0,
                           std::string("the field is not finite at ") + at + " (sample (" + std::to_string(i) + ", " +
                               std::to_string(j) + ", " + std::to_string(k) + "))");
        }
        v.at(i, j, k) = x;
      }
  return v;
}

FieldSpec read_field_spec(const std::string& path) {
  const size_t size = regular_file_size(path, path, 0, "file");
  if (size == 0) throw InputError(path, 0, "file is empty");
  if (size > (size_t(1) << 20)) throw InputError(path, 0, "too large for a .field file (over 1 MiB)");
  const std::string text = read_prefix(path, size);

  struct Entry {
    int line = 0;
    std::vector<double> values;
  };
  int field_line = 0;
  FieldKind kind = FieldKind::kSphere;
  Entry size_e, bounds, radius, radii, periods, alpha, fm;
  const struct {
    const char* key;
    Entry* entry;
    size_t count;
  } keys[] = {{"size", &size_e, 1},     {"bounds", &bounds, 2}, {"radius", &radius, 1}, {"radii", &radii, 2},
              {"periods", &periods, 1}, {"alpha", &alpha, 1},   {"fm", &fm, 1}};

  size_t pos = 0;
  int line_no = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (line.find('\0') != std::string_view::npos)
      throw InputError(path, line_no, "binary data (NUL byte) in a text file");
    const size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    const auto w = words(line);
    if (w.empty()) continue;
    const std::string key(w[0]);
    auto fail = [&](const std::string& what) -> void { throw InputError(path, line_no, what); };
    if (key == "field") {
      if (field_line) fail("a second 'field' line (the first is on line " + std::to_string(field_line) + ")");
      if (w.size() != 2) fail("'field' takes one name: sphere, torus, gyroid or marschner_lobb");
      if (w[1] == "sphere")
        kind = FieldKind::kSphere;
      else if (w[1] == "torus")
        kind = FieldKind::kTorus;
      else if (w[1] == "gyroid")
        kind = FieldKind::kGyroid;
      else if (w[1] == "marschner_lobb")
        kind = FieldKind::kMarschnerLobb;
      else
        fail("unknown field " + quoted(w[1]) + " (sphere, torus, gyroid or marschner_lobb)");
      field_line = line_no;
      continue;
    }
    const auto* k = std::find_if(std::begin(keys), std::end(keys), [&](const auto& e) { return key == e.key; });
    if (k == std::end(keys))
      fail("unknown key " + quoted(key) + " (field, size, bounds, radius, radii, periods, alpha, fm)");
    if (k->entry->line)
      fail("a second '" + key + "' line (the first is on line " + std::to_string(k->entry->line) + ")");
    if (w.size() != k->count + 1)
      fail("'" + key + "' takes " + std::to_string(k->count) + " value(s), got " + std::to_string(w.size() - 1));
    k->entry->line = line_no;
    for (size_t i = 1; i < w.size(); ++i) {
      const std::string s(w[i]);
      char* e = nullptr;
      const double x = std::strtod(s.c_str(), &e);
      if (e == s.c_str() || *e != '\0') fail("not a number: " + quoted(s));
      if (!std::isfinite(x)) fail("number out of range (NaN, Inf or overflow): " + quoted(s));
      k->entry->values.push_back(x);
    }
  }
  if (!field_line) throw InputError(path, 0, "no 'field' line (field sphere|torus|gyroid|marschner_lobb)");

  FieldSpec f = field_defaults(kind);
  auto fail_at = [&](int line, const std::string& what) { throw InputError(path, line, what); };
  // Keys of another kind.
  const struct {
    Entry* entry;
    const char* key;
    FieldKind kind;
  } own[] = {{&radius, "radius", FieldKind::kSphere},
             {&radii, "radii", FieldKind::kTorus},
             {&periods, "periods", FieldKind::kGyroid},
             {&alpha, "alpha", FieldKind::kMarschnerLobb},
             {&fm, "fm", FieldKind::kMarschnerLobb}};
  for (const auto& o : own)
    if (o.entry->line && o.kind != kind)
      fail_at(o.entry->line,
              std::string("'") + o.key + "' is for " + field_name(o.kind) + " fields, not " + field_name(kind));
  if (size_e.line) {
    const double n = size_e.values[0];
    if (!(n == std::floor(n)) || n < 2 || n > kMaxFieldSize) {
      char b[32];
      std::snprintf(b, sizeof b, "%g", n);
      fail_at(size_e.line,
              std::string("size ") + b + " is out of range (an integer, 2 .. " + std::to_string(kMaxFieldSize) + ")");
    }
    f.n = int(n);
  }
  if (bounds.line) {
    f.lo = bounds.values[0];
    f.hi = bounds.values[1];
    if (!(f.lo < f.hi) || !std::isfinite(f.hi - f.lo)) fail_at(bounds.line, "bounds: LO must be less than HI");
    if (std::abs(f.lo) > kMaxFieldCoordinate || std::abs(f.hi) > kMaxFieldCoordinate)
      fail_at(bounds.line, "bounds must lie within [-1e6, 1e6]");
  }
  if (radius.line) f.a = radius.values[0];
  if (radii.line) f.a = radii.values[0], f.b = radii.values[1];
  if (periods.line) f.a = periods.values[0];
  if (alpha.line) f.a = alpha.values[0];
  if (fm.line) f.b = fm.values[0];
  std::string why;
  if (!valid_parameters(f, why)) {
    const int line = std::max({radius.line, radii.line, periods.line, alpha.line, fm.line});
    fail_at(line, why);
  }
  return f;
}

// ------------------------------------------------------------------ dispatch

Volume read_volume(const std::string& path) {
  const std::string ext = extension_of(path);
  if (ext == ".field") return sample_field(read_field_spec(path), path);
  if (ext == ".nrrd" || ext == ".nhdr") return read_nrrd(path);
  throw InputError(path, 0, "not a volume: the extension must be .nrrd, .nhdr or .field");
}

}  // namespace lockstep
