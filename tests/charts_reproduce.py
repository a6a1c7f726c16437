#!/usr/bin/env python3
"""The chart and table scripts reproduce the tables committed in bench/results/ from the
study outputs committed beside them (same columns, same rows): a script that
no longer reads its CSV, or reads it differently, fails here rather than on
the next re-measurement. Charts go to a scratch directory (gnuplot).

usage: charts_reproduce.py SOURCE_DIR SCRATCH_DIR
"""
import json
import os
import subprocess
import sys

CASES = [  # script, study output, the table it wrote, whether it draws a chart (OUT_DIR argument)
    ("ray_trace_chart.py", "ray_trace_acne.csv", "ray_trace_acne.json", True),
    ("ray_trace_depth_chart.py", "ray_trace_depth.csv", "ray_trace_depth.json", True),
    ("shadow_map_chart.py", "shadow_map.csv", "shadow_map.json", True),
    ("cones_chart.py", "cones_tess.csv", "cones_tess.json", True),
    ("embree_raw_table.py", "embree_raw.csv", "embree_raw.json", False),
    ("ray_trace_bench_table.py", "ray_trace.json", "ray_trace_rates.json", False),
    ("shadows_bench_table.py", "shadows_bench.json", "shadows.json", False),
]


def main():
    src, scratch = sys.argv[1], sys.argv[2]
    os.makedirs(scratch, exist_ok=True)
    failed = 0
    for script, csv, table, chart in CASES:
        out = os.path.join(scratch, table)
        args = [os.path.join(src, "bench/results", csv)] + ([scratch] if chart else []) + [out]
        r = subprocess.run([sys.executable, os.path.join(src, "bench", "scripts", script), *args], capture_output=True, text=True,
                           cwd=src)
        if r.returncode != 0:
            print(f"FAIL {script}: exit {r.returncode}\n{r.stderr[-2000:]}")
            failed += 1
            continue
        want = json.load(open(os.path.join(src, "bench/results", table)))
        got = json.load(open(out))
        for key in ("columns", "rows"):
            if want.get(key) != got.get(key):
                print(f"FAIL {script}: {key} of {out} differ from bench/results/{table}")
                for a, b in zip(want.get(key) or [], got.get(key) or []):
                    if a != b:
                        print(f"  committed {a}\n  now       {b}")
                        break
                failed += 1
                break
        else:
            print(f"ok   {script}: {len(got['rows'])} rows as committed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
