#!/usr/bin/env bash
# compare_nff.py can fail: a number off by two units of its last printed digit,
# a missing line and a changed word are each caught; one unit of rounding and a
# residue such as 1.11022e-16 against 0 are not differences.
#   compare_selftest.sh SCENE.nff
set -uo pipefail
cmp=$(dirname "$0")/compare_nff.py ref=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
expect() {  # expect RC FILE WHAT
  python3 "$cmp" "$ref" "$2" >"$dir/log" 2>&1
  local rc=$?
  [[ $rc == "$1" ]] || { echo "FAIL: $3: exit $rc, expected $1"; cat "$dir/log"; exit 1; }
  echo "ok: $3 -> exit $rc: $(head -1 "$dir/log")"
}
expect 0 "$ref" "a file against itself"
sed '0,/^s 0.272166 /s//s 0.272167 /' "$ref" >"$dir/a.nff"
expect 0 "$dir/a.nff" "one unit of the last digit"
sed '0,/^s 0.272166 /s//s 0.272168 /' "$ref" >"$dir/b.nff"
expect 1 "$dir/b.nff" "two units of the last digit"
sed '0,/ 1.11022e-16 /s// 0 /' "$ref" >"$dir/c.nff"
expect 0 "$dir/c.nff" "a rounding residue against 0"
sed '$d' "$ref" >"$dir/d.nff"
expect 1 "$dir/d.nff" "a missing last line"
sed '0,/^s /s//p /' "$ref" >"$dir/e.nff"
expect 1 "$dir/e.nff" "an entity's word changed"
