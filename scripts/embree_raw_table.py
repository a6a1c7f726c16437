#!/usr/bin/env python3
"""The embree row against raw Embree (tools/embree_raw.cpp) as a
lockstep-table/1 file for BENCHMARKS.md (issue #22); bench/targets.json
evaluates the issue's targets over it.

usage: embree_raw_table.py EMBREE_RAW_CSV JSON_OUT

EMBREE_RAW_CSV: the tool's CSV, one run per scene (each a fresh process, so
that first_ms is that scene's one-shot render), headers repeated or not.
Written through JSON_OUT.tmp and a rename.
"""
import datetime
import json
import os
import sys

COMMAND = ("ninja -C build lockstep_embree_raw && for s in balls-1 balls-3 balls-5; do ./build/lockstep_embree_raw "
           "--reps 7 ../shared/spd/$s.nff; done > bench/results/embree_raw.csv && python3 scripts/embree_raw_table.py "
           "bench/results/embree_raw.csv bench/results/embree_raw.json")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    head, recs = None, []
    with open(sys.argv[1]) as fh:
        for n, line in enumerate(fh, 1):
            line = line.strip()
            if not line:
                continue
            if line.startswith("scene,"):
                head = line.split(",")
                continue
            if head is None:
                sys.exit(f"{sys.argv[1]}:{n}: a row before the header")
            r = dict(zip(head, line.split(",")))
            try:
                recs.append({k: (v if k == "scene" else float(v)) for k, v in r.items()})
            except ValueError as e:
                sys.exit(f"{sys.argv[1]}:{n}: {e}")
    rows = []
    for r in recs:
        scene = r["scene"].removesuffix(".nff")
        first = r["first_ms"]
        rows.append([scene, int(r["spheres"]), round(r["raw_build_ms"], 3), round(r["row_build_ms"], 3),
                     round(r["row_build_ms"] / r["raw_build_ms"], 2), round(r["raw8_mrays"], 2),
                     round(r["raw1_mrays"], 2), round(r["row_unshaded_mrays"], 2),
                     round(100 * r["row_unshaded_mrays"] / r["raw8_mrays"], 1), round(r["row_shaded_ms"], 1),
                     round(first, 1) if first == first else None,
                     round(first / r["row_shaded_ms"], 2) if first == first else None,
                     round(r["device_ms"], 3)])
    size = int(recs[0]["size"]) if recs else 0
    doc = {
        "schema": "lockstep-table/1",
        "family": "ray_cast",
        "order": 20,
        "title": "The embree row against raw Embree",
        "command": COMMAND,
        "date": datetime.date.today().isoformat(),
        "machine": "2 cores, shared with other builds during the run (load 13-18)",
        "issue": 22,
        "note": (f"tools/embree_raw.cpp, one thread, {size} x {size} primary rays, medians of 7 runs taken in turn (raw, "
                 f"row, raw, row ...). raw: the same spheres as RTC_GEOMETRY_TYPE_SPHERE_POINT in the eye's frame "
                 f"and the ground polygon's triangles (no filter), default build quality and scene flags, rtcCommitScene alone timed; rtcIntersect8 over rows of 8 "
                 f"pixels (coherent context) and rtcIntersect1; no shading. row: the ray_cast embree row "
                 f"(optimized/ray_cast_embree.cpp) with shading off (render_unshaded: its own traversal and hit "
                 f"refinement), rays/s over the frame minus its BVH build; its build as FrameStats reports it (the "
                 f"geometry set-up included, as a render pays it); warm = the shaded row on a kept device; one-shot = "
                 f"the first render of a fresh process, device included. device_ms: making a further device once one "
                 f"exists. Since issue #22: one device per session (the benchmarks' embree rows keep it; the CLI renders "
                 f"once per process; verify and the properties still make one per render), built-in spheres up to 1e6 "
                 f"radii from the eye (was 256: balls-4 and balls-5 went almost whole into a double-precision user "
                 f"geometry), RTC_SCENE_FLAG_ROBUST only with triangles, no sidedness filter on triangles every primary ray "
                 f"sees from the front (the balls scenes' ground). Noise: this run at load 12 (other helpers' builds); "
                 f"one beside the full ctest suite (rates 4x lower) gave row / raw8 100 / 88 / 98%, build 1.15x, "
                 f"one-shot / warm 1.18 / 2.29 / 1.14; one before the triangle-filter change 64% / 76% on balls-1 / "
                 f"balls-3. A 10% target is within this machine's run-to-run "
                 f"spread under load, so read the ratios as +-15%. What is left on the small scenes is per-ray work "
                 f"outside Embree (the double camera ray, clear_packet, to_hit and the refinement, the image write): "
                 f"balls-1's 10 spheres cost Embree almost nothing to traverse."),
        "columns": ["scene", "spheres", "raw build ms", "row build ms", "build row / raw", "raw rtcIntersect8 Mrays/s",
                    "raw rtcIntersect1 Mrays/s", "row unshaded Mrays/s", "row / raw8 %", "row shaded warm ms",
                    "one-shot ms", "one-shot / warm", "device_ms"],
        "rows": rows,
    }
    tmp = sys.argv[2] + ".tmp"
    with open(tmp, "w") as fh:
        json.dump(doc, fh, indent=1)
        fh.write("\n")
    os.replace(tmp, sys.argv[2])


if __name__ == "__main__":
    main()
