#!/usr/bin/env bash
# Build lockstep (Release, Ninja) and run every test: properties, replayed
# counterexamples, the CLI and bad-input tests, and `lockstep verify` on the corpus;
# then the NFF reader fuzz under AddressSanitizer + UBSan (scripts/fuzz.sh).
# Deep mode (>= 1000 cases per property): LOCKSTEP_DEEP=1 bash scripts/test.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
ninja -C build
ctest --test-dir build --output-on-failure --no-tests=error -j2 --timeout 900
# The NFF reader's fuzz properties again, under AddressSanitizer + UBSan.
bash scripts/fuzz.sh
