#!/usr/bin/env python3
# Writes the bad volumes in this directory (README.md). Each NRRD file's second
# line says what is wrong with it, its third line `# expect: <regex>` what must
# follow the file name in the InputError's message (":line: message", anchored
# at the end); .field files say the same on lines 1 and 2. empty.nrrd stays 0
# bytes (its expectation is in tests/volume_io_test.cpp).
import gzip
import os
import struct

here = os.path.dirname(os.path.abspath(__file__))


def write(name, data):
    with open(os.path.join(here, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def nrrd(name, what, expect, fields, data=b"", attached=True):
    text = "NRRD0004\n# bad input for lockstep: %s\n# expect: %s\n%s" % (what, expect, "".join(f + "\n" for f in fields))
    write(name, text.encode() + (b"\n" + data if attached else b""))


def field(name, what, expect, lines):
    write(name, "# bad input for lockstep: %s\n# expect: %s\n%s" % (what, expect, "".join(l + "\n" for l in lines)))


U8 = ["type: uchar", "dimension: 3", "sizes: 4 4 4", "encoding: raw"]
cube = bytes(range(64))

# ---- lying or truncated headers
nrrd("truncated.nrrd", "sizes 4 4 4 but only 10 bytes of data",
     r":6: sizes 4 x 4 x 4 uchar need 64 bytes, but the file holds 10 byte\(s\) of data", U8, cube[:10])
nrrd("truncated-detached.nhdr", "the data file holds 40 of the 64 bytes the sizes need",
     r":6: sizes 4 x 4 x 4 uchar need 64 bytes, but the data file 'truncated-detached\.raw' holds 40 byte\(s\) of data",
     U8 + ["data file: truncated-detached.raw"], attached=False)
write("truncated-detached.raw", cube[:40])
nrrd("truncated-gzip.nrrd", "gzip data that inflates to 32 of the 64 bytes",
     r":6: sizes need 64 bytes, but the gzip data inflates to 32", ["type: uchar", "dimension: 3", "sizes: 4 4 4", "encoding: gzip"],
     gzip.compress(cube[:32], mtime=0))
nrrd("not-gzip.nrrd", "encoding gzip, but the data is raw",
     r":7: encoding gzip, but the data is not gzip \(zlib: incorrect header check\)",
     ["type: uchar", "dimension: 3", "sizes: 4 4 4", "encoding: gzip"], cube)
corrupt = bytearray(gzip.compress(bytes(range(256)) * 4, mtime=0))
corrupt[30] ^= 0xFF
nrrd("corrupt-gzip.nrrd", "a gzip stream with a damaged byte",
     r":7: corrupt gzip data after [0-9]+ of the 1024 bytes the sizes need \(zlib: .*\)",
     ["type: uchar", "dimension: 3", "sizes: 16 8 8", "encoding: gzip"], bytes(corrupt))
nrrd("gzip-bad-crc.nrrd", "a gzip stream whose CRC is wrong",
     r":7: corrupt gzip data after 64 of the 64 bytes the sizes need \(zlib: incorrect data check\)",
     ["type: uchar", "dimension: 3", "sizes: 4 4 4", "encoding: gzip"], gzip.compress(cube, mtime=0)[:-8] + b"\0\0\0\0" + gzip.compress(cube, mtime=0)[-4:])
nrrd("gzip-junk-member.nrrd", "a broken second gzip member right after the data",
     r":7: corrupt gzip data after 64 of the 64 bytes the sizes need \(zlib: a broken gzip header after the data\)",
     ["type: uchar", "dimension: 3", "sizes: 4 4 4", "encoding: gzip"], gzip.compress(cube, mtime=0) + b"\x1f\x8bxyz")
nrrd("gzip-no-trailer.nrrd", "a gzip stream cut before its CRC (every data byte is there)",
     r":7: corrupt gzip data after 64 of the 64 bytes the sizes need \(zlib: the stream stops before its end\)",
     ["type: uchar", "dimension: 3", "sizes: 4 4 4", "encoding: gzip"], gzip.compress(cube, mtime=0)[:-8])
nrrd("gzip-line-skip.nrrd", "a line skip before gzip data",
     r":8: line skip with gzip encoding is not read",
     ["type: uchar", "dimension: 3", "sizes: 4 4 4", "encoding: gzip", "line skip: 1"], b"x\n" + gzip.compress(cube, mtime=0))
nrrd("seven-dimensions.nrrd", "a 7-dimensional array",
     r":5: dimension 7: only 3-D volumes are read",
     ["type: uchar", "dimension: 7", "sizes: 2 2 2 2 2 2 2", "encoding: raw"], cube[:128] + cube[:64])
nrrd("two-dimensions.nrrd", "a 2-D image",
     r":5: dimension 2: only 3-D volumes are read", ["type: uchar", "dimension: 2", "sizes: 8 8", "encoding: raw"], cube)
nrrd("sizes-count.nrrd", "dimension 3 with two sizes",
     r":6: sizes: 2 values, expected 3 \(a 3-D volume\)", ["type: uchar", "dimension: 3", "sizes: 8 8", "encoding: raw"], cube)
nrrd("negative-size.nrrd", "a negative size",
     r":6: sizes: '-4' is not a size \(a non-negative integer\)",
     ["type: uchar", "dimension: 3", "sizes: 4 -4 4", "encoding: raw"], cube)
nrrd("overflowing-sizes.nrrd", "sizes whose product overflows 64 bits (2^96)",
     r":6: sizes 4294967296 x 4294967296 x 4294967296 exceed 2147483648 samples",
     ["type: uchar", "dimension: 3", "sizes: 4294967296 4294967296 4294967296", "encoding: raw"], cube)
nrrd("huge-sizes.nrrd", "2^48 samples claimed by a 100-byte file",
     r":6: sizes 65536 x 65536 x 65536 exceed 2147483648 samples",
     ["type: uchar", "dimension: 3", "sizes: 65536 65536 65536", "encoding: raw"], cube)
nrrd("size-too-long.nrrd", "a size of 30 digits",
     r":6: sizes: '100000000000000000000000000000' is not a size \(a non-negative integer\)",
     ["type: uchar", "dimension: 3", "sizes: 4 100000000000000000000000000000 4", "encoding: raw"], cube)
nrrd("size-one.nrrd", "an axis of one sample (no cells)",
     r":6: sizes: axis 0 has 1 sample\(s\); at least 2 are needed",
     ["type: uchar", "dimension: 3", "sizes: 1 8 8", "encoding: raw"], cube)
nrrd("size-zero.nrrd", "an axis of no samples",
     r":6: sizes: axis 2 has 0 sample\(s\); at least 2 are needed",
     ["type: uchar", "dimension: 3", "sizes: 8 8 0", "encoding: raw"], cube)

# ---- unknown or unsupported type and encoding
nrrd("unknown-type.nrrd", "type quaternion",
     r":4: unknown type 'quaternion'", ["type: quaternion", "dimension: 3", "sizes: 4 4 4", "encoding: raw"], cube)
nrrd("int64-type.nrrd", "64-bit integers (not read)",
     r":4: type 'int64' is not read \(uchar, char, ushort, short, uint, int, float, double\)",
     ["type: int64", "dimension: 3", "sizes: 2 2 2", "endian: little", "encoding: raw"], cube)
nrrd("block-type.nrrd", "type block",
     r":4: type 'block' is not read .*", ["type: block", "block size: 4", "dimension: 3", "sizes: 2 2 2", "encoding: raw"], cube)
nrrd("unknown-encoding.nrrd", "encoding lzma",
     r":7: unknown encoding 'lzma'", ["type: uchar", "dimension: 3", "sizes: 4 4 4", "encoding: lzma"], cube)
nrrd("bzip2-encoding.nrrd", "encoding bzip2 (not read)",
     r":7: encoding 'bzip2' is not read \(raw, gzip, ascii, hex\)",
     ["type: uchar", "dimension: 3", "sizes: 4 4 4", "encoding: bzip2"], cube)
nrrd("unknown-endian.nrrd", "endian middle",
     r":8: unknown endian 'middle' \(little or big\)",
     ["type: ushort", "dimension: 3", "sizes: 4 4 2", "encoding: raw", "endian: middle"], cube)
nrrd("no-endian.nrrd", "16-bit raw data without 'endian:'",
     r": the NRRD header has no 'endian:' field \(needed for multi-byte unsigned short data\)",
     ["type: ushort", "dimension: 3", "sizes: 4 4 2", "encoding: raw"], cube)
nrrd("missing-type.nrrd", "no 'type:' field",
     r": the NRRD header has no 'type:' field", ["dimension: 3", "sizes: 4 4 4", "encoding: raw"], cube)
nrrd("unknown-field.nrrd", "a field NRRD does not have",
     r":8: unknown NRRD field 'frobnication'", U8 + ["frobnication: 3"], cube)
nrrd("duplicate-field.nrrd", "two 'sizes:' fields",
     r":8: a second 'sizes:' field \(the first is on line 6\)", U8 + ["sizes: 2 2 2"], cube)
nrrd("teem-parse-error.nrrd", "spacings Teem cannot parse",
     r":8: Teem: spacings: parsed 1 values, but dimension is 3", U8 + ["spacings: 1 x 1"], cube)
nrrd("zero-spacing.nrrd", "a spacing of 0",
     r":8: Teem: spacings: axis 1 spacing \(0\) invalid", U8 + ["spacings: 1 0 1"], cube)

# ---- the data file
nrrd("missing-data-file.nhdr", "a detached header whose data file is not there",
     r":8: cannot open data file 'no-such-volume\.raw': No such file or directory",
     U8 + ["data file: no-such-volume.raw"], attached=False)
nrrd("directory-data-file.nhdr", "a data file that is a directory",
     r":8: data file '\.' is not a regular file", U8 + ["data file: ."], attached=False)
nrrd("data-file-list.nhdr", "data file: LIST (several files)",
     r":8: data file: lists and numbered sequences of files are not read \(one file only\)",
     U8 + ["data file: LIST", "truncated-detached.raw"], attached=False)
nrrd("data-file-sequence.nhdr", "a numbered sequence of data files",
     r":8: data file: lists and numbered sequences of files are not read \(one file only\)",
     U8 + ["data file: slice%03d.raw 1 4 1 2"], attached=False)
nrrd("no-blank-line.nrrd", "an attached header that never ends (no blank line, no data file)",
     r": no data: neither a 'data file:' field nor a blank line before data", U8, attached=False)

# ---- not NRRD, geometry, samples
write("not-nrrd.nrrd", b"P5\n# bad input for lockstep: a PGM image named .nrrd (Teem would read it)\n"
      b"# expect: :1: not a NRRD file: the first line is 'P5', not NRRD0001\\.\\.NRRD0005\n4 4\n255\n" + cube[:16])
nrrd("oblique.nrrd", "a rotated grid",
     r":9: axis 0: space direction \(0\.707107, 0\.707107, 0\.000000\) is not along x \(oblique and permuted grids are not read\)",
     U8 + ["space: right-anterior-superior", "space directions: (0.70710678,0.70710678,0) (-0.70710678,0.70710678,0) (0,0,1)"], cube)
nrrd("permuted.nrrd", "axis 0 along y",
     r":9: axis 0: space direction \(0\.000000, 1\.000000, 0\.000000\) is not along x .*",
     U8 + ["space dimension: 3", "space directions: (0,1,0) (1,0,0) (0,0,1)"], cube)
nrrd("nan-voxel.nrrd", "a NaN sample",
     r": sample \(1, 0, 1\) is nan; samples must be finite",
     ["type: float", "dimension: 3", "sizes: 2 2 2", "encoding: raw", "endian: little"],
     struct.pack("<8f", 0, 1, 2, 3, 4, float("nan"), 6, 7))
nrrd("inf-voxel.nrrd", "an infinite sample",
     r": sample \(0, 1, 1\) is -inf; samples must be finite",
     ["type: float", "dimension: 3", "sizes: 2 2 2", "encoding: raw", "endian: big"],
     struct.pack(">8f", 0, 1, 2, 3, 4, 5, float("-inf"), 7))
nrrd("double-beyond-float.nrrd", "a double beyond float's range",
     r": sample \(1, 1, 0\) is 1e\+300 \(beyond float's range\); samples must be finite",
     ["type: double", "dimension: 3", "sizes: 2 2 2", "encoding: raw", "endian: little"],
     struct.pack("<8d", 0, 1, 2, 1e300, 4, 5, 6, 7))
nrrd("nul-in-header.nrrd", "a NUL byte in the header",
     r":8: NUL byte in the NRRD header", U8 + ["content: a\0b"], cube)
write("empty.nrrd", b"")

# ---- .field files
field("unknown-field.field", "a field lockstep does not know", r":3: unknown field 'cube' \(sphere, torus, gyroid or marschner_lobb\)",
      ["field cube", "size 16"])
field("size-0.field", "size 0", r":4: size 0 is out of range \(an integer, 2 \.\. 1024\)", ["field sphere", "size 0"])
field("size-5000.field", "size 5000 (10^11 samples)", r":4: size 5000 is out of range \(an integer, 2 \.\. 1024\)",
      ["field sphere", "size 5000"])
field("size-fraction.field", "size 3.5", r":4: size 3\.5 is out of range \(an integer, 2 \.\. 1024\)", ["field torus", "size 3.5"])
field("bounds-reversed.field", "bounds 1 -1", r":4: bounds: LO must be less than HI", ["field sphere", "bounds 1 -1"])
field("bounds-nan.field", "a NaN bound", r":4: number out of range \(NaN, Inf or overflow\): 'nan'", ["field gyroid", "bounds nan 1"])
field("bounds-overflow.field", "a bound of 1e999", r":4: number out of range \(NaN, Inf or overflow\): '1e999'", ["field gyroid", "bounds -1 1e999"])
field("bounds-huge.field", "bounds of 1e308 (the field's sines would be NaN)", r":4: bounds must lie within \[-1e6, 1e6\]",
      ["field marschner_lobb", "bounds -1 1e308"])
field("unknown-key.field", "a key .field files do not have",
      r":4: unknown key 'colour' \(field, size, bounds, radius, radii, periods, alpha, fm\)", ["field sphere", "colour red"])
field("missing-field.field", "no 'field' line", r": no 'field' line \(field sphere\|torus\|gyroid\|marschner_lobb\)", ["size 32", "radius 0.5"])
field("other-kind-key.field", "periods on a sphere", r":5: 'periods' is for gyroid fields, not sphere", ["size 8", "field sphere", "periods 2"])
field("negative-radius.field", "a negative radius", r":4: sphere radius must be > 0", ["field sphere", "radius -0.5"])
field("duplicate-key.field", "two size lines", r":5: a second 'size' line \(the first is on line 4\)", ["field sphere", "size 8", "size 9"])
field("extra-value.field", "radii with three values", r":4: 'radii' takes 2 value\(s\), got 3", ["field torus", "radii 0.5 0.25 1"])
field("not-a-number.field", "a word where a number goes", r":4: not a number: 'big'", ["field marschner_lobb", "alpha big"])
field("two-fields.field", "two 'field' lines", r":4: a second 'field' line \(the first is on line 3\)", ["field sphere", "field torus"])
field("zero-fm.field", "f_M = 0", r":5: marschner_lobb fm must be > 0", ["field marschner_lobb", "alpha 0.25", "fm 0"])
