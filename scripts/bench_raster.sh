#!/usr/bin/env bash
# Reproduce the raster section of BENCHMARKS.md (issue #7; about 15 minutes on 2
# cores, run it on an idle machine): the 1024^2 frames of the zbuffer, scanline
# and painter families, every implementation at 1 and 2 threads, llvmpipe in the
# same run (one process per thread count: Mesa reads LP_NUM_THREADS once per
# process), then the raster study (speed against accuracy, failure maps) and
# the charts into bench/charts/, the tables into bench/results/raster_tables.md.
# Extra arguments go to lockstep_bench, e.g.
#   bash scripts/bench_raster.sh --benchmark_min_time=0.1
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
ninja -C build lockstep_bench lockstep_raster_study >/dev/null
mkdir -p bench/results bench/charts
R=bench/results
B=./build/bench/lockstep_bench
common=(--benchmark_out_format=json --benchmark_min_time=0.3 --benchmark_repetitions=3
        --benchmark_report_aggregates_only=true)
$B --benchmark_filter='frame/(zbuffer|scanline|painter)/.*/(reference|simd)/' \
  --benchmark_out=$R/raster_own.json "${common[@]}" "$@"
if ./build/lockstep --version | grep -q 'llvmpipe row: built'; then
  for t in 1 2; do
    $B --benchmark_filter="frame/zbuffer/.*/llvmpipe/threads:$t/" \
      --benchmark_out=$R/raster_llvmpipe_$t.json "${common[@]}" "$@"
  done
fi
python3 - "$R" <<'EOF'
import glob, json, sys
r = sys.argv[1]
parts = [json.load(open(p)) for p in [f"{r}/raster_own.json"] + sorted(glob.glob(f"{r}/raster_llvmpipe_*.json"))]
out = parts[0]
for p in parts[1:]:
    out["benchmarks"] += p["benchmarks"]
json.dump(out, open(f"{r}/raster.json", "w"), indent=1)
EOF
./build/props/lockstep_raster_study all > $R/raster_study.csv
python3 scripts/raster_charts.py $R/raster_study.csv $R/raster.json bench/charts | tee $R/raster_tables.md

# The page: BENCHMARKS.md from bench/results/ (scripts/benchmarks_md.py).
python3 scripts/benchmarks_md.py
