#!/usr/bin/env bash
# `lockstep spd` against the SPD's own file:
#   check_scene.sh LOCKSTEP STEM SHARED_SPD_DIR OUT_DIR
# (SHARED_SPD_DIR: the build's default; $LOCKSTEP_SPD_DIR overrides it)
# STEM as ../shared/spd names its files (balls-3, tree-2-tess). Generates
# NAME --size N [--tess] and compares it with SHARED_SPD_DIR/STEM.nff by
# compare_nff.py (entities in order, numbers to the printed precision); says
# whether the bytes are identical too. Exit 77 (skipped) when the SPD's file
# is not there: a clone without ../shared.
set -uo pipefail
lockstep=$1 stem=$2 shared=$3 out=$4
# As the resolver reads it (registry/loaders.h spd_dir): $LOCKSTEP_SPD_DIR first.
shared=${LOCKSTEP_SPD_DIR:-$shared}
expected=$shared/$stem.nff
if [[ ! -f $expected ]]; then
  echo "skipped: $expected is not there (a clone without ../shared)"
  exit 77
fi
base=${stem%-tess} tess=()
[[ $base != "$stem" ]] && tess=(--tess)
name=${base%-*} size=${base##*-}
# The PID in the name: spd.matches.X and spd.matches_corpus.X run the same stem,
# perhaps at once (ctest -j2), and each removes its file when done.
got=$out/spd-$stem-$$.nff
"$lockstep" spd "$name" --size "$size" "${tess[@]}" -o "$got" || { echo "FAIL: lockstep spd exited $?"; exit 1; }
python3 "$(dirname "$0")/compare_nff.py" "$expected" "$got" || exit 1
if cmp -s "$expected" "$got"; then echo "bytes: identical"; else echo "bytes: differ (within the printed precision)"; fi
rm -f "$got"
