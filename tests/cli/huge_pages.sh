#!/usr/bin/env bash
# Large buffers on transparent huge pages (core/large_buffer.h, issue #35):
# the fallback path (4 KiB pages: where the kernel's mode is `never`, or
# LOCKSTEP_HUGE_PAGES=0) writes the same bytes as the huge-page path.
#   huge_pages.sh LOCKSTEP SCENE.nff VOLUME.nhdr OUT_DIR
# (VOLUME: 8-bit samples; the marching cubes run on a 128^3 gyroid written
# here, whose 8 MiB of samples and intermediates take the huge-page path.)
# Checks:
#   - --version states the kernel's mode, as /sys/kernel/mm/transparent_hugepage/enabled has it;
#   - a 1024^2 z-buffer render (.exr), a marching-cubes mesh (.ply) and a volume
#     rendering (.exr) are the same either way (the mesh byte for byte, the
#     images pixel for pixel: an EXR's header holds the time it was written);
#   - the stats line gives the frame's page faults and system time;
#   - where the mode is always or madvise, the huge-page path really differs:
#     the 1024^2 frame (16 MiB of colour, 4 MiB of depth) takes under half the
#     page faults of the fallback's (measured: about 800-1,400 against 5,400).
set -uo pipefail
L=$1 scene=$2 volume=$3 out=$4
fail() { echo "FAIL: $*"; exit 1; }
mkdir -p "$out"
thp=/sys/kernel/mm/transparent_hugepage/enabled
mode=unavailable
[[ -r $thp ]] && mode=$(sed -E 's/.*\[([a-z]+)\].*/\1/' "$thp")
"$L" --version | grep -q "transparent huge pages $mode " || fail "--version does not state the mode '$mode': $("$L" --version | grep memory)"

faults() { sed -nE 's/.*\(([0-9]+) page faults, system [0-9.]+ s; the call so far: [0-9]+, [0-9.]+ s\).*/\1/p' <<< "$1"; }
run() {  # NAME ENV... -- ARGS...: runs, keeps the stats line in $line
  local name=$1; shift
  local envs=()
  while [[ $1 != -- ]]; do envs+=("$1"); shift; done
  shift
  line=$(env "${envs[@]}" "$L" "$@" 2>&1 >/dev/null) || fail "$name: exit $?: $line"
  grep -qE '\([0-9]+ page faults, system [0-9.]+ s; the call so far' <<< "$line" || fail "$name: no page faults in the stats line: $line"
}
printf 'field gyroid\nsize 128\nperiods 3\n' > "$out/gyroid-128.field"
declare -A hp_faults lp_faults
for what in zbuffer isosurface volume; do
  case $what in
    zbuffer) args=(render "$scene" --algo zbuffer --impl simd --threads 1 --size 1024x1024) ext=exr ;;
    isosurface) args=(isosurface "$out/gyroid-128.field" --iso 0 --impl simd --threads 1) ext=ply ;;
    volume) args=(volume "$volume" --tf ct-skin --impl simd --threads 1 --size 1024x1024) ext=exr ;;
  esac
  run "$what (huge pages)" LOCKSTEP_NO_SAVE=1 -- "${args[@]}" -o "$out/$what-huge.$ext"
  hp_faults[$what]=$(faults "$line")
  run "$what (4 KiB pages)" LOCKSTEP_NO_SAVE=1 LOCKSTEP_HUGE_PAGES=0 -- "${args[@]}" -o "$out/$what-small.$ext"
  lp_faults[$what]=$(faults "$line")
  # An EXR's header holds the time it was written: its pixels are compared.
  if [[ $ext == exr ]]; then
    d=$("$L" diff "$out/$what-huge.$ext" "$out/$what-small.$ext" --fail 0 --warn 0) && grep -qE 'max error +0 ' <<< "$d" ||
      fail "$what: the huge-page and 4 KiB-page images differ: $d"
  else
    cmp -s "$out/$what-huge.$ext" "$out/$what-small.$ext" ||
      fail "$what: the huge-page and 4 KiB-page outputs differ ($out/$what-huge.$ext, $out/$what-small.$ext)"
  fi
  echo "$what: same output either way; frame page faults ${hp_faults[$what]} (huge pages) and ${lp_faults[$what]} (4 KiB pages)"
done
if [[ $mode == always || $mode == madvise ]]; then
  ((2 * ${hp_faults[zbuffer]} < ${lp_faults[zbuffer]})) ||
    fail "zbuffer 1024^2: ${hp_faults[zbuffer]} page faults with huge pages, ${lp_faults[zbuffer]} without: not under half"
else
  echo "the kernel's mode is $mode: both paths use 4 KiB pages (not compared)"
fi
echo "huge_pages: ok"
