#!/usr/bin/env bash
# A clone without ../shared: the SPD scenes are generated and the real volumes'
# frames and tests skipped, and everything still ends with exit 0.
#   without_shared.sh LOCKSTEP_BENCH VOLUME_IO_TEST [VOLPACK_TEST]
# Points LOCKSTEP_SPD_DIR and LOCKSTEP_VOLUMES_DIR at an empty folder, then runs
#   * lockstep_bench on SPD frames of two families (ray_cast, zbuffer) and the
#     volume families (whose real-volume frames must be gone, with one note);
#   * the volume tests, whose real-data parts must skip with a message.
set -uo pipefail
bench=$1 vio=$2 vp=${3:-}
empty=$(mktemp -d)
log=$(mktemp)
trap 'rm -rf "$empty" "$log"' EXIT
export LOCKSTEP_SPD_DIR=$empty LOCKSTEP_VOLUMES_DIR=$empty LOCKSTEP_NO_SAVE=1
fail() { echo "FAIL: $*"; sed 's/^/    /' "$log" | tail -40; exit 1; }

filter='frame/ray_cast/(balls-2|tetra-3)/simd/threads:1/|frame/zbuffer/(rings-1-tess|teapot-2)/flat/simd/threads:1/|frame/(volume|iso|splat|marching_cubes)/(cthead|ch2)|frame/marching_cubes/gyroid-256/simd/threads:2/'
"$bench" --benchmark_filter="$filter" --benchmark_min_time=0.01 >"$log" 2>&1 || fail "lockstep_bench exited $?"
for name in frame/ray_cast/balls-2/simd frame/ray_cast/tetra-3/simd frame/zbuffer/rings-1-tess/flat/simd \
            frame/zbuffer/teapot-2/flat/simd frame/marching_cubes/gyroid-256/simd; do
  grep -q "^$name/" "$log" || fail "lockstep_bench did not run $name (its scene should have been generated)"
done
grep -Eq "^frame/[a-z_]+/(cthead|ch2)" "$log" && fail "lockstep_bench ran a real-volume frame without the volume"
[[ $(grep -c "note: cthead.nhdr or ch2.nhdr not in" "$log") == 1 ]] || fail "expected one note about the missing volumes"
echo "ok: lockstep_bench: SPD frames on generated scenes, volume frames skipped with one note"

"$vio" >"$log" 2>&1 || fail "volume_io_test exited $?"
grep -q "has no real volumes" "$log" || fail "volume_io_test did not say it skipped the real volumes"
echo "ok: volume_io_test: $(grep -c '\[  SKIPPED \]' "$log") skipped line(s), exit 0"
if [[ -n $vp ]]; then
  "$vp" >"$log" 2>&1 || fail "volpack_test exited $?"
  grep -Eq "is not there: Agree|no volpack row" "$log" || fail "volpack_test did not say it left the CT frames out"
  echo "ok: volpack_test: exit 0, CT frames left out"
fi
