#!/usr/bin/env python3
"""The ray-tracing benchmarks (bench/results/ray_trace.json, Google Benchmark)
as a lockstep-table/1 file for BENCHMARKS.md (issue #22).

usage: ray_trace_bench_table.py RAY_TRACE_JSON JSON_OUT

One row per scene and depth: total rays per second (primary + shadow +
secondary, the rays_per_s counter) of the reference (one thread; at 128^2,
heavy_for_reference) and of embree on 1 and 2 threads, embree / reference
on one thread, and the mix of rays embree traced (primary / shadow / reflect /
refract per pixel). A "lockstep_spliced" string in the JSON's context (rows
re-run on their own and spliced in) is appended to the note. Written through
JSON_OUT.tmp and a rename.
"""
import datetime
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import chartlib  # noqa: E402
import charts  # noqa: E402

COMMAND = ("./build/bench/lockstep_bench --benchmark_filter='^frame/ray_trace/' --benchmark_out=bench/results/ray_trace.json "
           "--benchmark_out_format=json --benchmark_min_time=0.2 --benchmark_repetitions=3 "
           "--benchmark_report_aggregates_only=true && python3 bench/scripts/ray_trace_bench_table.py bench/results/ray_trace.json "
           "bench/results/ray_trace_rates.json")


def rate(x):
    return "" if x is None else (f"{x / 1e6:.2f}M" if x >= 1e6 else f"{x / 1e3:.0f}k")


def main():
    a = chartlib.args(__doc__)
    ctx, rows = charts.load(a.ray_trace_json)
    rows = dict(rows)
    keys = chartlib.bench_keys(rows, r"frame/ray_trace/([^/]+)/depth([0-9]+)/([^/]+)/threads:([0-9]+)",
                               lambda m: (m.group(1), int(m.group(2))))
    order = ["balls-3", "balls-4", "balls-5", "shells-1", "tetra-3", "mount-3", "gears-2"]
    keys.sort(key=lambda k: (order.index(k[0]) if k[0] in order else 99, k[0], k[1]))
    body = []
    left_out = []
    for scene, depth in keys:
        def get(impl, t, c="rays_per_s"):
            b = rows.get(f"frame/ray_trace/{scene}/depth{depth}/{impl}/threads:{t}")
            return b.get(c) if b else None
        ref, e1, e2 = get("reference", 1), get("embree", 1), get("embree", 2)
        if ref is None:
            left_out.append(f"{scene} depth {depth}")
        mix = ""
        if e1:
            prim = get("embree", 1, "primary_per_s")
            if prim:
                mix = " / ".join(f"{get('embree', 1, k + '_per_s') / prim:.2f}" for k in
                                 ("primary", "shadow", "reflect", "refract"))
        body.append([scene, str(depth), rate(ref), rate(e1), rate(e2),
                     f"{e1 / ref:.0f}x" if ref and e1 else "", mix])
    doc = {
        "schema": "lockstep-table/1",
        "family": "ray_trace",
        "order": 20,
        "title": "Frames: total rays per second",
        "command": COMMAND,
        "date": ctx.get("date", "")[:10] or datetime.date.today().isoformat(),
        "machine": f"{ctx.get('num_cpus', '?')} cores, {ctx.get('mhz_per_cpu', '?')} MHz",
        "issue": 22,
        "note": ("512 x 512 (the reference at 128 x 128: brute force costs the same for every ray, so rays/s carries "
                 "over), medians of 3 repetitions; rays = primary + shadow + reflected + refracted (the frame's "
                 "rays_per_s counter; per kind: primary_per_s .. refract_per_s). The reference is left out on balls-5 "
                 "(66k spheres: about a minute per 128^2 frame here): " + (", ".join(left_out) or "nothing") + ". "
                 "The machine's 2 cores were shared with other builds during the run (load 13-18"
                 + (" for the reference rows" if ctx.get("lockstep_spliced") else "") + "): 2-thread figures "
                 "in particular are what the scheduler gave, not what the code can do. mix: rays of each kind per "
                 "primary ray (primary / shadow / reflect / refract), embree, one thread."
                 + (" " + ctx["lockstep_spliced"] if ctx.get("lockstep_spliced") else "")),
        "columns": ["scene", "depth", "reference 1T rays/s", "embree 1T rays/s", "embree 2T rays/s",
                    "embree / reference (1T)", "mix"],
        "rows": body,
    }
    chartlib.write_table(doc, a.json_out)


if __name__ == "__main__":
    main()
