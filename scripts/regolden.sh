#!/usr/bin/env bash
# Re-render the corpus golden images (corpus/golden/<case>.exr) with the
# reference implementation only. Goldens are never made from optimized code.
# Run after a deliberate change to the reference or to a corpus scene, review the
# images (git diff shows which changed), and say why in the commit message.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
ninja -C build lockstep
./build/lockstep verify corpus --regolden "$@"
