#!/usr/bin/env python3
"""The embree row against raw Embree (bench/timing/embree_raw.cpp) as a
lockstep-table/1 file for BENCHMARKS.md (issue #22); bench/targets.json
evaluates the issue's targets over it.

usage: embree_raw_table.py EMBREE_RAW_CSV JSON_OUT

EMBREE_RAW_CSV: the tool's CSV, one run per scene and process (each a fresh
process, so that first_ms is that scene's one-shot render), headers repeated or
not. A scene run more than once (in separate processes) is reported by the
median of each figure over its runs.
Written through JSON_OUT.tmp and a rename.
"""
import datetime
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import chartlib  # noqa: E402

COMMAND = ("ninja -C build lockstep_embree_raw && for run in 1 2 3; do for s in balls-1 balls-3 balls-5; do "
           "./build/bench/lockstep_embree_raw --reps 7 --clock cpu ../shared/spd/$s.nff; done; done > bench/results/embree_raw.csv "
           "&& python3 bench/scripts/embree_raw_table.py bench/results/embree_raw.csv bench/results/embree_raw.json")


def main():
    a = chartlib.args(__doc__)
    recs = chartlib.load_csv(a.embree_raw_csv, lambda r: {k: (v if k == "scene" else float(v)) for k, v in r.items()})
    # The row's rate against raw's within each process (the two alternate there,
    # so they share that process's conditions: the rates alone vary by 15%
    # between processes on this machine), then the median over the processes,
    # as for every other figure.
    for r in recs:
        r["vs_raw8"] = 100 * r["row_unshaded_mrays"] / r["raw8_mrays"]
        r["vs_robust"] = 100 * r["row_unshaded_mrays"] / r["raw8_robust_mrays"]
    runs = {}
    for r in recs:
        runs.setdefault(r["scene"], []).append(r)
    recs = [{k: (v[0]["scene"] if k == "scene" else statistics.median(x[k] for x in v)) for k in v[0]} | {"runs": len(v)}
            for v in runs.values()]
    rows = []
    for r in recs:
        scene = r["scene"].removesuffix(".nff")
        first = r["first_ms"]
        rows.append([scene, int(r["spheres"]), round(r["raw_build_ms"], 3), round(r["row_build_ms"], 3),
                     round(r["row_build_ms"] / r["raw_build_ms"], 2), round(r["raw8_mrays"], 2),
                     round(r["raw1_mrays"], 2), round(r["row_unshaded_mrays"], 2),
                     round(r["vs_raw8"], 1), round(r["raw8_robust_mrays"], 2),
                     round(r["vs_robust"], 1), round(r["row_shaded_ms"], 1),
                     round(first, 1) if first == first else None,
                     round(first / r["row_shaded_ms"], 2) if first == first else None,
                     round(r["device_ms"], 3), r["runs"]])
    size = int(recs[0]["size"]) if recs else 0
    nruns = "/".join(sorted({str(r["runs"]) for r in recs})) or "0"
    doc = {
        "schema": "lockstep-table/1",
        "family": "ray_cast",
        "order": 20,
        "title": "The embree row against raw Embree",
        "command": COMMAND,
        "date": datetime.date.today().isoformat(),
        "machine": chartlib.machine(),
        "issue": 22,
        "note": (f"bench/timing/embree_raw.cpp, one thread, {size} x {size} primary rays; each scene in {nruns} fresh processes, "
                 f"each the median of 7 runs taken in turn (raw, row, raw ROBUST, ...), timed by the thread's CPU "
                 f"time (--clock cpu: on a shared machine the wall clock counts waits for a core); the table gives the "
                 f"median over the processes, of each figure and of the row / raw ratios taken within each process. raw: the same spheres as RTC_GEOMETRY_TYPE_SPHERE_POINT in the eye's "
                 f"frame and the ground polygon's triangles (no filter), default build quality and scene flags, "
                 f"rtcCommitScene alone timed; rtcIntersect8 over rows of 8 pixels (coherent context) and "
                 f"rtcIntersect1; no shading. raw ROBUST: the same with RTC_SCENE_FLAG_ROBUST, which the row sets on "
                 f"any scene with triangles: it makes Embree's triangle test watertight at shared edges (a property "
                 f"the row is tested for, props watertight.shared_edge_rays) and its traversal conservative, for "
                 f"the spheres too, as the flag is per scene. row: the ray_cast embree row "
                 f"(optimized/ray_cast_embree.cpp) with shading off (render_unshaded: its own traversal and hit "
                 f"refinement), rays/s over the frame minus its BVH build; its build as FrameStats reports it (wall "
                 f"clock, the geometry set-up included, as a render pays it); warm = the shaded row on a kept device; "
                 f"one-shot = the first render of a fresh process, device included. device_ms: making a further "
                 f"device once one exists (wall). The row against raw ROBUST is what lockstep adds; raw against raw "
                 f"ROBUST is the price of watertight edges. Tried to avoid that price and not kept (A/B by CPU time "
                 f"against the row as it is, balls-1 / 3 / 5): the triangles in a ROBUST scene of their own instanced "
                 f"(identity) into a plain one, 76-83 / 88-91 / 89-91% of raw against 82-85 / 91-93 / 90-98% in the "
                 f"same two alternations (the instance costs what the flag did); the triangles' scene queried after "
                 f"the spheres' with the hit distance as tfar, medians of three 87 / 89 / 101% against 83 / 89 / 95% "
                 f"(within the spread, and every query of both rows would have to do it). This run: a quiet machine "
                 f"(load 0.7), where the same binary's rates still varied by up to 20% from process to process."),
        "columns": ["scene", "spheres", "raw build ms", "row build ms", "build row / raw", "raw rtcIntersect8 Mrays/s",
                    "raw rtcIntersect1 Mrays/s", "row unshaded Mrays/s", "row / raw8 %", "raw8 ROBUST Mrays/s",
                    "row / raw8 ROBUST %", "row shaded warm ms", "one-shot ms", "one-shot / warm", "device_ms",
                    "runs"],
        "rows": rows,
    }
    chartlib.write_table(doc, a.json_out)


if __name__ == "__main__":
    main()
