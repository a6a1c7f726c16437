// lockstep io: NRRD volumes, the header scanned by us, the data read by Teem
// (io/volume_io.h says what is read and what is refused).
#include <zlib.h>

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
#include "io/text.h"
#include "io/tokenizer.h"
#include "io/volume_io.h"

namespace lockstep {

namespace {

using namespace text;

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
  bool big_endian = false;
  std::string data_name;  // the file the data is in (the header's own when attached)
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

// Reads and checks the header of the NRRD file at path (io/volume_io.h lists the checks).
NrrdHeader scan_nrrd_header(const std::string& path) {
  const size_t file_size = regular_file_size(path, path, 0, "file");
  if (file_size == 0) throw InputError(path, 0, "file is empty");
  const std::string text = read_prefix(path, std::min(file_size, kMaxHeaderBytes));

  NrrdHeader h;
  // The lines, '\n'-terminated ('\r' before it dropped), up to the first empty line
  // (the data may follow it: each line is looked at only when reached).
  // NUL bytes are looked for below, after the checks for the header's end.
  Tokenizer in(text, path, {.comments = Comments::none, .nul = nullptr});
  while (in.next_line()) {
    const int line_no = in.line_no();
    const std::string_view line = in.line();
    if (!in.terminated() && text.size() == kMaxHeaderBytes && file_size > kMaxHeaderBytes)
      in.fail("header longer than 1 MiB (no blank line ends it)");
    if (line.empty()) {
      h.header_ends = true;
      h.data_offset = in.offset();
      break;
    }
    if (line.find('\0') != std::string_view::npos) in.fail("NUL byte in the NRRD header");
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
        h.big_endian = airEnumVal(airEndian, v.c_str()) == airEndianBig;
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
  h.data_name = data_name;
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

// n samples of type T at data as float at out; bad = the first that is not
// finite or beyond float's range (n when none).
template <class T>
void convert_as(const void* data, size_t n, float* out, size_t& bad) {
  const T* p = static_cast<const T*>(data);
  for (size_t i = 0; i < n; ++i) {
    const double v = double(p[i]);
    if (!std::isfinite(v) || std::abs(v) > double(FLT_MAX)) {
      bad = i;
      return;
    }
    out[i] = float(p[i]);
  }
  bad = n;
}

void convert(int type, const void* data, size_t n, float* out, size_t& bad) {
  switch (type) {
    case nrrdTypeChar:
      return convert_as<signed char>(data, n, out, bad);
    case nrrdTypeUChar:
      return convert_as<unsigned char>(data, n, out, bad);
    case nrrdTypeShort:
      return convert_as<int16_t>(data, n, out, bad);
    case nrrdTypeUShort:
      return convert_as<uint16_t>(data, n, out, bad);
    case nrrdTypeInt:
      return convert_as<int32_t>(data, n, out, bad);
    case nrrdTypeUInt:
      return convert_as<uint32_t>(data, n, out, bad);
    case nrrdTypeFloat:
      return convert_as<float>(data, n, out, bad);
    default:
      return convert_as<double>(data, n, out, bad);
  }
}

// Reverses the bytes of each of n samples of `size` bytes.
void swap_bytes(unsigned char* p, size_t n, size_t size) {
  for (size_t i = 0; i < n; ++i, p += size) std::reverse(p, p + size);
}

// Raw samples read straight into the volume's buffer (issue #35: Teem would
// zero a buffer of its own, read into it and leave us to copy: the file's size
// of fresh pages touched twice). Float samples land where they stay; other
// types go through a 1 MiB buffer. Sets bad (the first bad sample, or n) and
// bad_value; throws InputError when the file ends early.
void read_raw(const NrrdHeader& h, const std::string& path, Samples& out, size_t& bad, double& bad_value) {
  const size_t n = out.size(), size = type_size(h.type);
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(h.data_name.c_str(), "rb"), &std::fclose);
  const long offset = long(h.data_file.empty() ? h.data_offset : 0) + h.byte_skip;
  if (!f || std::fseek(f.get(), offset, SEEK_SET) != 0)
    throw InputError(path, 0, "cannot read the data of " + h.data_name + ": " + std::strerror(errno));
  auto fail_short = [&] { throw InputError(path, 0, "the data ends early (read error or file changed)"); };
  if (h.type == nrrdTypeFloat) {
    if (std::fread(out.data(), size, n, f.get()) != n) fail_short();
    if (h.big_endian) swap_bytes(reinterpret_cast<unsigned char*>(out.data()), n, size);
    convert(h.type, out.data(), n, out.data(), bad);
    if (bad < n) bad_value = out[bad];
    return;
  }
  std::vector<unsigned char> buf(size_t(1) << 20);
  const size_t per = buf.size() / size;
  for (size_t at = 0; at < n; at += per) {
    const size_t m = std::min(per, n - at);
    if (std::fread(buf.data(), size, m, f.get()) != m) fail_short();
    if (h.big_endian && size > 1) swap_bytes(buf.data(), m, size);
    size_t b = m;
    convert(h.type, buf.data(), m, out.data() + at, b);
    if (b < m) {
      bad = at + b;
      bad_value = nrrdDLookup[h.type](buf.data(), b);
      return;
    }
  }
  bad = n;
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

}  // namespace

Volume read_nrrd(const std::string& path) { return read_nrrd(path, NrrdData::kDirect); }

Volume read_nrrd(const std::string& path, NrrdData how) {
  const NrrdHeader h = scan_nrrd_header(path);
  // Raw data at a known offset (no line skip, no byte skip -1) is read
  // straight into the volume (read_raw); Teem reads the header only.
  const bool direct = how == NrrdData::kDirect && h.encoding == nrrdEncodingTypeRaw && h.line_skip == 0 &&
                      h.byte_skip >= 0;
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
    nio->skipData = direct ? AIR_TRUE : AIR_FALSE;
    if (nrrdLoad(nrrd.get(), path.c_str(), nio.get())) {
      const auto [line, message] = teem_error(h);
      throw InputError(path, line, message);
    }
    const Nrrd* r = nrrd.get();
    if (r->dim != 3 || r->type != h.type || r->axis[0].size != h.sizes[0] || r->axis[1].size != h.sizes[1] ||
        r->axis[2].size != h.sizes[2] || (!direct && !r->data))
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
    v.data.resize(n);  // every sample written below, or an error thrown
    if (direct) {
      read_raw(h, path, v.data, bad, bad_value);
    } else {
      convert(r->type, r->data, n, v.data.data(), bad);
      if (bad < n) bad_value = nrrdDLookup[r->type](r->data, bad);
    }
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

}  // namespace lockstep
