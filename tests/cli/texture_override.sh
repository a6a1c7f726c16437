#!/usr/bin/env bash
# `lockstep texture SCENE --texture SPEC --wrap W` draws what a scene with that
# texture and wrap mode in its own lines draws, and differs from SCENE as
# written (so the options are not ignored).
#   texture_override.sh LOCKSTEP TESTS_DIR OUT_DIR
set -uo pipefail
L=$1 T=$2 O=$3
base=$O/tx-override-base.exr over=$O/tx-override-options.exr want=$O/tx-override-file.exr
rm -f "$base" "$over" "$want"
fail() { echo "FAIL: $*"; exit 1; }
scene=$O/tx-override.texscene
# one-texel's quad with override.texscene's repeat, the 1x1 texture kept.
sed 's/^texture .*/texture checker 1 1/; /^wrap /d' "$T/texture/override.texscene" > "$scene"
"$L" texture "$scene" --filter aniso4 -o "$base" 2>/dev/null || fail "plain draw"
"$L" texture "$scene" --filter aniso4 --texture "checker 8 4" --wrap mirror -o "$over" 2>/dev/null || fail "draw with options"
"$L" texture "$T/texture/override.texscene" --filter aniso4 -o "$want" 2>/dev/null || fail "draw of override.texscene"
"$L" diff "$over" "$want" --fail 0 >/dev/null || fail "--texture/--wrap differ from the same lines in the scene"
"$L" diff "$base" "$want" --fail 0 >/dev/null && fail "--texture/--wrap changed nothing"
rm -f "$base" "$over" "$want" "$scene"
echo "ok: --texture and --wrap replace the scene's texture and wrap mode"
