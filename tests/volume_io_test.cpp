// Tests of the volume reader (io/volume_io.h).
//
//   * real data: every header in ../shared/volumes reads with the dimensions,
//     types and value ranges of its README (min/max from `teem-unu minmax`),
//     and a few voxels equal what `teem-unu slice ... | teem-unu save -f text`
//     prints (the big-endian 16-bit CT head among them);
//   * hand-written NRRD files (bytes chosen here): attached and detached, raw,
//     gzip (zlib), ascii and hex, each type, both endiannesses, spacings, space
//     directions and origins, a negative direction; read back to exact values;
//   * analytic fields: values at points where they are known in closed form,
//     and sample_field's grid positions; .field files;
//   * bad input: every file in tests/bad-volumes throws one InputError whose
//     message, after the file name, matches the file's '# expect:' line, and
//     nothing is printed on stderr.
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/volume_io.h"
#include "registry/loaders.h"

namespace lockstep {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- helpers

// A fresh directory for this test's files, removed at the end.
class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() /
            ("lockstep-volume-io-" + std::to_string(::getpid()) + "-" + std::to_string(counter_++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  static inline int counter_ = 0;
  fs::path path_;
};

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  ASSERT_TRUE(out.good()) << path;
}

// The bytes of values of type T in the given byte order.
template <class T>
std::string bytes_of(const std::vector<T>& values, bool big_endian) {
  std::string out;
  for (T v : values) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big_endian == (std::endian::native == std::endian::little)) std::reverse(b, b + sizeof(T));
    out.append(b, sizeof(T));
  }
  return out;
}

// gzip (RFC 1952) of the bytes, with zlib.
std::string gzip(const std::string& raw) {
  z_stream z{};
  EXPECT_EQ(deflateInit2(&z, 9, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY), Z_OK);
  std::string out(deflateBound(&z, uLong(raw.size())) + 64, '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(raw.data()));
  z.avail_in = uInt(raw.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = uInt(out.size());
  EXPECT_EQ(deflate(&z, Z_FINISH), Z_STREAM_END);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

std::string sizes_line(int nx, int ny, int nz) {
  return "sizes: " + std::to_string(nx) + " " + std::to_string(ny) + " " + std::to_string(nz) + "\n";
}

// Every sample of v equals expected[i] exactly.
void expect_samples(const Volume& v, const std::vector<double>& expected, const std::string& what) {
  ASSERT_EQ(v.data.size(), expected.size()) << what;
  for (size_t i = 0; i < expected.size(); ++i)
    ASSERT_EQ(v.data[i], float(expected[i]))
        << what << ": sample " << i << " is " << v.data[i] << ", expected " << expected[i];
}

Volume read_quietly(const std::string& path) {
  testing::internal::CaptureStderr();
  try {
    Volume v = read_volume(path);
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(err, "") << "reading " << path << " printed on stderr";
    return v;
  } catch (...) {
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(err, "") << "reading " << path << " printed on stderr";
    throw;
  }
}

// The InputError message of reading path ("" and a test failure when it reads).
std::string error_of(const std::string& path) {
  try {
    const Volume v = read_quietly(path);
    ADD_FAILURE() << path << " read as a " << v.nx << "x" << v.ny << "x" << v.nz << " volume; expected an InputError";
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << path << ": " << typeid(e).name() << " (" << e.what() << ") instead of InputError";
  }
  return "";
}

// read_nrrd's direct raw read (NrrdData::kDirect) against Teem reading the
// whole file (kTeem): the same volume, sample for sample and bit for bit, or
// the same InputError.
void expect_direct_is_teems(const std::string& path) {
  std::string direct_error, teem_error;
  Volume a, b;
  try {
    a = read_nrrd(path, NrrdData::kDirect);
  } catch (const InputError& e) {
    direct_error = e.what();
  }
  try {
    b = read_nrrd(path, NrrdData::kTeem);
  } catch (const InputError& e) {
    teem_error = e.what();
  }
  ASSERT_EQ(direct_error, teem_error) << path;
  EXPECT_EQ(a.nx, b.nx) << path;
  EXPECT_EQ(a.ny, b.ny) << path;
  EXPECT_EQ(a.nz, b.nz) << path;
  EXPECT_EQ(a.spacing, b.spacing) << path;
  EXPECT_EQ(a.origin, b.origin) << path;
  ASSERT_EQ(a.data.size(), b.data.size()) << path;
  for (size_t i = 0; i < a.data.size(); ++i)
    ASSERT_EQ(std::bit_cast<uint32_t>(a.data[i]), std::bit_cast<uint32_t>(b.data[i]))
        << path << ": sample " << i << ": direct " << a.data[i] << ", Teem " << b.data[i];
}

// ---------------------------------------------------------------- real volumes (../shared/volumes)

struct RealVolume {
  const char* header;
  int nx, ny, nz;
  float min, max;
  double sz;  // spacing along z (x and y: 1)
  struct Voxel {
    int i, j, k;
    float value;
  } voxels[3];
};

// Voxel values from teem-unu, e.g. for cthead (100..110, 128, 56):
//   teem-unu slice -i cthead.nhdr -a 2 -p 56 | teem-unu slice -a 1 -p 128 |
//     teem-unu crop -min 100 -max 110 | teem-unu save -f text
const RealVolume kRealVolumes[] = {
    {"bucky.nhdr", 32, 32, 32, 0, 255, 1, {{10, 16, 16, 2}, {11, 16, 16, 1}, {12, 16, 16, 1}}},
    {"fuel.nhdr", 64, 64, 64, 0, 255, 1, {}},
    {"neghip.nhdr", 64, 64, 64, 0, 255, 1, {}},
    {"silicium.nhdr", 98, 34, 34, 0, 255, 1, {}},
    {"ch2.nhdr", 181, 217, 181, 0, 254, 1, {{90, 108, 90, 33}, {91, 108, 90, 62}, {92, 108, 90, 100}}},
    {"cthead.nhdr", 256, 256, 113, 0, 3272, 2, {{100, 128, 56, 1064}, {110, 128, 56, 1084}, {125, 60, 100, 936}}},
};

TEST(VolumeIo, RealVolumesReadWithTheirReadmeSizesAndRanges) {
  // Where the one resolver says they are (registry/loaders.h volumes_dir:
  // $LOCKSTEP_VOLUMES_DIR, else ../shared/volumes), as the benchmarks read them.
  const fs::path dir = volumes_dir();
  if (!fs::exists(dir / "cthead.nhdr"))
    GTEST_SKIP() << dir << " has no real volumes (cthead.nhdr): a clone without ../shared";
  for (const RealVolume& r : kRealVolumes) {
    const std::string path = (dir / r.header).string();
    const Volume v = read_quietly(path);
    EXPECT_EQ(v.nx, r.nx) << path;
    EXPECT_EQ(v.ny, r.ny) << path;
    EXPECT_EQ(v.nz, r.nz) << path;
    EXPECT_EQ(v.source, path);
    ASSERT_EQ(v.data.size(), size_t(r.nx) * r.ny * r.nz) << path;
    const auto [lo, hi] = std::minmax_element(v.data.begin(), v.data.end());
    EXPECT_EQ(*lo, r.min) << path;
    EXPECT_EQ(*hi, r.max) << path;
    EXPECT_EQ(v.spacing.x, 1) << path;
    EXPECT_EQ(v.spacing.y, 1) << path;
    EXPECT_EQ(v.spacing.z, r.sz) << path;
    EXPECT_EQ(v.origin.x, 0) << path;
    for (const auto& x : r.voxels) {
      if (x.value != 0) {
        EXPECT_EQ(v.at(x.i, x.j, x.k), x.value) << path << " voxel (" << x.i << ", " << x.j << ", " << x.k << ")";
      }
    }
  }
}

TEST(VolumeIo, DirectRawReadIsTeems) {
  // Every NRRD the tests hold, good (the corpus, the real volumes) and bad
  // (tests/bad-volumes: the same message either way).
  std::vector<fs::path> files;
  for (const fs::path& dir : std::vector<fs::path>{fs::path(LOCKSTEP_CORPUS_DIR) / "volumes", fs::path(LOCKSTEP_BAD_VOLUMES_DIR), fs::path(volumes_dir())})
    if (fs::exists(dir))
      for (const auto& e : fs::directory_iterator(dir))
        if (e.path().extension() == ".nrrd" || e.path().extension() == ".nhdr") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& p : files) expect_direct_is_teems(p.string());
  EXPECT_GE(files.size(), 40u);
  std::cout << "[ lockstep ] " << files.size() << " NRRD files read both ways\n";
}

TEST(VolumeIo, CorpusVolumesRead) {
  const fs::path dir = fs::path(LOCKSTEP_CORPUS_DIR) / "volumes";
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string ext = e.path().extension().string();
    if (ext != ".nhdr" && ext != ".nrrd" && ext != ".field") continue;
    const Volume v = read_quietly(e.path().string());
    EXPECT_GE(std::min({v.nx, v.ny, v.nz}), 2) << e.path();
    EXPECT_EQ(v.data.size(), size_t(v.nx) * v.ny * v.nz) << e.path();
    ++n;
  }
  EXPECT_EQ(n, 6) << "corpus/volumes: expected 2 NRRD volumes and 4 .field files";
  // What corpus/volumes/README.md says of them.
  const Volume bucky = read_volume((dir / "bucky.nhdr").string());
  EXPECT_EQ(bucky.nx * bucky.ny * bucky.nz, 32 * 32 * 32);
  EXPECT_EQ(bucky.at(10, 16, 16), 2);
  const Volume neghip = read_volume((dir / "neghip.nhdr").string());
  EXPECT_EQ(neghip.nx * neghip.ny * neghip.nz, 64 * 64 * 64);
  const Volume sphere = read_volume((dir / "sphere-32.field").string());
  EXPECT_EQ(sphere.nx, 32);
  EXPECT_EQ(sphere.origin, (Vec3{-1, -1, -1}));
  EXPECT_EQ(sphere.at(0, 0, 0), float(std::sqrt(3.0)));
  const FieldSpec torus = read_field_spec((dir / "torus-32.field").string());
  EXPECT_EQ(torus.kind, FieldKind::kTorus);
  EXPECT_EQ(natural_iso(torus), 0.25);
  EXPECT_EQ(read_field_spec((dir / "gyroid-32.field").string()).a, 2);
  const Volume ml = read_volume((dir / "ml-41.field").string());
  EXPECT_EQ(ml.nx, 41);
  EXPECT_NEAR(ml.at(20, 20, 20), 0.6, 1e-7);  // the origin
}

// ---------------------------------------------------------------- hand-written NRRD files

// 2 x 3 x 4 samples; value(i, j, k) = f(index).
constexpr int kNx = 2, kNy = 3, kNz = 4, kN = kNx * kNy * kNz;

template <class T>
std::vector<T> values(double (*f)(int)) {
  std::vector<T> v;
  for (int i = 0; i < kN; ++i) v.push_back(T(f(i)));
  return v;
}

template <class T>
std::vector<double> as_double(const std::vector<T>& v) {
  return std::vector<double>(v.begin(), v.end());
}

struct Encoded {
  const char* type;
  bool big;
  const char* encoding;
  bool detached;
};

// Writes a 2x3x4 NRRD of type T holding f(index), in every layout asked for, and reads it back.
template <class T>
void round_trip(const char* type, double (*f)(int)) {
  const std::vector<T> v = values<T>(f);
  for (bool big : {false, true})
    for (const char* encoding : {"raw", "gzip", "hex"})
      for (bool detached : {false, true}) {
        TempDir dir;
        const std::string raw = bytes_of(v, big);
        std::string data = raw;
        if (std::string(encoding) == "gzip") data = gzip(raw);
        if (std::string(encoding) == "hex") {
          data.clear();
          for (unsigned char c : raw) {
            char b[4];
            std::snprintf(b, sizeof b, "%02x", c);
            data += b;
          }
          data += "\n";
        }
        std::string header = std::string("NRRD0004\n# written by volume_io_test\ntype: ") + type + "\ndimension: 3\n" +
                             sizes_line(kNx, kNy, kNz) + "encoding: " + encoding +
                             "\nendian: " + (big ? "big" : "little") + "\n";
        std::string path;
        if (detached) {
          fs::create_directories(dir.file("sub"));
          write_file(dir.file("sub/data.bin"), data);
          header += "data file: sub/data.bin\n";
          path = dir.file("v.nhdr");
          write_file(path, header);
        } else {
          path = dir.file("v.nrrd");
          write_file(path, header + "\n" + data);
        }
        const std::string what = std::string(type) + (big ? " big-endian " : " little-endian ") + encoding +
                                 (detached ? " detached" : " attached") + " (" + path + ")";
        Volume vol;
        try {
          vol = read_quietly(path);
        } catch (const std::exception& e) {
          FAIL() << what << ": " << e.what();
        }
        EXPECT_EQ(vol.nx, kNx) << what;
        EXPECT_EQ(vol.ny, kNy) << what;
        EXPECT_EQ(vol.nz, kNz) << what;
        expect_samples(vol, as_double(v), what);
        expect_direct_is_teems(path);
      }
}

double ramp(int i) { return i * 10 + 3; }
double signed_ramp(int i) { return (i - 12) * 1000 - 7; }
double fractions(int i) { return (i - 12) * 0.375 + 1.0 / 1024; }

TEST(VolumeIo, EveryTypeEndiannessEncodingAndAttachment) {
  round_trip<uint8_t>("uchar", ramp);
  round_trip<int8_t>("signed char", [](int i) { return double(i * 5 - 60); });
  round_trip<uint16_t>("ushort", [](int i) { return double(i * 2731 + 258); });
  round_trip<int16_t>("short", signed_ramp);
  round_trip<uint32_t>("uint", [](int i) { return double(i * 65537 + 16777216 / 4); });
  round_trip<int32_t>("int", signed_ramp);
  round_trip<float>("float", fractions);
  round_trip<double>("double", fractions);
}

TEST(VolumeIo, AsciiEncoding) {
  TempDir dir;
  std::string text;
  for (int i = 0; i < kN; ++i) text += std::to_string(i * 7 - 50) + (i % 5 == 4 ? "\n" : " ");
  write_file(dir.file("a.nrrd"),
             "NRRD0004\ntype: short\ndimension: 3\n" + sizes_line(kNx, kNy, kNz) + "encoding: ascii\n\n" + text);
  std::vector<double> expected;
  for (int i = 0; i < kN; ++i) expected.push_back(i * 7 - 50);
  expect_samples(read_quietly(dir.file("a.nrrd")), expected, "ascii short");
}

TEST(VolumeIo, SpacingsAndSpaceDirections) {
  TempDir dir;
  const std::string data = bytes_of(values<uint8_t>(ramp), false);
  const std::string head = "NRRD0004\ntype: uchar\ndimension: 3\n" + sizes_line(kNx, kNy, kNz) + "encoding: raw\n";
  {
    write_file(dir.file("s.nrrd"), head + "spacings: 0.5 2 3.25\n\n" + data);
    const Volume v = read_quietly(dir.file("s.nrrd"));
    EXPECT_EQ(v.spacing, (Vec3{0.5, 2, 3.25}));
    EXPECT_EQ(v.origin, (Vec3{0, 0, 0}));
  }
  {
    write_file(dir.file("d.nrrd"), head +
                                       "space: right-anterior-superior\nspace directions: (0.5,0,0) (0,2,0) "
                                       "(0,0,3.25)\nspace origin: (1,-2,30)\n\n" +
                                       data);
    const Volume v = read_quietly(dir.file("d.nrrd"));
    EXPECT_EQ(v.spacing, (Vec3{0.5, 2, 3.25}));
    EXPECT_EQ(v.origin, (Vec3{1, -2, 30}));
    expect_samples(v, as_double(values<uint8_t>(ramp)), "space directions");
  }
  {
    // An LPS-style negative x direction: the samples are reversed along x and
    // the origin moves to the other end, so every sample keeps its world position.
    write_file(dir.file("n.nrrd"), head +
                                       "space dimension: 3\nspace directions: (-0.5,0,0) (0,2,0) (0,0,-1)\n"
                                       "space origin: (10,0,5)\n\n" +
                                       data);
    const Volume v = read_quietly(dir.file("n.nrrd"));
    EXPECT_EQ(v.spacing, (Vec3{0.5, 2, 1}));
    EXPECT_EQ(v.origin, (Vec3{9.5, 0, 2}));
    const std::vector<uint8_t> file = values<uint8_t>(ramp);
    for (int k = 0; k < kNz; ++k)
      for (int j = 0; j < kNy; ++j)
        for (int i = 0; i < kNx; ++i) {
          // File sample (i, j, k) sits at (10 - 0.5 i, 2 j, 5 - k).
          const float expected = file[size_t((k * kNy + j) * kNx + i)];
          const Vec3 world{10 - 0.5 * i, 2.0 * j, 5.0 - k};
          const int ii = int(std::lround((world.x - v.origin.x) / v.spacing.x));
          const int kk = int(std::lround((world.z - v.origin.z) / v.spacing.z));
          EXPECT_EQ(v.at(ii, j, kk), expected) << "file sample (" << i << ", " << j << ", " << k << ")";
          EXPECT_EQ(v.position(ii, j, kk), world);
        }
  }
  {
    write_file(dir.file("o.nrrd"), head + "space dimension: 3\nspace directions: (1,0.5,0) (0,1,0) (0,0,1)\n\n" + data);
    const std::string m = error_of(dir.file("o.nrrd"));
    EXPECT_NE(m.find("o.nrrd:7: axis 0: space direction (1.000000, 0.500000, 0.000000) is not along x"),
              std::string::npos)
        << m;
  }
}

TEST(VolumeIo, UnknownExtensionMissingFileDirectory) {
  TempDir dir;
  write_file(dir.file("v.raw"), "abc");
  EXPECT_NE(error_of(dir.file("v.raw")).find("v.raw: not a volume: the extension must be"), std::string::npos);
  EXPECT_NE(error_of(dir.file("nope.nrrd")).find("nope.nrrd: cannot open file: No such file"), std::string::npos);
  fs::create_directories(dir.file("d.nrrd"));
  EXPECT_NE(error_of(dir.file("d.nrrd")).find("d.nrrd: file is not a regular file"), std::string::npos);
  EXPECT_NE(error_of(dir.file("nope.field")).find("nope.field: cannot open file: No such file"), std::string::npos);
}

// ---------------------------------------------------------------- analytic fields

TEST(VolumeIo, FieldValuesAtKnownPoints) {
  const double pi = std::numbers::pi;
  const FieldSpec sphere = field_defaults(FieldKind::kSphere);
  EXPECT_EQ(natural_iso(sphere), 0.5);
  EXPECT_EQ(field_value(sphere, {0.5, 0, 0}), 0.5);
  EXPECT_EQ(field_value(sphere, {0, 0.3, 0.4}), 0.5);
  EXPECT_EQ(field_value(sphere, {0, 0, 0}), 0);

  const FieldSpec torus = field_defaults(FieldKind::kTorus);  // R = 0.5, r = 0.25
  EXPECT_EQ(natural_iso(torus), 0.25);
  EXPECT_EQ(field_value(torus, {0.75, 0, 0}), 0.25);
  EXPECT_EQ(field_value(torus, {0, -0.25, 0}), 0.25);
  EXPECT_EQ(field_value(torus, {0, 0.5, 0.25}), 0.25);
  EXPECT_EQ(field_value(torus, {0.3, 0.4, 0}), 0);  // on the core circle

  FieldSpec gyroid = field_defaults(FieldKind::kGyroid);  // 2 periods across [-1, 1]: k = 2 pi
  EXPECT_EQ(gyroid.a, 2);
  EXPECT_EQ(natural_iso(gyroid), 0);
  EXPECT_EQ(field_value(gyroid, {0, 0, 0}), 0);
  // x = y = z = t: f = 3 sin(kt) cos(kt) = 1.5 sin(2kt), zero at kt = pi/2 and 1 at kt = pi/4... times 1.5.
  EXPECT_NEAR(field_value(gyroid, {0.25, 0.25, 0.25}), 0, 1e-15);
  EXPECT_NEAR(field_value(gyroid, {0.125, 0.125, 0.125}), 1.5, 1e-15);
  EXPECT_NEAR(field_value(gyroid, {0.25, 0, 0}), 1, 1e-15);  // sin(pi/2) cos(0)
  gyroid.lo = 0, gyroid.hi = 4;                              // the same 2 periods across a side of 4: k = pi
  EXPECT_NEAR(field_value(gyroid, {0.5, 0, 0}), 1, 1e-15);

  const FieldSpec ml = field_defaults(FieldKind::kMarschnerLobb);
  EXPECT_EQ(ml.a, 0.25);
  EXPECT_EQ(ml.b, 6);
  EXPECT_EQ(natural_iso(ml), 0.5);
  EXPECT_NEAR(field_value(ml, {0, 0, 0}), 0.6, 1e-15);  // (1 - 0 + 0.25 (1 + cos 12 pi)) / 2.5
  EXPECT_NEAR(field_value(ml, {0, 0, 1}), 0.2, 1e-15);  // (1 - 1 + 0.5) / 2.5
  EXPECT_NEAR(field_value(ml, {0, 0, -1}), 1.0, 1e-15);
  // r = 1: cos(pi/2) = 0, rho_r = cos(0) = 1; the same as the axis.
  EXPECT_NEAR(field_value(ml, {1, 0, 0}), 0.6, 1e-15);
  // r with cos(pi r / 2) = 1/24: rho_r = cos(pi / 2) = 0.
  const double r = 2 / pi * std::acos(1.0 / 24);
  EXPECT_NEAR(field_value(ml, {r, 0, 0}), 0.5, 1e-12);
}

TEST(VolumeIo, SampleFieldPositions) {
  for (FieldKind kind : {FieldKind::kSphere, FieldKind::kTorus, FieldKind::kGyroid, FieldKind::kMarschnerLobb}) {
    FieldSpec f = field_defaults(kind);
    f.n = 7;
    f.lo = -1.5;
    f.hi = 2;
    const Volume v = sample_field(f, "test");
    EXPECT_EQ(v.source, "test");
    ASSERT_EQ(v.nx, 7);
    ASSERT_EQ(v.ny, 7);
    ASSERT_EQ(v.nz, 7);
    EXPECT_EQ(v.origin, (Vec3{-1.5, -1.5, -1.5}));
    EXPECT_EQ(v.spacing, (Vec3{3.5 / 6, 3.5 / 6, 3.5 / 6}));
    for (int k = 0; k < 7; ++k)
      for (int j = 0; j < 7; ++j)
        for (int i = 0; i < 7; ++i) {
          const auto c = [](int t) { return -1.5 + 3.5 * t / 6; };
          const Vec3 p{c(i), c(j), c(k)};
          ASSERT_EQ(v.at(i, j, k), float(field_value(f, p)))
              << field_name(kind) << " (" << i << ", " << j << ", " << k << ")";
          const Vec3 q = v.position(i, j, k);
          ASSERT_NEAR(q.x, p.x, 1e-15);
          ASSERT_NEAR(q.y, p.y, 1e-15);
          ASSERT_NEAR(q.z, p.z, 1e-15);
        }
    EXPECT_EQ(v.at(6, 6, 6), float(field_value(f, {2, 2, 2}))) << "the far corner is hi exactly";
  }
  // The sphere through sample_field: the sample at radius 0.5 holds 0.5 (iso = radius).
  FieldSpec s = field_defaults(FieldKind::kSphere);
  s.n = 5;  // samples at -1, -0.5, 0, 0.5, 1
  const Volume v = sample_field(s, "sphere");
  EXPECT_EQ(v.at(3, 2, 2), 0.5f);
  EXPECT_EQ(v.at(2, 2, 2), 0.0f);
}

TEST(VolumeIo, SampleFieldRejectsBadSpecs) {
  auto rejects = [](FieldSpec f, const std::string& what) {
    try {
      sample_field(f, "spec");
      ADD_FAILURE() << "accepted: " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  FieldSpec f;
  f.n = 1;
  rejects(f, "size 1 is out of range");
  f.n = 1025;
  rejects(f, "size 1025 is out of range");
  f = FieldSpec{};
  f.lo = 1, f.hi = 1;
  rejects(f, "LO < HI");
  f = FieldSpec{};
  f.hi = NAN;
  rejects(f, "finite");
  f = FieldSpec{};
  f.a = 0;
  rejects(f, "sphere radius must be > 0");
  f = FieldSpec{};
  f.hi = 1e7;
  rejects(f, "bounds must lie within [-1e6, 1e6]");
  f = field_defaults(FieldKind::kGyroid);  // k = 2 pi 1e6 / 1e-310 overflows: NaN samples
  f.a = 1e6, f.lo = 0, f.hi = 1e-310;
  rejects(f, "the field is not finite at (0, 0, 0) (sample (0, 0, 0))");
}

TEST(VolumeIo, FieldFiles) {
  TempDir dir;
  write_file(dir.file("t.field"), "# a torus\nfield torus   # the kind\n\nsize 9\nbounds -2 2\nradii 1 0.5\n");
  const FieldSpec t = read_field_spec(dir.file("t.field"));
  EXPECT_EQ(t.kind, FieldKind::kTorus);
  EXPECT_EQ(t.n, 9);
  EXPECT_EQ(t.lo, -2);
  EXPECT_EQ(t.hi, 2);
  EXPECT_EQ(t.a, 1);
  EXPECT_EQ(t.b, 0.5);
  const Volume v = read_quietly(dir.file("t.field"));
  EXPECT_EQ(v.nx, 9);
  EXPECT_EQ(v.source, dir.file("t.field"));
  EXPECT_EQ(v.at(7, 4, 4), 0.5f);  // (1.5, 0, 0): 0.5 from the core circle
  EXPECT_EQ(v.at(6, 4, 4), 0.0f);  // (1, 0, 0): on it

  write_file(dir.file("m.field"), "size 41\nfield marschner_lobb\n");  // any order; defaults
  const FieldSpec m = read_field_spec(dir.file("m.field"));
  EXPECT_EQ(m.kind, FieldKind::kMarschnerLobb);
  EXPECT_EQ(m.n, 41);
  EXPECT_EQ(m.lo, -1);
  EXPECT_EQ(m.hi, 1);
  EXPECT_EQ(m.a, 0.25);
  EXPECT_EQ(m.b, 6);
  const Volume mv = read_volume(dir.file("m.field"));
  EXPECT_NEAR(mv.at(20, 20, 20), 0.6, 1e-7);

  write_file(dir.file("g.field"), "field gyroid\r\nperiods 3\r\n");
  EXPECT_EQ(read_field_spec(dir.file("g.field")).a, 3);
  write_file(dir.file("s.field"), "field sphere\nradius 0.75\nsize 2\n");
  EXPECT_EQ(read_field_spec(dir.file("s.field")).a, 0.75);
  EXPECT_EQ(read_field_spec(dir.file("s.field")).n, 2);
}

// ---------------------------------------------------------------- bad input (tests/bad-volumes)

std::string regex_escaped(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (std::strchr(".^$|()[]{}*+?\\", c)) out += '\\';
    out += c;
  }
  return out;
}

TEST(VolumeIo, BadVolumesThrowTheExpectedError) {
  int n = 0;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(LOCKSTEP_BAD_VOLUMES_DIR)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& p : files) {
    const std::string ext = p.extension().string();
    if (ext != ".nrrd" && ext != ".nhdr" && ext != ".field") continue;  // data files, README
    std::string expect;
    if (p.stem() == "empty") {
      expect = ": file is empty";  // 0 bytes: no room for the comment
    } else {
      std::ifstream in(p, std::ios::binary);
      std::string line;
      for (int i = 0; i < 3 && std::getline(in, line); ++i)
        if (line.starts_with("# expect: ")) expect = line.substr(10);
      ASSERT_FALSE(expect.empty()) << p << " has no '# expect: <regex>' line among its first three";
    }
    const std::string m = error_of(p.string());
    const std::regex re(regex_escaped(p.string()) + expect + "$");
    EXPECT_TRUE(std::regex_search(m, re)) << p << "\n  message:  " << m << "\n  expected: <file>" << expect;
    ++n;
  }
  EXPECT_GE(n, 20) << "fewer bad volumes than expected in " << LOCKSTEP_BAD_VOLUMES_DIR;
  std::cout << "[ lockstep ] " << n << " bad volume files checked\n";
}

}  // namespace
}  // namespace lockstep
