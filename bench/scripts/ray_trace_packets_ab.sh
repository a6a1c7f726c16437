#!/usr/bin/env bash
# The embree ray tracer's frame, one ray at a time against Embree streams
# (issue #22): the frame/ray_trace benchmarks of two lockstep_bench binaries
# run in turn, ROUNDS times (one repetition each), into OUT_DIR/<tag>-<round>.json,
# then bench/results/ray_trace_packets.json (bench/scripts/ray_trace_packets_table.py).
# The machine's load drifts and is shared: alternating keeps the two sides under
# the same conditions, the table takes medians of CPU time (less sensitive to
# the load than wall time) and states the load seen.
#
#   bash bench/scripts/ray_trace_packets_ab.sh SINGLE_BENCH STREAM_BENCH [ROUNDS [FILTER [OUT_DIR]]]
#   e.g. SINGLE_BENCH built from the commit before the streams (git worktree).
set -euo pipefail
cd "$(dirname "$0")/../.."
single="$1"
stream="$2"
rounds="${3:-7}"
filter="${4:-^frame/ray_trace/[^/]+/depth(3|6)/embree/threads:1}"
out="${5:-/tmp/ray_trace_packets_ab}"
rm -rf "$out"
mkdir -p "$out"
for r in $(seq 1 "$rounds"); do
  for side in single stream; do
    bin="$single"
    [ "$side" = stream ] && bin="$stream"
    echo "$side $r $(cut -d' ' -f1 /proc/loadavg)" >>"$out/load.txt"
    "$bin" --benchmark_filter="$filter" --benchmark_min_time=0.2 --benchmark_repetitions=1 \
      --benchmark_out="$out/$side-$r.json" --benchmark_out_format=json >/dev/null
  done
done
python3 bench/scripts/ray_trace_packets_table.py "$out" bench/results/ray_trace_packets.json
