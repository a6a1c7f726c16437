#!/usr/bin/env python3
"""Marching cubes' speed against accuracy chart and table for BENCHMARKS.md.

usage: mc_chart.py STUDY_CSV OUT_DIR

STUDY_CSV is the output of `lockstep_mc_study` (bench/studies/marching_cubes_study.cpp):
  ./build/bench/lockstep_mc_study > bench/results/mc_study.csv
  python3 bench/scripts/mc_chart.py bench/results/mc_study.csv bench/charts

  mc_accuracy.png   two-sided Hausdorff distance to the analytic surface against
                    extraction time (one thread), per field and implementation,
                    points labelled by the grid's samples a side
Prints the markdown table used in BENCHMARKS.md.
"""
import os
import subprocess

import chartlib


def load(csv):
    rows = []
    for line in open(csv):
        line = line.strip()
        if line and not line.startswith("#"):
            f = line.split(",")
            rows.append(dict(field=f[0], n=int(f[1]), h=float(f[2]), impl=f[3], ms=float(f[5]), tris=int(f[6]),
                             haus=float(f[9]), c=float(f[10])))
    return rows


def table(rows):
    out = ["| field | n | h | triangles | reference ms | simd ms | Hausdorff | c |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    keys = sorted({(r["field"], r["n"]) for r in rows})
    for field, n in keys:
        by = {r["impl"]: r for r in rows if r["field"] == field and r["n"] == n}
        ref, simd = by["reference"], by.get("simd", by["reference"])
        out.append(f"| {field} | {n} | {ref['h']:.4f} | {ref['tris']} | {ref['ms']:.2f} | {simd['ms']:.2f} | "
                   f"{ref['haus']:.2e} | {ref['c']:.3f} |")
    return "\n".join(out)


def main():
    a = chartlib.args(__doc__)
    out = a.out_dir
    rows = load(a.study_csv)
    print(table(rows))
    dat = os.path.join(out, "mc_accuracy.dat")
    series = sorted({(r["field"], r["impl"]) for r in rows})
    with open(dat, "w") as f:
        for field, impl in series:
            f.write(f"# {field} {impl}\n")
            for r in rows:
                if (r["field"], r["impl"]) == (field, impl):
                    f.write(f"{r['ms']} {r['haus']} {r['n']}\n")
            f.write("\n\n")
    plots = ", ".join(
        f"'{dat}' index {k} using 1:2 with linespoints title '{field} {impl}', "
        f"'' index {k} using 1:2:3 with labels offset 1,0.6 notitle"
        for k, (field, impl) in enumerate(series))
    subprocess.run(["gnuplot"], text=True, check=True, input=f"""set terminal pngcairo size 800,500
set output '{out}/mc_accuracy.png'
set title "Marching cubes, speed against accuracy (labels: samples a side; one thread)"
set xlabel "ms per extraction"; set ylabel "two-sided Hausdorff distance to the surface"
set logscale xy; set grid; set key top right; set format y "%.0e"
plot {plots}
""")


if __name__ == "__main__":
    main()
