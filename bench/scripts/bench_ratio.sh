#!/usr/bin/env bash
# The simd z-buffer against its reference on one thread, measured alternately
# (issue #7's 10x target on a machine whose speed drifts): ROUNDS times the
# reference's frames, then the simd's, 3 repetitions each; prints the best
# frame of each and their ratio per scene. On a KVM guest the drift over a
# minute is larger than the difference being measured, so alternating keeps the
# two sides under the same conditions.
#
#   bash bench/scripts/bench_ratio.sh [SCENE_REGEX [ROUNDS [SHADING]]]
#   bash bench/scripts/bench_ratio.sh 'sombrero-3|balls-3|shells-1' 4
set -euo pipefail
cd "$(dirname "$0")/../.."
scenes="${1:-sombrero-3|balls-3|shells-1}"
rounds="${2:-4}"
shading="${3:-flat}"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
ninja -C build lockstep_bench >/dev/null
B=./build/bench/lockstep_bench
for _ in $(seq 1 "$rounds"); do
  for impl in reference simd; do
    $B --benchmark_filter="frame/zbuffer/($scenes)/$shading/$impl/threads:1/" \
      --benchmark_repetitions=3 --benchmark_min_time=0.2 --benchmark_format=json 2>/dev/null
  done
done | python3 -c '
import json, sys, collections
text = sys.stdin.read()
dec = json.JSONDecoder()
best = collections.defaultdict(lambda: float("inf"))
i = 0
while i < len(text):
    while i < len(text) and text[i].isspace():
        i += 1
    if i >= len(text):
        break
    doc, i = dec.raw_decode(text, i)
    for b in doc["benchmarks"]:
        if b.get("run_type") != "iteration":
            continue
        parts = b["name"].split("/")
        ms = b["real_time"] * {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b["time_unit"]]
        best[(parts[2], parts[4])] = min(best[(parts[2], parts[4])], ms)
for scene in sorted({k[0] for k in best}):
    r, s = best[(scene, "reference")], best[(scene, "simd")]
    print(f"{scene}: reference {r:.2f} ms, simd {s:.3f} ms, {r / s:.2f}x")
'
