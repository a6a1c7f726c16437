#!/usr/bin/env bash
# Fuzz the NFF and volume readers under AddressSanitizer + UndefinedBehaviorSanitizer.
#
# Configures build-asan (-DLOCKSTEP_SANITIZE=ON, no benchmarks), builds only the
# fuzz test binaries and runs them: props/fuzz_nff.cpp (random bytes, token
# soups, mutated SPD files; parse_nff must return a consistent Scene or throw
# InputError) and props/fuzz_volume.cpp (mutated NRRD files, attached and
# detached, and .field files; read_volume must return a valid Volume or throw
# InputError; mutated transfer functions, tests/bad-tf and corpus/tf: a valid one or
# InputError; mutated texture scenes, tests/bad-texscenes and corpus/textures:
# a valid scene or InputError: our header checks and Teem's reading both run under the
# sanitizers). Any memory error, leak or undefined behaviour aborts the run.
# Seeds: random here (LOCKSTEP_RANDOM_SEED=1; ctest runs the fixed ones,
# props/driver/rc_run.h); each property prints its seed and replay line first.
#   bash scripts/fuzz.sh                       # 5000 cases per property
#   LOCKSTEP_DEEP=1 bash scripts/fuzz.sh       # 50000 cases per property
#   LOCKSTEP_RANDOM_SEED= bash scripts/fuzz.sh # the fixed seeds ctest runs
#   RC_PARAMS="seed=123" bash scripts/fuzz.sh  # replay a seed
# Extra arguments go to both test binaries (e.g. --gtest_filter=FuzzNff.TokenSoup).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLOCKSTEP_SANITIZE=ON \
  -DLOCKSTEP_BUILD_BENCH=OFF >/dev/null
ninja -C build-asan lockstep_fuzz_nff lockstep_fuzz_volume
export LOCKSTEP_RANDOM_SEED="${LOCKSTEP_RANDOM_SEED-1}"
export ASAN_OPTIONS="${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:strict_string_checks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
# Teem's own small leaks on some bad headers (scripts/lsan-teem.supp says which and why).
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$PWD/scripts/lsan-teem.supp:print_suppressions=0}"
./build-asan/props/lockstep_fuzz_nff "$@"
./build-asan/props/lockstep_fuzz_volume "$@"
