#!/usr/bin/env python3
"""Ray tracing's speed against accuracy: time and image error against the
ray-tree depth, for BENCHMARKS.md (issue #22).

usage: ray_trace_depth_chart.py DEPTH_CSV OUT_DIR JSON_OUT

DEPTH_CSV is the output of bench/timing/ray_trace_depth.cpp:
  ./build/bench/lockstep_ray_trace_depth ../shared/spd/balls-3.nff ... > bench/results/ray_trace_depth.csv
  python3 bench/scripts/ray_trace_chart.py ... (see COMMAND)

Writes OUT_DIR/ray_trace_depth.png (left: ms per frame against depth; right:
pixels off the deepest frame, the reference answer, in % of the image, and
pixels changed by each extra level, against depth; one curve per scene),
OUT_DIR/ray_trace_depth.dat, and JSON_OUT, a lockstep-table/1 file (through
JSON_OUT.tmp and a rename).
"""
import datetime
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import chartlib  # noqa: E402

COMMAND = ("ninja -C build lockstep_ray_trace_depth && ./build/bench/lockstep_ray_trace_depth "
           "../shared/spd/{balls-3,balls-4,balls-5,shells-1,tetra-3,mount-3,gears-2}.nff > "
           "bench/results/ray_trace_depth.csv && python3 bench/scripts/ray_trace_depth_chart.py "
           "bench/results/ray_trace_depth.csv bench/charts bench/results/ray_trace_depth.json")


def load(path):
    return chartlib.load_csv(path, lambda r: dict(
        scene=r["scene"], depth=int(r["depth"]), size=int(r["size"]), ms=float(r["ms"]), rays=int(r["rays"]),
        off=int(r["vs_answer"]), changed=int(r["vs_prev"]), pixels=int(r["pixels"])))


def pct(n, total):
    return "0" if n == 0 else f"{100 * n / total:.2g}%"


def main():
    a = chartlib.args(__doc__)
    rows = load(a.depth_csv)
    out, json_out = a.out_dir, a.json_out
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    depths = sorted({r["depth"] for r in rows})
    dmax = depths[-1]
    by = {(r["scene"], r["depth"]): r for r in rows}
    cols = ["scene"] + [f"depth {d}" for d in depths] + ["depth needed"]
    body = []
    needed = {}
    for s in scenes:
        cells = [s]
        for d in depths:
            r = by.get((s, d))
            if not r:
                cells.append("")
                continue
            c = f"{r['ms']:.0f} ms, {pct(r['off'], r['pixels'])} off"
            if d > 1:
                c += f" ({r['changed']} px changed)"
            cells.append(c)
        # The shallowest depth from which no deeper level changes a pixel.
        need = next((d for d in depths if all(by[(s, e)]["off"] == 0 for e in depths if e >= d)), dmax)
        needed[s] = need
        last = by[(s, dmax)]["changed"]
        cells.append(f"{need}" + (f" (depth {dmax} still changed {last} px: the answer may be short)" if last else ""))
        body.append(cells)
    size = rows[0]["size"] if rows else 0
    doc = {
        "schema": "lockstep-table/1",
        "family": "ray_trace",
        "order": 30,
        "title": "Speed against accuracy: the ray-tree depth",
        "command": COMMAND,
        "date": datetime.date.today().isoformat(),
        "machine": chartlib.machine(),
        "issue": 22,
        "note": (f"embree (robust offset, shadow rays, cut-off 1/256), one thread, {size} x {size}, median of 3 frames per "
                 f"depth (a shared, loaded machine: times are noisy, their growth with depth is the point). Each cell: ms "
                 f"per frame, the pixels that differ by more than 1/255 in a channel from the depth-{dmax} frame (the "
                 f"reference answer) in % of the image, and in brackets the pixels changed by that extra level. 'depth "
                 f"needed': the shallowest depth whose frame and every deeper one equal the answer: how deep a tree the "
                 f"scene needs at 8 bits. bench/timing/ray_trace_depth.cpp, bench/scripts/ray_trace_depth_chart.py."),
        "chart": ["ray_trace_depth.png", "ray tracing: time and pixels off the answer against depth"],
        "columns": cols,
        "rows": body,
    }
    chartlib.write_table(doc, json_out)

    dat = os.path.join(out, "ray_trace_depth.dat")
    floor = 1e-4
    with open(dat, "w") as f:
        for s in scenes:
            f.write(f"# {s}: depth ms off_percent changed_percent\n")
            for d in depths:
                r = by[(s, d)]
                f.write(f"{d} {r['ms']} {max(100 * r['off'] / r['pixels'], floor)} "
                        f"{max(100 * r['changed'] / r['pixels'], floor) if d > 1 else floor}\n")
            f.write("\n\n")
    plots_t = ", ".join(f"'{dat}' index {i} using 1:2 with linespoints title '{s}'" for i, s in enumerate(scenes))
    plots_e = ", ".join(f"'{dat}' index {i} using 1:3 with linespoints title '{s}'" for i, s in enumerate(scenes))
    plots_c = ", ".join(f"'{dat}' index {i} using 1:4 with linespoints title '{s}'" for i, s in enumerate(scenes))
    subprocess.run(["gnuplot"], text=True, check=True, input=f"""set terminal pngcairo size 1500,500
set output '{out}/ray_trace_depth.png'
set multiplot layout 1,3 title "Ray tracing (embree, 1 thread, {size}^2): how deep a tree each scene needs"
set grid; set xlabel "max depth"; set key top left font ",8"; set xtics 1
set title "time per frame"; set ylabel "ms"; set logscale y
plot {plots_t}
set title "pixels off the depth-{dmax} frame (> 1/255; {floor:g}% = none)"; set ylabel "% of pixels"
set yrange [{floor / 2}:100]
plot {plots_e}
set title "pixels changed by this extra level"
plot {plots_c}
unset multiplot
""")
    print(json.dumps(needed))


if __name__ == "__main__":
    main()
