#!/usr/bin/env python3
"""Radiosity's speed against accuracy: charts and tables for BENCHMARKS.md (issue #33).

usage: radiosity_chart.py STUDY_CSV OUT_DIR

STUDY_CSV is the output of `lockstep_radiosity_study` (bench/studies/radiosity_study.cpp):
  ./build/bench/lockstep_radiosity_study > bench/results/radiosity_study.csv
  python3 bench/scripts/radiosity_chart.py bench/results/radiosity_study.csv bench/charts

  radiosity_form_factors.png  the mean row error (over i of sum_j |F_ij - F*_ij|) against the
                              form-factor matrix's time, per method and row, points
                              labelled by k (rays, exact) or pixels (hemicube)
  radiosity_solvers.png       the residual against the solve's time per solver
  radiosity_failure_map.png   two facing unit plates at distance d: F's relative error, the
                              centre point's (proximity) and the hemicube's per resolution (aliasing)
  radiosity_refinement.png    the Cornell box image's error (largest pixel, rms) against patch
                              count, uniform meshes and refined ones (--error)
Prints the two markdown tables used in BENCHMARKS.md.
"""
import os
import subprocess

import chartlib


def load_maps(csv):
    maps = []
    for line in open(csv):
        f = line.strip().split(",")
        if f[0] == "map":
            maps.append(dict(method=f[1], res=int(f[2]), d=float(f[3]), err=float(f[4])))
    return maps


def load(csv):
    ff, solve = [], []
    for line in open(csv):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        f = line.split(",")
        if f[0] == "ff":
            ff.append(dict(patches=int(f[2]), method=f[3], setting=int(f[4]), impl=f[5], ms=float(f[6]),
                           max=float(f[7]), mean=float(f[8])))
        elif f[0] == "solve" and f[1] == "cornell":
            solve.append(dict(patches=int(f[2]), solver=f[3], iterations=int(f[4]), ms=float(f[5]),
                              residual=float(f[6])))
    return ff, solve


def form_factor_table(ff):
    out = ["| patches | method | k / pixels | reference ms | simd ms (2 threads) | speed-up | max row error | mean row error |",
           "|---:|---|---:|---:|---:|---:|---:|---:|"]
    keys = sorted({(r["patches"], r["method"], r["setting"]) for r in ff},
                  key=lambda k: (k[0], ["rays", "exact", "hemicube"].index(k[1]), k[2]))
    for patches, method, setting in keys:
        by = {r["impl"]: r for r in ff if (r["patches"], r["method"], r["setting"]) == (patches, method, setting)}
        ref, simd = by.get("reference"), by["simd"]
        up = f"{ref['ms'] / simd['ms']:.1f}x" if ref else ""
        out.append(f"| {patches} | {method} | {setting} | {ref['ms']:.1f} | {simd['ms']:.1f} | {up} | "
                   f"{simd['max']:.3g} | {simd['mean']:.3g} |" if ref else
                   f"| {patches} | {method} | {setting} |  | {simd['ms']:.1f} |  | {simd['max']:.3g} | {simd['mean']:.3g} |")
    return "\n".join(out)


def solver_table(solve):
    """Sweeps 1, 2, 4, ... 32 and the first to reach 1e-6 and 1e-12; shots 1, 4, 16, ..."""
    out = ["| solver | sweeps / shots | ms | residual / emission |", "|---|---:|---:|---:|"]
    for name in ("jacobi", "gauss-seidel", "progressive"):
        rows = [r for r in solve if r["solver"] == name]
        keep = set()
        for goal in (1e-6, 1e-12):
            first = next((r["iterations"] for r in rows if r["residual"] <= goal), None)
            if first:
                keep.add(first)
        for r in rows:
            n = r["iterations"]
            power = n & (n - 1) == 0
            if (name == "progressive" and power and (n.bit_length() - 1) % 2 == 0) or (
                    name != "progressive" and power) or n in keep:
                out.append(f"| {name} | {n} | {r['ms']:.2f} | {r['residual']:.3g} |")
    return "\n".join(out)


def table(csv):
    ff, solve = load(csv)
    return form_factor_table(ff) + "\n\n" + solver_table(solve)


def plot_series(out, name, series, settings, labels=False):
    """A log-log gnuplot chart OUT/NAME.png of series [(title, [(x, y, label), ...])],
    its data in OUT/NAME.dat (one indexed block per series); labels: each point's
    third column printed beside it."""
    dat = os.path.join(out, name + ".dat")
    with open(dat, "w") as f:
        for title, points in series:
            f.write(f"# {title}\n" + "".join(f"{x} {y} {label}\n" for x, y, label in points) + "\n\n")
    plots = ", ".join(
        f"'{dat}' index {k} using 1:2 with linespoints title '{title}'"
        + (f", '' index {k} using 1:2:3 with labels offset 1,0.6 notitle" if labels else "")
        for k, (title, _) in enumerate(series))
    subprocess.run(["gnuplot"], text=True, check=True, input=f"""set terminal pngcairo size 800,500
set output '{out}/{name}.png'
{settings}
set logscale xy; set grid; set format y "%.0e"
plot {plots}
""")


def chart(ff, solve, out):
    largest = max(r["patches"] for r in ff)
    series = []
    for m in ("rays", "exact", "hemicube"):
        for i in ("reference", "simd"):
            points = [(r["ms"], r["mean"], r["setting"]) for r in ff
                      if (r["method"], r["impl"], r["patches"]) == (m, i, largest)]
            if points:
                series.append((f"{m} {i}", points))
    plot_series(out, "radiosity_form_factors", series, f"""set title "Form factors, Cornell box, {largest} patches (labels: k or hemicube pixels)"
set xlabel "ms per form-factor matrix (simd: 2 threads)"; set ylabel "mean over i of sum_j |F_ij - F*_ij|"
set key outside right""", labels=True)
    series = [(s, [(max(r["ms"], 1e-3), r["residual"], r["iterations"]) for r in solve
                   if r["solver"] == s and r["residual"] > 0])
              for s in ("jacobi", "gauss-seidel", "progressive") if any(r["solver"] == s for r in solve)]
    plot_series(out, "radiosity_solvers", series, f"""set title "Radiosity solvers, Cornell box, {solve[0]['patches']} patches, exact form factors"
set xlabel "ms per solve (one thread)"; set ylabel "residual / largest emission"
set key top right""")


def map_table(maps):
    ds = sorted({m["d"] for m in maps})
    series = [("point", 0)] + sorted({("hemicube", m["res"]) for m in maps if m["method"] == "hemicube"},
                                     key=lambda x: x[1])
    out = ["| d / side | " + " | ".join("centre point" if r == 0 else f"hemicube {r}" for _, r in series) + " |",
           "|---:|" + "---:|" * len(series)]
    for d in ds:
        cells = []
        for meth, r in series:
            e = next((m["err"] for m in maps if m["method"] == meth and m["res"] == r and m["d"] == d), None)
            cells.append(f"{e:.3g}" if e is not None else "")
        out.append(f"| {d:g} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def load_rows(csv, kind):
    """The study's rows of one kind, as lists of fields (the kind dropped)."""
    return [line.strip().split(",")[1:] for line in open(csv) if line.startswith(kind + ",")]


def leak_table(csv):
    rows = load_rows(csv, "leak")
    phases = sorted({float(r[1]) for r in rows})
    out = ["| floor patches a side (cube: a quarter of the floor's side) | " +
           " | ".join(f"phase {p:g}: leaked / darkened" for p in phases) + " |",
           "|---:|" + "---:|" * len(phases)]
    for n in sorted({int(r[0]) for r in rows}):
        cells = [next((f"{float(r[2]):.3g} / {float(r[3]):.3g}" for r in rows if int(r[0]) == n and float(r[1]) == p), "")
                 for p in phases]
        out.append(f"| {n} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def refinement_table(csv):
    out = ["| mesh | setting | patches | largest pixel error | rms error | frame ms (simd 2T, 96²) |",
           "|---|---:|---:|---:|---:|---:|"]
    for kind, setting, patches, mx, rms, ms in load_rows(csv, "mesh"):
        what = "uniform, patch area" if kind == "uniform" else "refined from 8000, error"
        out.append(f"| {what} | {float(setting):g} | {patches} | {float(mx):.3g} | {float(rms):.3g} | {float(ms):.0f} |")
    out += ["", "| mesh | T-junctions | largest step | mean step |", "|---|---:|---:|---:|"]
    for e, count, mx, mean in load_rows(csv, "tjunction"):
        what = "uniform (patch area 8000)" if float(e) == 0 else f"refined, error {float(e):g}"
        out.append(f"| {what} | {count} | {float(mx):.3g} | {float(mean):.3g} |")
    return "\n".join(out)


def refinement_chart(csv, out):
    rows = load_rows(csv, "mesh")
    series = []
    for kind in ("uniform", "refined"):
        for col, what in ((3, "largest pixel"), (4, "rms")):
            series.append((f"{kind}: {what}", [(int(r[2]), float(r[col]), r[1]) for r in rows if r[0] == kind]))
    plot_series(out, "radiosity_refinement", series, """set title "Cornell box image (96^2) against 8,014 uniform patches"
set xlabel "patches"; set ylabel "image error (labels: patch area or error E)"
set key bottom left""", labels=True)


def map_chart(maps, out):
    kinds = [("point", 0)] + sorted({("hemicube", m["res"]) for m in maps if m["method"] == "hemicube"},
                                    key=lambda x: x[1])
    series = [("centre point (rays, any k)" if r == 0 else f"hemicube {r}",
               [(m["d"], max(m["err"], 1e-6), "") for m in maps if m["method"] == meth and m["res"] == r])
              for meth, r in kinds]
    plot_series(out, "radiosity_failure_map", series, """set title "Two facing unit plates at distance d: F's relative error against the exact factor"
set xlabel "d / side"; set ylabel "relative error of F"
set key bottom left""")


def main():
    a = chartlib.args(__doc__)
    ff, solve = load(a.study_csv)
    maps = load_maps(a.study_csv)
    if maps:
        map_chart(maps, a.out_dir)
    if load_rows(a.study_csv, "mesh"):
        refinement_chart(a.study_csv, a.out_dir)
    print(form_factor_table(ff))
    print()
    print(solver_table(solve))
    chart(ff, solve, a.out_dir)


if __name__ == "__main__":
    main()
