#!/usr/bin/env python3
"""Texture filtering's failure maps for BENCHMARKS.md (issue #32): where each filter breaks.

usage: texture_map_chart.py STUDY_CSV OUT_DIR

STUDY_CSV is the output of `lockstep_texture_map_study` (bench/studies/texture_map_study.cpp):
  ./build/bench/lockstep_texture_map_study > bench/results/texture_map.csv
  python3 bench/scripts/texture_map_chart.py bench/results/texture_map.csv bench/charts

  texture_failure_maps.png  one map per filter: RMS error against the pixel's exact
                            box filter over viewing angle (elevation above the plane)
                            and minification (texels a pixel covers across, at the
                            image's centre)
Prints the markdown table of the boundaries used in BENCHMARKS.md: per filter and
angle, the minifications at which its RMS error stays under 0.05.
"""
import math
import os
import subprocess

import chartlib

LIMIT = 0.05


def load(csv):
    rows = []
    for line in open(csv):
        line = line.strip()
        if line and not line.startswith(("#", "filter,")):
            f = line.split(",")
            rows.append(dict(filter=f[0], theta=float(f[1]), m=float(f[2]), rms=float(f[3])))
    return rows


def ordered(values):
    out = []
    for v in values:
        if v not in out:
            out.append(v)
    return out


def table(rows):
    filters = ordered(r["filter"] for r in rows)
    thetas = sorted(set(r["theta"] for r in rows))
    body = []
    for flt in filters:
        cells = [flt]
        for th in thetas:
            ms = sorted((r["m"], r["rms"]) for r in rows if r["filter"] == flt and r["theta"] == th)
            held = [m for m, rms in ms if rms < LIMIT]
            cells.append("none" if not held else ("all" if len(held) == len(ms) else
                                                  ", ".join(f"{m:g}" for m in held)))
        body.append(cells)
    return chartlib.markdown_table(["filter"] + [f"{th:g} deg" for th in thetas], body)


def main():
    a = chartlib.args(__doc__)
    rows = load(a.study_csv)
    print(table(rows))
    filters = ordered(r["filter"] for r in rows)
    thetas = sorted(set(r["theta"] for r in rows))
    ms = sorted(set(r["m"] for r in rows))
    dat = os.path.join(a.out_dir, "texture_failure_maps.dat")
    with open(dat, "w") as f:
        for flt in filters:
            f.write(f"# {flt}\n")
            for i, th in enumerate(thetas):
                for j, m in enumerate(ms):
                    r = next(r for r in rows if r["filter"] == flt and r["theta"] == th and r["m"] == m)
                    f.write(f"{j} {i} {r['rms']}\n")
                f.write("\n")
            f.write("\n\n")
    cols = 3
    rows_n = math.ceil(len(filters) / cols)
    xt = ", ".join(f'"{m:g}" {j}' for j, m in enumerate(ms))
    yt = ", ".join(f'"{th:g}" {i}' for i, th in enumerate(thetas))
    plots = "\n".join(
        f"set title '{flt}'; plot '{dat}' index {k} using 1:2:3 with image notitle" for k, flt in enumerate(filters))
    subprocess.run(["gnuplot"], text=True, check=True, input=f"""set terminal pngcairo size 1100,{330 * rows_n}
set output '{a.out_dir}/texture_failure_maps.png'
set multiplot layout {rows_n},{cols} title "RMS error against the pixel's box filter (white: > 0.3); x: texels a pixel covers, y: degrees above the plane"
set xtics ({xt}); set ytics ({yt})
set cbrange [0:0.3]; set palette defined (0 '#1a9850', 0.05 '#fee08b', 0.15 '#f46d43', 0.3 '#ffffff')
set xrange [-0.5:{len(ms) - 0.5}]; set yrange [-0.5:{len(thetas) - 0.5}]
{plots}
unset multiplot
""")
    os.remove(dat)


if __name__ == "__main__":
    main()
