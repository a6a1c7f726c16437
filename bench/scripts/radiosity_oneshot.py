#!/usr/bin/env python3
"""Radiosity's one-shot cost: what one `lockstep radiosity` call costs beside the
warm frame of the benchmarks (issue #33; the guide: state the one-shot cost).

usage: radiosity_oneshot.py LOCKSTEP RADIOSITY_JSON JSON_OUT [RUNS]

For the Cornell box at 128 x 128 and each patch count of the benchmarks (patch
area 8000, 2000, 500 mm^2; rays, k = 2; simd, all cores): the whole call's wall
time (process start to exit, the image written to a temporary .exr), the
frame's wall time as the CLI reports it in that fresh process (patches, the
Embree BVH, form factors, solve, display), the BVH build it reports, and the
warm frame of RADIOSITY_JSON (lockstep_bench, simd 2T). The median of RUNS
(default 5) calls per figure, the frames alternated call by call. Writes a
lockstep-table/1 file through JSON_OUT.tmp and a rename.
"""
import datetime
import json
import os
import re
import statistics
import subprocess
import tempfile
import time

import chartlib

FRAMES = [("cornell-305-rays", "8000"), ("cornell-1078-rays", "2000"), ("cornell-4119-rays", "500")]
SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "corpus", "radiosity", "cornell_box.nff")


def warm_ms(bench_json, frame):
    with open(bench_json) as f:
        doc = json.load(f)
    # The median of the repetitions (the page's figure), else the one run.
    found = [b for b in doc["benchmarks"] if b["name"].startswith(f"frame/radiosity/{frame}/simd/threads:2/")]
    pick = [b for b in found if b.get("aggregate_name") == "median"] or [b for b in found if b.get("run_type") != "aggregate"]
    if not pick:
        return None
    return pick[0]["real_time"] * {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[pick[0].get("time_unit", "ns")]


def main():
    a = chartlib.args(__doc__)
    runs = int(a.runs or 5)
    calls = {name: [] for name, _ in FRAMES}
    frames = {name: [] for name, _ in FRAMES}
    builds = {name: [] for name, _ in FRAMES}
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "box.exr")
        for _ in range(runs):
            for name, area in FRAMES:
                t0 = time.perf_counter()
                p = subprocess.run([a.lockstep, "radiosity", SCENE, "--patch-area", area, "--size", "128x128", "-o", out],
                                   capture_output=True, text=True, check=True)
                calls[name].append(time.perf_counter() - t0)
                m = re.search(r"build ([0-9.]+) s, .* wall ([0-9.]+) s", p.stderr)
                builds[name].append(float(m.group(1)))
                frames[name].append(float(m.group(2)))
    body = []
    for name, area in FRAMES:
        warm = warm_ms(a.radiosity_json, name)
        call, frame = statistics.median(calls[name]) * 1e3, statistics.median(frames[name]) * 1e3
        body.append([name, f"{call:.0f}", f"{frame:.0f}", f"{statistics.median(builds[name]) * 1e3:.1f}",
                     f"{warm:.0f}" if warm else "", f"{frame / warm:.2f}x" if warm else ""])
    doc = {
        "schema": "lockstep-table/1",
        "family": "radiosity",
        "order": 2,
        "title": "One-shot: one `lockstep radiosity` call, ms",
        "command": f"python3 bench/scripts/radiosity_oneshot.py build/lockstep bench/results/radiosity.json "
                   f"bench/results/radiosity_oneshot.json {runs} (bash bench/run.sh --only radiosity,page)",
        "date": datetime.date.today().isoformat(),
        "machine": chartlib.machine(),
        "issue": 33,
        "note": (f"The Cornell box at 128 x 128, rays (k = 2), simd on both cores, the image to .exr; the median of "
                 f"{runs} calls. whole call: process start to exit; frame: the CLI's own wall time of the frame in "
                 "that fresh process (meshing, the Embree BVH, form factors, solve, display: its first touch of "
                 "the n^2 matrix included); BVH: the build it reports; warm: the benchmarks' frame (simd 2T, "
                 "buffers and the Embree device reused)."),
        "columns": ["frame", "whole call ms", "frame ms (fresh process)", "BVH build ms", "warm frame ms",
                    "fresh / warm"],
        "rows": body,
    }
    chartlib.write_table(doc, a.json_out)
    print(chartlib.markdown_table(doc["columns"], body))


if __name__ == "__main__":
    main()
