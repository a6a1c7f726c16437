#!/usr/bin/env python3
"""The radiosity benchmarks (bench/results/radiosity.json, Google Benchmark) as
a lockstep-table/1 file for BENCHMARKS.md (issue #33).

usage: radiosity_table.py RADIOSITY_JSON JSON_OUT

One row per frame (the Cornell box at a patch count, a form-factor method):
ms per whole frame (patches, form factors, solve, display) of the reference
(one thread) and of simd on 1 and 2 threads, and the speed-ups; the target
(simd >= 20x the reference on the Cornell box) is judged on the largest rays
frame, two threads. Written through JSON_OUT.tmp and a rename.
"""
import datetime
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import chartlib  # noqa: E402
import charts  # noqa: E402

COMMAND = ("bash bench/run.sh --only radiosity,page (./build/bench/lockstep_bench --benchmark_filter='^frame/radiosity/' "
           "--benchmark_min_time=0.2, then python3 bench/scripts/radiosity_table.py)")


def ms(b):
    return b["real_time"] * {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b.get("time_unit", "ns")]


def main():
    a = chartlib.args(__doc__)
    ctx, rows = charts.load(a.radiosity_json)
    rows = dict(rows)
    keys = chartlib.bench_keys(rows, r"frame/radiosity/([^/]+)/([^/]+)/threads:([0-9]+)", lambda m: m.group(1))
    body, largest = [], None
    for frame in keys:
        get = lambda impl, t: rows.get(f"frame/radiosity/{frame}/{impl}/threads:{t}")
        ref, s1, s2 = get("reference", 1), get("simd", 1), get("simd", 2)
        any_row = ref or s1 or s2
        patches = int(any_row["patches"]) if any_row and "patches" in any_row else 0
        up = lambda s: f"{ms(ref) / ms(s):.1f}x" if ref and s else ""
        body.append([frame, str(patches), f"{ms(ref):.1f}" if ref else "", f"{ms(s1):.1f}" if s1 else "",
                     f"{ms(s2):.1f}" if s2 else "", up(s1), up(s2)])
        if "rays" in frame and ref and s2 and (largest is None or patches > largest[0]):
            largest = (patches, ms(ref) / ms(s2))
    targets = []
    if largest:
        targets.append({"text": "simd >= 20x the reference on the Cornell box (the largest rays frame, 2 threads)",
                        "measured": f"{largest[1]:.1f}x at {largest[0]} patches", "met": largest[1] >= 20})
    doc = {
        "schema": "lockstep-table/1",
        "family": "radiosity",
        "order": 1,
        "title": "Frames: the Cornell box, ms per frame",
        "command": COMMAND,
        "date": ctx.get("date", "")[:10] or datetime.date.today().isoformat(),
        "machine": f"{ctx.get('num_cpus', '?')} cores, {ctx.get('mhz_per_cpu', '?')} MHz",
        "issue": 33,
        "note": ("corpus/radiosity/cornell_box.nff at 128 x 128: cut into patches (patch_area 8000, 2000, 500 mm^2), "
                 "form factors by rays (k = 2: 4 segments a pair) or by the hemicube (32 pixels), Gauss-Seidel to "
                 "1e-4, the display through the z-buffer: the whole frame, as `lockstep radiosity` runs it. Warm "
                 "frames (the simd row's session keeps its Embree device and the form-factor matrix's storage). "
                 "Equal error: both rows compute the same factors (each segment decided by the same test in "
                 "double: tests/radiosity_rows_test.cpp, 0 pairs differ)."),
        "columns": ["frame", "patches", "reference 1T ms", "simd 1T ms", "simd 2T ms", "speed-up 1T", "speed-up 2T"],
        "rows": body,
        "targets": targets,
    }
    chartlib.write_table(doc, a.json_out)


if __name__ == "__main__":
    main()
