#!/usr/bin/env bash
# OpenImageIO is a module opened on first use (io/oiio.h; issue #21,
# "One-shot cost"): its ~250 shared libraries are mapped only by a call that
# reads, writes or compares an image.
#   oiio_module.sh LOCKSTEP SCENE.nff FIELD OUT_DIR [BINARY...]
# BINARY: other binaries of the build that must not link OpenImageIO either
# (the property and benchmark binaries). Checks:
#   - ldd lists no libOpenImageIO for LOCKSTEP and each BINARY;
#   - --version names OpenImageIO's version (lockstep_oiio.version), and
#     --version, `spd` and an isosurface to .ply run without opening
#     lockstep_oiio.so or libOpenImageIO (LD_DEBUG=files lists every object
#     the dynamic loader opens);
#   - a render to .png and to .exr (OpenEXR and libpng directly, io/;
#     issue #31 item 6) opens neither the module nor the library, and their
#     files read back through it (diff); a render to .tif and diff open both;
#   - a broken module in LOCKSTEP_PEER_DIR (searched first): exit 2, one
#     stderr line naming the module and dlerror()'s words, no output file; a
#     good copy there is the one opened.
set -uo pipefail
L=$1 scene=$2 field=$3 out=$4
shift 4
fail() { echo "FAIL: $*"; exit 1; }
mkdir -p "$out"
dir=$(dirname "$L")
lib='libOpenImageIO'
loaded='file=[^ ]*(libOpenImageIO|lockstep_oiio\.so)'

for b in "$L" "$@"; do
  ldd "$b" | grep -F "$lib" && fail "ldd: $b links OpenImageIO"
done
echo "ok: ldd lists no $lib for $L $*"

[[ -s $dir/lockstep_oiio.so && -s $dir/lockstep_oiio.version ]] || fail "no lockstep_oiio.so and .version beside $L"
v=$(head -n1 "$dir/lockstep_oiio.version")
[[ $v =~ ^[0-9]+\.[0-9]+ ]] || fail "lockstep_oiio.version holds '$v', not a version"
LD_DEBUG=files "$L" --version >"$out/version.txt" 2>"$out/version.trace" || fail "--version exit $?"
grep -Fq "OpenImageIO $v)" "$out/version.txt" || fail "--version does not name OpenImageIO $v: $(head -n1 "$out/version.txt")"
grep -Eq 'file=[^ ]*libembree' "$out/version.trace" || fail "LD_DEBUG=files listed nothing (the check would pass vacuously)"
grep -E "$loaded" "$out/version.trace" && fail "--version loaded OpenImageIO"
echo "ok: --version names OpenImageIO $v without loading it"

rm -f "$out/balls.nff" "$out/mesh.ply"
LD_DEBUG=files "$L" spd balls --size 1 -o "$out/balls.nff" >/dev/null 2>"$out/spd.trace" || fail "spd exit $?"
[[ -s $out/balls.nff ]] || fail "spd wrote nothing"
grep -E "$loaded" "$out/spd.trace" && fail "spd loaded OpenImageIO"
LD_DEBUG=files "$L" isosurface "$field" --iso 0.5 -o "$out/mesh.ply" >/dev/null 2>"$out/iso.trace" || fail "isosurface exit $?"
[[ -s $out/mesh.ply ]] || fail "isosurface wrote nothing"
grep -E "$loaded" "$out/iso.trace" && fail "isosurface to .ply loaded OpenImageIO"
echo "ok: spd and isosurface (no image) load no OpenImageIO"

for ext in png exr; do
  rm -f "$out/a.$ext"
  LD_DEBUG=files "$L" render "$scene" --size 32x24 -o "$out/a.$ext" >/dev/null 2>"$out/render-$ext.trace" ||
    fail "render to .$ext exit $?"
  [[ -s $out/a.$ext ]] || fail "render wrote no a.$ext"
  grep -Eq 'file=[^ ]*libembree' "$out/render-$ext.trace" || fail "LD_DEBUG=files listed nothing for the render to .$ext"
  grep -E "$loaded" "$out/render-$ext.trace" && fail "render to .$ext loaded OpenImageIO"
done
echo "ok: render to .png and .exr load no OpenImageIO"

rm -f "$out/a.tif"
LD_DEBUG=files "$L" render "$scene" --size 32x24 -o "$out/a.tif" >/dev/null 2>"$out/render.trace" || fail "render exit $?"
[[ -s $out/a.tif ]] || fail "render wrote no a.tif"
LD_DEBUG=files "$L" diff "$out/a.png" "$out/a.png" >/dev/null 2>"$out/diff.trace" || fail "diff .png .png exit $?"
"$L" diff "$out/a.exr" "$out/a.tif" >/dev/null 2>&1 || fail "diff .exr .tif exit $?"
for t in render diff; do
  grep -Eq "file=[^ ]*lockstep_oiio\.so" "$out/$t.trace" || fail "$t did not open lockstep_oiio.so"
  grep -Eq "file=[^ ]*$lib" "$out/$t.trace" || fail "$t did not load $lib"
done
echo "ok: render to .tif and diff open lockstep_oiio.so and $lib, and the .exr agrees with the .tif"

d=$out/oiio-dir
rm -rf "$d" && mkdir -p "$d"
echo "not a shared object" >"$d/lockstep_oiio.so"
rm -f "$out/b.tif"
LOCKSTEP_PEER_DIR=$d "$L" render "$scene" --size 32x24 -o "$out/b.tif" >/dev/null 2>"$out/broken.err"
rc=$?
[[ $rc == 2 ]] || fail "broken module: exit $rc, expected 2: $(cat "$out/broken.err")"
[[ $(grep -c . "$out/broken.err") == 1 ]] || fail "broken module: not one stderr line: $(cat "$out/broken.err")"
grep -Eq "$d/lockstep_oiio\.so: cannot open OpenImageIO module: .*(file too short|invalid ELF header)" "$out/broken.err" ||
  fail "broken module: the error names neither the module nor dlerror's words: $(cat "$out/broken.err")"
[[ -n $(find "$out" -maxdepth 1 -name '*b.tif*') ]] && fail "broken module: output left behind"
echo "ok: a broken module in LOCKSTEP_PEER_DIR: $(cat "$out/broken.err")"
cp "$dir/lockstep_oiio.so" "$d/"
LD_DEBUG=files LOCKSTEP_PEER_DIR=$d "$L" render "$scene" --size 32x24 -o "$out/b.tif" >/dev/null 2>"$out/copy.trace" ||
  fail "copy in LOCKSTEP_PEER_DIR: exit $?"
grep -Eq "file=$d/lockstep_oiio\.so" "$out/copy.trace" || fail "the copy in LOCKSTEP_PEER_DIR was not the one opened"
[[ -s $out/b.tif ]] || fail "copy in LOCKSTEP_PEER_DIR: no b.tif"
echo "ok: LOCKSTEP_PEER_DIR's copy is the one opened"
