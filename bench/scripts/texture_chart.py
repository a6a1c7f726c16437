#!/usr/bin/env python3
"""Texture filtering's speed against accuracy chart and table for BENCHMARKS.md (issue #32).

usage: texture_chart.py STUDY_CSV OUT_DIR

STUDY_CSV is the output of `lockstep_texture_study` (bench/studies/texture_study.cpp):
  ./build/bench/lockstep_texture_study > bench/results/texture_study.csv
  python3 bench/scripts/texture_chart.py bench/results/texture_study.csv bench/charts

  texture_speed_accuracy.png  RMS error against the pixel's exact box filter
                              against ns per lookup (one thread), one series per
                              row, points labelled by filter
Prints the markdown table used in BENCHMARKS.md.
"""
import os
import subprocess

import chartlib


def load(csv):
    rows = []
    for line in open(csv):
        line = line.strip()
        if line and not line.startswith("#") and not line.startswith("row,"):
            f = line.split(",")
            rows.append(dict(row=f[0], filter=f[1], rms=float(f[2]), p99=float(f[3]), max=float(f[4]),
                             s=float(f[5]), lookups=int(f[6]), ns=float(f[7])))
    return rows


def table(rows):
    filters = []
    for r in rows:
        if r["filter"] not in filters:
            filters.append(r["filter"])
    body = []
    for flt in filters:
        by = {r["row"]: r for r in rows if r["filter"] == flt}
        ref, simd, oiio = by["reference"], by.get("simd"), by.get("oiio")
        cells = [flt, f"{ref['rms']:.4f}", f"{ref['p99']:.3f}", f"{ref['ns']:.0f}"]
        cells += [f"{simd['ns']:.1f}", f"{ref['ns'] / simd['ns']:.1f}x"] if simd else ["-", "-"]
        cells += [f"{oiio['rms']:.4f}", f"{oiio['ns']:.0f}"] if oiio else ["n/a", "n/a"]
        body.append(cells)
    return chartlib.markdown_table(["filter", "RMS error (reference, simd)", "p99 error", "reference ns/lookup",
                                    "simd ns/lookup", "simd speed-up", "oiio RMS error", "oiio ns/lookup"], body)


def main():
    a = chartlib.args(__doc__)
    rows = load(a.study_csv)
    print(table(rows))
    dat = os.path.join(a.out_dir, "texture_speed_accuracy.dat")
    series = []
    for r in rows:
        if r["row"] not in series:
            series.append(r["row"])
    with open(dat, "w") as f:
        for row in series:
            f.write(f"# {row}\n")
            for r in rows:
                if r["row"] == row:
                    f.write(f"{r['ns']} {r['rms']} {r['filter']}\n")
            f.write("\n\n")
    plots = ", ".join(
        f"'{dat}' index {k} using 1:2 with points pt 7 title '{row}', "
        f"'' index {k} using 1:2:3 with labels offset 0,0.7 font ',8' notitle"
        for k, row in enumerate(series))
    subprocess.run(["gnuplot"], text=True, check=True, input=f"""set terminal pngcairo size 900,560
set output '{a.out_dir}/texture_speed_accuracy.png'
set title "Texture filtering, speed against accuracy (receding zone plate, 192^2, one thread)"
set xlabel "ns per lookup"; set ylabel "RMS error against the pixel's exact box filter"
set logscale xy; set grid; set key top right
plot {plots}
""")
    os.remove(dat)


if __name__ == "__main__":
    main()
