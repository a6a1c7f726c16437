// lockstep io: reading volumes -- NRRD files and analytic fields.
//
// NRRD (Gordon Kindlmann's "Nearly Raw Raster Data",
// http://teem.sourceforge.net/nrrd/format.html) is read with Teem's nrrd
// library (Debian libteem-dev), the format's reference implementation:
// attached (.nrrd: header, a blank line, the data) and detached headers
// (.nhdr: `data file:` names the data, relative to the header's directory),
// encodings raw, gzip (where Teem was built with zlib), ascii and hex, both
// endiannesses, types uchar, char, ushort, short, uint, int, float and double
// (converted to float: exact up to 2^24; int and uint beyond that round).
// Only 3-D arrays are read, each axis with at least 2 samples. Geometry:
// spacing from `spacings:` or from `space directions:` (axis-aligned only:
// axis 0 along x, 1 along y, 2 along z; an oblique or permuted grid is an
// error), `nan` or absent meaning 1; origin from `space origin:` (default 0;
// `axis mins:` is ignored). A negative spacing (an LPS scan's -1 0 0) is
// turned positive by reversing the samples along that axis and moving the
// origin to the other end: every sample keeps its world position.
//
// Why we look at the header before Teem does. Teem trusts the header: it
// allocates what `sizes:` x `type:` says before it looks at the data (a
// 40-byte file claiming 2^40 samples asks malloc for a terabyte; under
// AddressSanitizer that aborts the process), it reads PNG, PNM, VTK and plain
// text as well as NRRD whatever the extension, it follows `data file:` to any
// path (a FIFO or /dev/zero hangs or fills memory) and to lists and numbered
// sequences of files, and it reports errors without a line number. So
// read_volume first reads the header's text lines itself (up to the blank
// line; the magic NRRD0001..NRRD0005 first) and rejects, naming the line:
//   - a first line that is not a NRRD magic (Teem's other formats are not read);
//   - NUL bytes in the header; a missing `type:`, `dimension:`, `sizes:` or `encoding:`;
//   - a dimension other than 3; sizes that are not 3 plain integers >= 2, or
//     whose product exceeds kMaxVolumeSamples (checked without overflow);
//   - unknown or unsupported types (int64, uint64, block) and encodings (bzip2, zrl);
//   - `data file:` lists and %d sequences; a data file that is not an existing regular file;
//   - unknown fields, a field given twice, per-axis fields before `dimension:`,
//     `block size:`;
//   - a `byte skip:` below -1 or `line skip:` below 0;
//   - less data than the sizes need: raw needs the bytes (after the header and
//     any byte skip), hex two characters a byte, ascii at least one byte a
//     sample, gzip at most 1032 bytes out per byte in (deflate's limit);
//   - gzip data is inflated here (zlib) as far as the sizes need, and must
//     yield them without an error: Teem's gzip reader leaks its zlib state on
//     a short or corrupt stream, and zlib passes non-gzip bytes through as if
//     they were the data (line skips and byte skip -1 with gzip are refused).
// Then Teem reads the file (raw data: the header only, the data is read
// straight into the volume; see read_nrrd below) (under a mutex: biff, Teem's error stack, is
// global), and what it reports becomes the InputError: biff's innermost
// message on one line, on the line of the field it names (else line 0).
// Teem prints nothing on stderr (nrrdStateVerboseIO = 0). Known left to
// Teem: on some header errors it finds itself (an unterminated quoted string
// in `units:` or `labels:`, for one) it leaks a few hundred bytes
// (scripts/lsan-teem.supp, the fuzz run's suppressions, lists them).
// After reading: the geometry as above, and every sample finite in float (a
// NaN, an infinity or a double beyond float's range is an InputError naming
// the sample's (i, j, k)).
//
// Analytic fields, sampled at any resolution, so that exact surfaces and
// exact integrals are known. Each kind's natural iso value (natural_iso)
// gives its surface:
//   sphere          f = |p|                          iso = radius a (default 0.5)
//   torus           f = sqrt((sqrt(x^2+y^2) - a)^2 + z^2)   iso = minor radius b
//                   (the distance to the core circle of radius a in the z = 0
//                   plane; defaults a = 0.5, b = 0.25)
//   gyroid          f = sin(kx)cos(ky) + sin(ky)cos(kz) + sin(kz)cos(kx),
//                   k = 2 pi a / (hi - lo): a periods across the cube's side
//                   (default 2); iso = 0; f(0, 0, 0) = 0
//   marschner_lobb  Marschner & Lobb, "An evaluation of reconstruction filters
//                   for volume rendering", IEEE Visualization 1994:
//                   f = (1 - sin(pi z / 2) + alpha (1 + rho_r(sqrt(x^2+y^2)))) / (2 (1 + alpha)),
//                   rho_r(r) = cos(2 pi f_M cos(pi r / 2)); alpha = a (0.25), f_M = b (6),
//                   meant for [-1, 1]^3 at 41^3; iso = 0.5; f(0, 0, 0) = 0.6
// Sphere and torus are Euclidean distances (to a point, to a circle), so the
// iso value is the radius: a user writes iso = 0.5 for a radius-0.5 sphere,
// through sample_field or through a .field file alike.
//
// A .field file: text, '#' starts a comment, one 'key value...' per line:
//   field sphere|torus|gyroid|marschner_lobb   (required)
//   size N                                     (2 <= N <= 1024; default 64)
//   bounds LO HI                               (LO < HI, within [-1e6, 1e6]; default -1 1)
//   radius R          sphere: R > 0
//   radii R r         torus: R > 0, r > 0
//   periods P         gyroid: P > 0
//   alpha A / fm F    marschner_lobb: A >= 0, F > 0
// Parameters lie within [-1e6, 1e6]; a spec whose samples would not all be
// finite floats (a tiny cube with many gyroid periods) is an InputError.
// Keys may come in any order, each at most once; a key of another kind, an
// unknown key, a missing or extra value, a non-number, NaN or Inf is an
// InputError naming the line. The volume's source is the file's path.
#pragma once

#include <cstddef>
#include <string>

#include "core/math.h"
#include "core/volume.h"

namespace lockstep {

// ------------------------------------------------------------------ limits
// More samples than this is called absurd (8 GiB of floats).
inline constexpr size_t kMaxVolumeSamples = size_t(1) << 31;
inline constexpr int kMaxFieldSize = 1024;

// ------------------------------------------------------------------ reading
// Reads a volume: a NRRD file (.nrrd attached, .nhdr detached; through Teem) or
// an analytic field description (.field). The extension decides (any case).
// Throws InputError(path, line, msg) for every bad input (line 0 when there is
// none), never crashes, never returns a volume with NaN/inf samples or fewer
// than 2 samples on an axis. Thread-safe (Teem is called under a mutex).
Volume read_volume(const std::string& path);
// A NRRD file alone (.nrrd or .nhdr, whatever its extension; io/nrrd.cpp).
Volume read_nrrd(const std::string& path);
// How the samples are read: kDirect, read_nrrd's way, reads raw data (no line
// skip, no byte skip -1) itself, straight into the volume's buffer, and lets
// Teem read the header only (nio->skipData); Teem would zero a buffer of its
// own, read into it and leave the copy to us: the file's size in fresh pages
// touched twice (issue #35). kTeem has Teem read every encoding: what tests
// compare kDirect with, sample for sample.
enum class NrrdData { kDirect, kTeem };
Volume read_nrrd(const std::string& path, NrrdData how);

// ------------------------------------------------------------------ analytic fields
enum class FieldKind { kSphere, kTorus, kGyroid, kMarschnerLobb };
struct FieldSpec {
  FieldKind kind = FieldKind::kSphere;
  int n = 64;              // samples per axis (n x n x n)
  double lo = -1, hi = 1;  // the cube [lo, hi]^3 sampled, corners included
  // sphere: radius; torus: major, minor radius; gyroid: periods per side; marschner_lobb: alpha, f_M
  double a = 0.5, b = 0.25;
};

// The kind's name in .field files ("sphere", "torus", "gyroid", "marschner_lobb").
const char* field_name(FieldKind kind);
// A FieldSpec of that kind with the kind's default parameters (table above).
FieldSpec field_defaults(FieldKind kind);
// The iso value whose level set is the field's surface (table above).
double natural_iso(const FieldSpec& f);

// f(p) at a world point (double precision; no validation).
double field_value(const FieldSpec& f, const Vec3& p);
// The field sampled on n^3 points: sample (i, j, k) is field_value at
// (lo + (hi - lo) i / (n - 1), ... j ..., ... k ...), rounded to float;
// origin = (lo, lo, lo), spacing = (hi - lo) / (n - 1) on each axis. Throws
// InputError(source, 0, ...) for an invalid spec (n outside 2..1024, bounds
// not finite or not increasing, a parameter out of its range above).
Volume sample_field(const FieldSpec& f, std::string source);
// Reads a .field file; InputError(path, line, ...) on anything wrong.
FieldSpec read_field_spec(const std::string& path);

}  // namespace lockstep
