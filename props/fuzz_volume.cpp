// lockstep props: fuzzing the volume reader (io/volume_io.h).
//
// Property: read_volume either returns a valid Volume (every axis >= 2 samples,
// nx*ny*nz finite samples, finite positive spacing, finite origin) or throws
// lockstep::InputError -- never another exception, never a crash, never a
// hang (built under AddressSanitizer + UBSan by scripts/fuzz.sh: any memory
// error, leak or undefined behaviour aborts the run, in our code or in Teem's).
//
// Inputs, written to a temporary directory and read by path as a user's file
// would be: valid NRRD files made here (attached and detached, raw, gzip,
// ascii and hex, 1-, 2-, 4- and 8-byte types in both byte orders, spacings,
// space directions and origins) and .field files, mutated by byte flips,
// insertions, deletions, duplications, truncation, dropped and duplicated
// lines, numbers swapped for huge, negative or malformed ones, and header
// lines from NRRD's vocabulary (7 dimensions, block types, bzip2, data file
// lists and sequences, byte skips, 9-D spaces, ...). A detached header's data
// file is a real file beside it (raw or gzip), so mutated headers reach Teem's
// data readers too.
//
// A .field file asking for more than 64^3 samples is checked by read_field_spec
// only (sampling 1024^3 would take seconds).
//
// Cases: 50x every property's count (each case writes and reads a file: 5000
// cases take under 2 s, a few seconds under the sanitizers); LOCKSTEP_DEEP=1
// makes that 50000. Seeds fixed per property, as every property binary's
// (props/driver/rc_run.h); scripts/fuzz.sh draws random ones.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <unistd.h>
#include <zlib.h>

#include <bit>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/transfer_function_io.h"
#include "io/texture_scene.h"
#include "io/volume_io.h"
#include "props/driver/rc_run.h"

namespace {

namespace fs = std::filesystem;
using lockstep::InputError;
using lockstep::Volume;

// ------------------------------------------------------------------ the files

std::string escaped(const std::string& s, size_t max = 2000) {
  std::string out;
  for (size_t i = 0; i < s.size() && i < max; ++i) {
    const unsigned char ch = static_cast<unsigned char>(s[i]);
    if (ch == '\n')
      out += "\\n\n";
    else if (ch == '\\')
      out += "\\\\";
    else if (ch >= 32 && ch < 127)
      out += char(ch);
    else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", ch);
      out += buf;
    }
  }
  if (s.size() > max) out += "... (" + std::to_string(s.size()) + " bytes)";
  return out;
}

std::string gzip(const std::string& raw) {
  z_stream z{};
  deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY);
  std::string out(deflateBound(&z, uLong(raw.size())) + 64, '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(raw.data()));
  z.avail_in = uInt(raw.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = uInt(out.size());
  deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

template <class T>
std::string bytes_of(size_t n, bool big, double scale) {
  std::string out;
  for (size_t i = 0; i < n; ++i) {
    const T v = T(double(i % 97) * scale);
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big == (std::endian::native == std::endian::little)) std::reverse(b, b + sizeof(T));
    out.append(b, sizeof(T));
  }
  return out;
}

struct Seed {
  std::string name;  // file name (the extension picks the reader)
  std::string bytes;
};

// The temporary directory: the detached seeds' data files live here, and each case's file.
const fs::path& dir() {
  static const fs::path d = [] {
    fs::path p = fs::temp_directory_path() / ("lockstep-fuzz-volume-" + std::to_string(::getpid()));
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
  }();
  return d;
}

void write_file(const fs::path& p, const std::string& bytes) {
  // Removed first: ext4 flushes a file truncated and rewritten in place (auto_da_alloc), 3 ms a case.
  std::error_code ec;
  fs::remove(p, ec);
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

std::vector<Seed> make_seeds() {
  std::vector<Seed> s;
  const std::string u8 = bytes_of<uint8_t>(4 * 3 * 5, false, 2.5);
  // Attached files of each type, encoding and byte order.
  const char* head = "NRRD0004\n# a comment\n";
  s.push_back({"u8.nrrd", std::string(head) +
                              "type: uchar\ndimension: 3\nsizes: 4 3 5\nspacings: 1 2 0.5\n"
                              "encoding: raw\n\n" +
                              u8});
  s.push_back({"u16be.nrrd", std::string(head) +
                                 "type: ushort\ndimension: 3\nsizes: 4 3 5\nencoding: raw\n"
                                 "endian: big\n\n" +
                                 bytes_of<uint16_t>(60, true, 677.5)});
  s.push_back({"s16le.nrrd", std::string(head) +
                                 "type: short\ndimension: 3\nsizes: 4 3 5\nencoding: raw\n"
                                 "endian: little\nspace: RAS\nspace directions: (1,0,0) (0,1,0) (0,0,-2)\n"
                                 "space origin: (-1,2,3.5)\n\n" +
                                 bytes_of<int16_t>(60, false, -300)});
  s.push_back({"f32.nrrd", std::string(head) +
                               "type: float\ndimension: 3\nsizes: 4 3 5\nencoding: gzip\n"
                               "endian: little\nkinds: space space space\ncenters: cell cell cell\n"
                               "key:=value\n\n" +
                               gzip(bytes_of<float>(60, false, 0.125))});
  s.push_back({"f64.nrrd", std::string(head) +
                               "type: double\ndimension: 3\nsizes: 2 2 2\nencoding: hex\n"
                               "endian: big\naxis mins: 0 0 0\n\n" +
                               [] {
                                 std::string h;
                                 for (unsigned char c : bytes_of<double>(8, true, 1.5)) {
                                   char b[4];
                                   std::snprintf(b, sizeof b, "%02x", c);
                                   h += b;
                                 }
                                 return h + "\n";
                               }()});
  s.push_back({"i32.nrrd", std::string(head) + "type: int\ndimension: 3\nsizes: 3 2 2\nencoding: ascii\n\n"
                                               "1 -2 3\n4 5 -6\n7 8 9\n10 11 -12\n"});
  s.push_back({"c8.nrrd",
               "NRRD0005\ntype: signed char\ndimension: 3\nsizes: 2 2 2\nbyte skip: 3\nencoding: raw\n"
               "content: x\nmin: 0\nmax: 9\n\nabc" +
                   bytes_of<int8_t>(8, false, -1)});
  // Detached headers, their data beside them.
  write_file(dir() / "data.raw", bytes_of<uint16_t>(4 * 3 * 5, false, 500));
  write_file(dir() / "data.raw.gz", gzip(bytes_of<uint32_t>(4 * 3 * 5, true, 100000)));
  s.push_back({"d16.nhdr", std::string(head) + "type: ushort\ndimension: 3\nsizes: 4 3 5\nencoding: raw\n"
                                               "endian: little\nspacings: 1 1 2\ndata file: data.raw\n"});
  s.push_back({"d32.nhdr", std::string(head) + "type: uint\ndimension: 3\nsizes: 4 3 5\nencoding: gzip\n"
                                               "endian: big\nspace dimension: 3\nspace directions: (0.5,0,0) "
                                               "(0,0.5,0) (0,0,0.5)\ndata file: ./data.raw.gz\nline skip: 0\n"});
  // Fields.
  s.push_back({"s.field", "# sphere\nfield sphere\nsize 8\nbounds -1 1\nradius 0.5\n"});
  s.push_back({"t.field", "field torus\nsize 7\nradii 0.5 0.25\n"});
  s.push_back({"g.field", "field gyroid\nperiods 2\nsize 6\n"});
  s.push_back({"m.field", "field marschner_lobb\nsize 9\nalpha 0.25\nfm 6\nbounds -1 1\n"});
  return s;
}

// ------------------------------------------------------------------ mutations

const std::vector<std::string> kNumbers = {"0",
                                           "1",
                                           "-1",
                                           "2",
                                           "3",
                                           "7",
                                           "16",
                                           "17",
                                           "-0",
                                           "0.5",
                                           "nan",
                                           "inf",
                                           "-inf",
                                           "1e308",
                                           "1e999",
                                           "-1e400",
                                           "2147483648",
                                           "4294967296",
                                           "18446744073709551615",
                                           "18446744073709551616",
                                           "99999999999999999999999",
                                           "65536",
                                           "1024",
                                           "1025",
                                           "5000",
                                           "0x10",
                                           "1e",
                                           "--1",
                                           "+1",
                                           ".",
                                           "",
                                           "1,2",
                                           "(1,0,0)",
                                           "(nan,0,0)",
                                           "none",
                                           "-2",
                                           "-3",
                                           "100000"};
const std::vector<std::string> kLines = {"dimension: 7",
                                         "dimension: 3",
                                         "dimension: 4",
                                         "dimension: 17",
                                         "dimension: -1",
                                         "sizes: 1 2 3 4 5 6 7",
                                         "sizes: 4294967296 4294967296 4294967296",
                                         "sizes: 2 2 2",
                                         "sizes: 100000 100000 100000",
                                         "type: block",
                                         "block size: 1000000000",
                                         "type: int64",
                                         "type: quaternion",
                                         "type: float",
                                         "type: double",
                                         "encoding: bzip2",
                                         "encoding: zrl",
                                         "encoding: lzma",
                                         "encoding: raw",
                                         "encoding: gzip",
                                         "encoding: ascii",
                                         "encoding: hex",
                                         "endian: big",
                                         "endian: middle",
                                         "data file: LIST",
                                         "data file: x%d.raw 1 3 1",
                                         "data file: data.raw",
                                         "data file: data.raw.gz",
                                         "data file: /dev/zero",
                                         "data file: .",
                                         "data file: /nonexistent/x",
                                         "data file: ../",
                                         "byte skip: -1",
                                         "byte skip: -2",
                                         "byte skip: 99999999999",
                                         "byte skip: 4",
                                         "line skip: 3",
                                         "line skip: 99999999",
                                         "space dimension: 9",
                                         "space dimension: 3",
                                         "space dimension: 0",
                                         "space: RAS",
                                         "space: 3D-right-handed-time",
                                         "space: nowhere",
                                         "space directions: (1,0,0) (0,1,0) (0,0,1)",
                                         "space directions: (1,0) (0,1) (1,1)",
                                         "space directions: none (0,1,0) (0,0,1)",
                                         "space directions: (nan,0,0) (0,1,0) (0,0,1)",
                                         "space directions: (1e308,0,0) (0,1e308,0) (0,0,1e-320)",
                                         "space origin: (1,2,3)",
                                         "space origin: (nan,nan,nan)",
                                         "space origin: (1,2)",
                                         "space units: \"mm\" \"mm\"",
                                         "measurement frame: (1,0,0) (0,1,0) (0,0,1)",
                                         "measurement frame: (1,0) (0,1)",
                                         "kinds: space space",
                                         "kinds: RGB-color 3-vector space",
                                         "centers: cell node ???",
                                         "spacings: 1 nan 2",
                                         "spacings: 0 0 0",
                                         "spacings: -1 -2 -3",
                                         "spacings: 1e308 1e308 1e308",
                                         "thicknesses: 1 1 1",
                                         "axis mins: 0 0 0",
                                         "axis maxs: nan 1",
                                         "labels: \"x\" \"y\" \"z\"",
                                         "units: \"mm\" \"\" \"",
                                         "old min: 3",
                                         "number: 5",
                                         "content: \x01\x02",
                                         "sample units: \"HU\"",
                                         "key:=value",
                                         "a:=b:=c",
                                         ": : :",
                                         "#",
                                         "",
                                         "NRRD0004",
                                         "field sphere",
                                         "field torus",
                                         "field gyroid",
                                         "field marschner_lobb",
                                         "field cube",
                                         "size 2",
                                         "size 1024",
                                         "size 0",
                                         "bounds 1 -1",
                                         "bounds -1e308 1e308",
                                         "radius 0",
                                         "radii 1 2",
                                         "periods 1e300",
                                         "alpha -1",
                                         "fm 0",
                                         "fm 1e308",
                                         "colour red"};

// A string of `n` random bytes.
std::string random_bytes(int n) {
  std::string s;
  for (int i = 0; i < n; ++i) s += char(*rc::gen::arbitrary<unsigned char>());
  return s;
}

std::string mutate(std::string s) {
  int n = 1;
  while (n < 6 && *rc::gen::inRange(0, 3) == 0) ++n;
  for (int k = 0; k < n; ++k) {
    const size_t len = s.size();
    // Mostly edits within the header (the first 400 bytes), where the checks are.
    const size_t span = std::min<size_t>(len, *rc::gen::arbitrary<bool>() ? 400 : len);
    const size_t at = span ? size_t(*rc::gen::inRange<size_t>(0, span)) : 0;
    auto line_bounds = [&](size_t p, size_t& b, size_t& e) {
      b = s.rfind('\n', p ? p - 1 : 0);
      b = (b == std::string::npos || p == 0) ? 0 : b + 1;
      e = s.find('\n', p);
      e = e == std::string::npos ? s.size() : e + 1;
    };
    switch (*rc::gen::inRange(0, 11)) {
      case 0:  // flip a bit
        if (len) s[at] = char(s[at] ^ char(1 << *rc::gen::inRange(0, 8)));
        break;
      case 1:  // insert random bytes
        s.insert(at, random_bytes(*rc::gen::inRange(1, 4)));
        break;
      case 2:  // delete a range
        s.erase(at, size_t(*rc::gen::inRange(1, 40)));
        break;
      case 3:  // duplicate a range
        s.insert(at, s.substr(at, size_t(*rc::gen::inRange(1, 120))));
        break;
      case 4:
      case 5: {  // replace the number or word at `at`
        size_t b = at, e = at;
        auto word = [](char c) { return !std::isspace(static_cast<unsigned char>(c)) && c != ':' && c != ','; };
        while (b > 0 && b <= len && word(s[b - 1])) --b;
        while (e < len && word(s[e])) ++e;
        s.replace(b, e - b, *rc::gen::elementOf(kNumbers));
        break;
      }
      case 6: {  // drop a line
        size_t b, e;
        line_bounds(at, b, e);
        s.erase(b, e - b);
        break;
      }
      case 7: {  // duplicate a line
        size_t b, e;
        line_bounds(at, b, e);
        s.insert(e, s.substr(b, e - b));
        break;
      }
      case 8: {  // insert a line from the vocabulary
        size_t b, e;
        line_bounds(at, b, e);
        s.insert(b, *rc::gen::elementOf(kLines) + "\n");
        break;
      }
      case 9:  // truncate
        s.resize(at);
        break;
      default: {  // replace a line with one from the vocabulary
        size_t b, e;
        line_bounds(at, b, e);
        s.replace(b, e - b, *rc::gen::elementOf(kLines) + "\n");
        break;
      }
    }
  }
  return s;
}

// ------------------------------------------------------------------ the property

std::string invalid(const Volume& v) {
  if (v.nx < 2 || v.ny < 2 || v.nz < 2) return "an axis with fewer than 2 samples";
  if (v.data.size() != size_t(v.nx) * size_t(v.ny) * size_t(v.nz)) return "data size";
  for (size_t i = 0; i < v.data.size(); ++i)
    if (!std::isfinite(v.data[i])) return "sample " + std::to_string(i) + " not finite";
  for (double s : {v.spacing.x, v.spacing.y, v.spacing.z})
    if (!(s > 0 && std::isfinite(s))) return "spacing";
  for (double o : {v.origin.x, v.origin.y, v.origin.z})
    if (!std::isfinite(o)) return "origin";
  return "";
}

void read_ok(const Seed& seed, const std::string& bytes) {
  const fs::path p = dir() / ("case-" + seed.name);
  write_file(p, bytes);
  try {
    if (p.extension() == ".field") {
      // A valid .field may ask for up to 1024^3 samples (seconds to compute):
      // sample only the small ones; the spec must be valid either way.
      const lockstep::FieldSpec f = lockstep::read_field_spec(p.string());
      if (!(f.n >= 2 && f.n <= lockstep::kMaxFieldSize && std::isfinite(f.lo) && std::isfinite(f.hi) && f.lo < f.hi &&
            std::isfinite(f.a) && std::isfinite(f.b)))
        RC_FAIL("read_field_spec returned an invalid spec for:\n" + escaped(bytes));
      if (f.n > 64) {
        RC_TAG("field too large to sample here");
        return;
      }
    }
    const Volume v = lockstep::read_volume(p.string());
    const std::string bad = invalid(v);
    if (!bad.empty())
      RC_FAIL("read_volume returned an invalid volume (" + bad + ") for " + seed.name + ":\n" + escaped(bytes));
    RC_TAG("read");
  } catch (const InputError& e) {
    if (std::string(e.what()).find(p.string()) != 0)
      RC_FAIL(std::string("InputError does not start with the file name: ") + e.what());
    if (std::string(e.what()).find('\n') != std::string::npos)
      RC_FAIL(std::string("InputError message of several lines: ") + e.what());
    RC_TAG("InputError");
  } catch (const std::exception& e) {
    RC_FAIL(std::string("read_volume threw ") + typeid(e).name() + " (" + e.what() + ") instead of InputError for " +
            seed.name + ":\n" + escaped(bytes));
  }
}

using lockstep::props::rc_run::fuzz;  // 50 times the usual case count (props/driver/rc_run.h)

const std::vector<Seed>& seeds() {
  static const std::vector<Seed> s = make_seeds();
  return s;
}

TEST(FuzzVolume, SeedsRead) {  // the unmutated seeds are valid volumes
  testing::internal::CaptureStderr();
  for (const Seed& s : seeds()) {
    const fs::path p = dir() / s.name;
    write_file(p, s.bytes);
    try {
      const Volume v = lockstep::read_volume(p.string());
      EXPECT_EQ(invalid(v), "") << s.name;
    } catch (const std::exception& e) {
      ADD_FAILURE() << s.name << ": " << e.what() << "\n" << escaped(s.bytes);
    }
  }
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "") << "reading printed on stderr";
}

TEST(FuzzVolume, MutatedFiles) {
  testing::internal::CaptureStderr();
  fuzz("fuzz_volume.mutated", [] {
    const Seed seed = *rc::gen::elementOf(seeds());
    // The generator keeps its own copy: RapidCheck runs it again while shrinking.
    read_ok(seed, *rc::gen::resize(rc::kNominalSize, rc::gen::exec([base = seed.bytes] { return mutate(base); })));
  });
  std::string err = testing::internal::GetCapturedStderr();
  if (err.starts_with("Using configuration:")) err.erase(0, err.find('\n') + 1);  // RapidCheck's own line
  EXPECT_EQ(err.substr(0, 2000), "") << "reading printed on stderr";
}

TEST(FuzzVolume, RandomBytes) {
  fuzz("fuzz_volume.random_bytes", [] {
    static const std::vector<Seed> kinds = {{"r.nrrd", ""}, {"r.nhdr", ""}, {"r.field", ""}};
    const Seed kind = *rc::gen::elementOf(kinds);
    // Random bytes after a NRRD magic (or none), so that the header scanner sees them.
    std::string bytes = *rc::gen::elementOf(std::vector<std::string>{"", "NRRD0004\n", "NRRD0001\n", "field "});
    bytes += random_bytes(*rc::gen::inRange(0, 300));
    read_ok(kind, bytes);
  });
}

// Transfer functions (core/transfer_function.h): the corpus' .tf files and
// every file of tests/bad-tf, mutated, parsed: a valid function (at least one
// point, values strictly increasing and finite, colours and alpha in [0, 1],
// eval finite everywhere) or an InputError.
TEST(FuzzVolume, TransferFunctions) {
  std::vector<std::string> bases;
  for (const char* d : {LOCKSTEP_CORPUS_DIR "/tf", LOCKSTEP_BAD_TF_DIR})
    for (const auto& e : fs::directory_iterator(d))
      if (e.path().extension() == ".tf") {
        std::ifstream f(e.path(), std::ios::binary);
        std::ostringstream t;
        t << f.rdbuf();
        bases.push_back(t.str());
      }
  ASSERT_GE(bases.size(), 10u);
  fuzz("fuzz_volume.transfer_functions", [&bases] {
    const std::string base = *rc::gen::elementOf(bases);
    const std::string text = *rc::gen::resize(rc::kNominalSize, rc::gen::exec([base] { return mutate(base); }));
    try {
      const lockstep::TransferFunction tf = lockstep::parse_transfer_function(text, "fuzz.tf");
      RC_ASSERT(!tf.points.empty());
      for (size_t i = 0; i < tf.points.size(); ++i) {
        const auto& q = tf.points[i];
        RC_ASSERT(std::isfinite(q.value));
        if (i) RC_ASSERT(q.value > tf.points[i - 1].value);
        for (float c : {q.r, q.g, q.b, q.a}) RC_ASSERT(c >= 0.0f && c <= 1.0f);
        double out[4];
        tf.eval(q.value * 0.5 + 1, out);
        for (double c : out) RC_ASSERT(std::isfinite(c) && c >= 0 && c <= 1);
      }
    } catch (const lockstep::InputError& e) {
      RC_ASSERT(std::string(e.what()).starts_with("fuzz.tf"));
    }
  });
}

// Texture scenes (io/texture_scene.h; issue #32): the corpus' .texscene files
// and every file of tests/bad-texscenes, mutated, parsed (texture files
// relative to corpus/textures): a scene with a texture of 1 to kMaxTexels
// texels, all finite, a quad with area, positive repeats, a view whose up is
// not along it; or an InputError naming the scene.
TEST(FuzzTexscene, MutatedScenes) {
  std::vector<std::string> bases;
  for (const char* d : {LOCKSTEP_CORPUS_DIR "/textures", LOCKSTEP_BAD_TF_DIR "/../bad-texscenes"})
    for (const auto& e : fs::directory_iterator(d))
      if (e.path().extension() == ".texscene") {
        std::ifstream f(e.path(), std::ios::binary);
        std::ostringstream t;
        t << f.rdbuf();
        bases.push_back(t.str());
      }
  ASSERT_GE(bases.size(), 15u);
  fuzz("fuzz_texscene.mutated", [&bases] {
    const std::string base = *rc::gen::elementOf(bases);
    const std::string text = *rc::gen::resize(rc::kNominalSize, rc::gen::exec([base] { return mutate(base); }));
    try {
      const lockstep::TextureScene sc =
          lockstep::parse_texture_scene(text, "fuzz.texscene", LOCKSTEP_CORPUS_DIR "/textures");
      const lockstep::Texture& t = sc.texture;
      RC_ASSERT(t.width >= 1 && t.height >= 1 && long(t.width) * t.height <= lockstep::kMaxTexels);
      RC_ASSERT(t.rgba.size() == size_t(t.width) * size_t(t.height) * 4);
      for (float v : t.rgba) RC_ASSERT(std::isfinite(v));
      RC_ASSERT(lockstep::length(lockstep::cross(sc.edge_s, sc.edge_t)) > 0);
      RC_ASSERT(sc.repeat_u > 0 && sc.repeat_v > 0);
      RC_ASSERT(sc.width >= 1 && sc.height >= 1);
      RC_ASSERT(sc.view.angle > 0 && sc.view.angle < 180);
    } catch (const lockstep::InputError& e) {
      RC_ASSERT(std::string(e.what()).starts_with("fuzz.texscene"));
    }
  });
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  const int rc = RUN_ALL_TESTS();
  std::error_code ec;
  fs::remove_all(dir(), ec);
  return rc;
}
