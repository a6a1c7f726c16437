#!/usr/bin/env bash
# The peer rows' modules (optimized/peer_module.h; issue #21, "One-shot cost").
#   peer_modules.sh LOCKSTEP SCENE.nff VOLUME FIELD OUT_DIR PEER...
# PEER: the modules this build made (llvmpipe, vtk, volpack). Checks:
#   - the binary links none of the peer libraries (ldd);
#   - --version names every built row and its version, and `diff` runs,
#     without loading any module or peer library (LD_DEBUG=files lists every
#     object the dynamic loader opens);
#   - a row's run opens its module (and its library) and writes its output;
#   - LOCKSTEP_PEER_DIR is searched first: a broken module there makes the row
#     fail with exit 2, one stderr line naming the module and dlerror()'s
#     words, and no output file; a good copy there is used.
set -uo pipefail
L=$1 scene=$2 volume=$3 field=$4 out=$5
shift 5
peers=("$@")
fail() { echo "FAIL: $*"; exit 1; }
mkdir -p "$out"
libs='osmesa|libLLVM|libvtk|volpack'

ldd "$L" | grep -Ei "$libs" && fail "ldd: $L links a peer library"
echo "ok: ldd lists no peer library"

LD_DEBUG=files "$L" --version >"$out/version.txt" 2>"$out/version.trace" || fail "--version exit $?"
grep -Ei "file=[^ ]*($libs|lockstep_peer)" "$out/version.trace" && fail "--version loaded a peer"
golden=$(dirname "$(dirname "$scene")")/golden/balls-1.exr
LD_DEBUG=files "$L" diff "$golden" "$golden" >/dev/null 2>"$out/diff.trace" || fail "diff exit $?"
grep -Ei "file=[^ ]*($libs|lockstep_peer)" "$out/diff.trace" && fail "diff loaded a peer"
echo "ok: --version and diff load no peer module or library"

# One run of each built row: what it runs, the version --version must show, the library it loads.
run_row() {
  case $1 in
    llvmpipe) echo render "$scene" --algo zbuffer --impl llvmpipe --shading flat --size 64x48 -o "$2.png" ;;
    vtk) echo isosurface "$field" --iso 0.5 --impl vtk -o "$2.ply" ;;
    volpack) echo volume "$volume" --tf ramp --impl volpack --size 32x32 -o "$2.png" ;;
  esac
}
declare -A version_re=([llvmpipe]='llvmpipe row: built \(OSMesa: llvmpipe \(LLVM [0-9.]+.*Mesa [0-9.]+'
                       [vtk]='vtk row: built \(VTK 9\.' [volpack]='volpack row: built \(VolPack')
declare -A lib_re=([llvmpipe]='libOSMesa' [vtk]='libvtkFiltersCore' [volpack]='libvolpack')
declare -A ext=([llvmpipe]=png [vtk]=ply [volpack]=png)
for p in "${peers[@]}"; do
  grep -Eq "${version_re[$p]}" "$out/version.txt" || fail "--version does not name the $p row: $(cat "$out/version.txt")"
  o=$out/peer-$p
  rm -f "$o.${ext[$p]}"
  # shellcheck disable=SC2046
  LD_DEBUG=files "$L" $(run_row "$p" "$o") >/dev/null 2>"$o.trace" || fail "$p row: exit $?"
  [[ -s $o.${ext[$p]} ]] || fail "$p row: no output"
  grep -Eq "file=[^ ]*lockstep_peer_$p\.so" "$o.trace" || fail "$p row did not open lockstep_peer_$p.so"
  grep -Eq "file=[^ ]*${lib_re[$p]}" "$o.trace" || fail "$p row did not load ${lib_re[$p]}"
  echo "ok: $p: --version names it; its run opens lockstep_peer_$p.so and ${lib_re[$p]}"

  # LOCKSTEP_PEER_DIR first: a broken module, then a good copy.
  d=$out/peer-dir-$p
  rm -rf "$d" && mkdir -p "$d"
  echo "not a shared object" >"$d/lockstep_peer_$p.so"
  rm -f "$o.${ext[$p]}"
  # shellcheck disable=SC2046
  LOCKSTEP_PEER_DIR=$d "$L" $(run_row "$p" "$o") >/dev/null 2>"$o.err"
  rc=$?
  [[ $rc == 2 ]] || fail "$p broken module: exit $rc, expected 2: $(cat "$o.err")"
  [[ $(grep -c . "$o.err") == 1 ]] || fail "$p broken module: not one stderr line: $(cat "$o.err")"
  grep -Eq "$d/lockstep_peer_$p\.so: cannot open peer module: .*(file too short|invalid ELF header)" "$o.err" ||
    fail "$p broken module: the error names neither the module nor dlerror's words: $(cat "$o.err")"
  [[ -e $o.${ext[$p]} ]] && fail "$p broken module: output left behind"
  echo "ok: $p: a broken module in LOCKSTEP_PEER_DIR: $(cat "$o.err")"
  cp "$(dirname "$L")/lockstep_peer_$p.so" "$d/"
  # shellcheck disable=SC2046
  LD_DEBUG=files LOCKSTEP_PEER_DIR=$d "$L" $(run_row "$p" "$o") >/dev/null 2>"$o.trace" || fail "$p copy in LOCKSTEP_PEER_DIR: exit $?"
  grep -Eq "file=$d/lockstep_peer_$p\.so" "$o.trace" || fail "$p: the copy in LOCKSTEP_PEER_DIR was not the one opened"
  echo "ok: $p: LOCKSTEP_PEER_DIR's copy is the one opened"
done
echo "ok: ${#peers[@]} peer modules"
