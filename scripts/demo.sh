#!/usr/bin/env bash
# Fresh machine to first result: install dependencies, build, and verify every
# implementation against the reference on the bundled corpus (report in ./lockstep-report).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
ninja -C build lockstep
./build/lockstep verify --report lockstep-report
