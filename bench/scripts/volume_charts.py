#!/usr/bin/env python3
"""Charts and tables of the volume study (bench/studies/volume_study.cpp) for BENCHMARKS.md.

usage: volume_charts.py STUDY.csv OUT_DIR
  STUDY.csv  lockstep_volume_study all > STUDY.csv (two CSV sections, each with its header)
  OUT_DIR    where volume_step.png and volume_cross.png go (bench/charts)
Prints the markdown tables on stdout.
"""
import os
import subprocess

import chartlib


def sections(path):
    out, fields = {}, None
    for line in open(path):
        w = line.strip().split(",")
        if not w or not w[0]:
            continue
        if w[0] == "study":
            fields = w
            continue
        out.setdefault(w[0], []).append(dict(zip(fields, w)))
    return out


def gnuplot(script):
    subprocess.run(["gnuplot"], input=script, text=True, check=True)


def step_label(step):
    return f"1/{round(1 / step)}" if step < 1 else f"{step:g}"


def step_table(rows):
    """One row per (input, implementation, threads), one column per step:
    ms per frame and mean error (volpack: its one point, with its largest error)."""
    steps = sorted({float(r["step"]) for r in rows if r["impl"] != "volpack"}, reverse=True)
    keys = []
    for r in rows:
        if (r["input"], r["impl"], r["threads"]) not in keys:
            keys.append((r["input"], r["impl"], r["threads"]))
    out = ["| input | row | " + " | ".join(f"step {step_label(x)}" for x in steps) + " |",
           "|---|---|" + "---:|" * len(steps)]
    for key in keys:
        cells = []
        for x in steps:
            hit = [r for r in rows if (r["input"], r["impl"], r["threads"]) == key and float(r["step"]) == x]
            c = ""
            if hit:
                r = hit[0]
                ms = float(r["ms"])
                c = f"{ms:.0f} ms, {float(r['mean_error']):.1e}" if ms >= 100 else f"{ms:.3g} ms, {float(r['mean_error']):.1e}"
                if key[1] == "volpack":
                    c += f" (max {float(r['max_error']):.2f})"
            cells.append(c)
        out.append(f"| {key[0]} | {key[1]} {key[2]}T | " + " | ".join(cells) + " |")
    return "\n".join(out)


def step(rows, out):
    inputs = []
    for r in rows:
        if r["input"] not in inputs:
            inputs.append(r["input"])
    dat = os.path.join(out, "volume_step.dat")
    panels = []
    with open(dat, "w") as f:
        k = 0
        for inp in inputs:
            impls = []
            for r in rows:
                key = (r["impl"], r["threads"])
                if r["input"] == inp and key not in impls:
                    impls.append(key)
            plots = []
            for im, th in impls:
                f.write(f"# {inp} {im} {th}T\n")
                for r in rows:
                    if r["input"] == inp and r["impl"] == im and r["threads"] == th:
                        f.write(f"{r['ms']} {r['mean_error']} {r['step']}\n")
                f.write("\n\n")
                style = "points pointsize 2" if im == "volpack" else "linespoints"
                plots.append(f"'{dat}' index {k} using 1:2 with {style} title '{im} {th}T'")
                k += 1
            panels.append(f"set title '{inp}'\nplot " + ", ".join(plots))
    body = "\n".join(panels)
    gnuplot(f"""set terminal pngcairo size 1500,520
set output '{out}/volume_step.png'
set multiplot layout 1,{len(panels)} title "Volume ray casting at 512x512: mean error against a step of 1/16 voxel, by time per frame (steps 2, 1, 1/2, 1/4, 1/8 left to right; volpack: one point, its own sampling)"
set logscale xy
set xlabel "ms per frame"
set ylabel "mean error per channel"
set format y "%.0e"
set key top right
set grid
{body}
unset multiplot
""")


def cross_table(rows):
    out = ["| field | n | h | triangles | outline (px) | pixels covered by one only | mean depth difference "
           "| largest |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        out.append(f"| {r['field']} | {r['n']} | {float(r['h']):.4f} | {r['triangles']} | {r['silhouette_px']} | "
                   f"{r['mismatch_px']} | {float(r['mean_depth_diff']):.2e} | {float(r['max_depth_diff']):.3f} |")
    return "\n".join(out)


def cross(rows, out):
    dat = os.path.join(out, "volume_cross.dat")
    fields = []
    for r in rows:
        if r["field"] not in fields:
            fields.append(r["field"])
    with open(dat, "w") as f:
        for fl in fields:
            f.write(f"# {fl}\n")
            for r in rows:
                if r["field"] == fl:
                    f.write(f"{r['h']} {r['mean_depth_diff']} {r['mismatch_px']}\n")
            f.write("\n\n")
    plot = ", ".join(f"'{dat}' index {i} using 1:2 with linespoints title '{fl}: mean depth difference'"
                     for i, fl in enumerate(fields))
    gnuplot(f"""set terminal pngcairo size 900,500
set output '{out}/volume_cross.png'
set title "Marching-cubes mesh (z-buffer) against the ray-cast isosurface, as the grid is refined"
set logscale xy
set xlabel "grid spacing h"
set ylabel "mean depth difference (world units)"
set key left top
set grid
f(x) = {float(rows[0]['mean_depth_diff']) / float(rows[0]['h']) ** 2} * x**2
plot {plot}, f(x) with lines dashtype 2 title 'h^2'
""")


def main():
    a = chartlib.args(__doc__)
    s = sections(a.study_csv)
    os.makedirs(a.out_dir, exist_ok=True)
    if "step" in s:
        print("\n### Ray casting: ms per frame and mean error against the step (truth: simd at step 1/16)\n")
        print(step_table(s["step"]))
        step(s["step"], a.out_dir)
    if "cross" in s:
        print("\n### Marching cubes through the z-buffer against the ray-cast isosurface\n")
        print(cross_table(s["cross"]))
        cross(s["cross"], a.out_dir)


if __name__ == "__main__":
    main()
