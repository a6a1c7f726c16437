#!/usr/bin/env bash
# Reproduce BENCHMARKS.md (about 15 minutes on 2 cores; run on an idle machine): build, run the benchmarks to bench/results/latest.json,
# measure accuracy against the oracle (props, to bench/results/accuracy.csv), and
# draw the charts into bench/charts/. Extra arguments go to lockstep_bench, e.g.
#   bash scripts/bench.sh --benchmark_filter='frame/balls-3'
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
ninja -C build lockstep_bench lockstep_props
mkdir -p bench/results bench/charts
{ lscpu | grep -E '^Model name' | sed 's/  */ /g'; echo "cores: $(nproc), $(free -g | awk '/Mem:/{print $2}') GiB"; \
  ./build/lockstep --version; } > bench/results/machine.txt
./build/bench/lockstep_bench --benchmark_out=bench/results/latest.json --benchmark_out_format=json \
  --benchmark_min_time=0.3 --benchmark_repetitions=3 --benchmark_report_aggregates_only=true "$@"
rm -f bench/results/accuracy.csv bench/results/stability.csv
LOCKSTEP_NO_SAVE=1 LOCKSTEP_ACCURACY_CSV=bench/results/accuracy.csv ./build/props/lockstep_props --gtest_filter='*Accuracy*' >/dev/null || true
# Where each method breaks (deep mode: >= 1000 cases per property).
LOCKSTEP_NO_SAVE=1 LOCKSTEP_DEEP=1 LOCKSTEP_STABILITY_CSV=bench/results/stability.csv \
  ./build/props/lockstep_props --gtest_filter='Stability*:Watertight*:Degenerate*' >/dev/null || true
LOCKSTEP_STABILITY_CSV=bench/results/stability.csv \
  python3 scripts/charts.py bench/results/latest.json bench/results/accuracy.csv bench/charts | tee bench/results/tables.md

# The page: BENCHMARKS.md from bench/results/ (scripts/benchmarks_md.py).
python3 scripts/benchmarks_md.py
