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


def fields(csv):
    """The comma-separated fields of each data line (no header, no comments)."""
    for line in open(csv):
        line = line.strip()
        if line and not line.startswith("#") and not line.startswith("row,"):
            yield line.split(",")


def load(csv):
    return [dict(row=f[0], filter=f[1], rms=float(f[2]), p99=float(f[3]), max=float(f[4]), s=float(f[5]),
                 lookups=int(f[6]), ns=float(f[7]), setup=float(f[8]) if len(f) > 8 else None)
            for f in fields(csv)]


def table(rows):
    filters = []
    for r in rows:
        if r["filter"] not in filters and not r["filter"].startswith("error"):
            filters.append(r["filter"])
    body = []
    for flt in filters:
        by = {r["row"]: r for r in rows if r["filter"] == flt}
        ref, simd, oiio, gl = by["reference"], by.get("simd"), by.get("oiio"), by.get("llvmpipe")
        cells = [flt, f"{ref['rms']:.4f}", f"{ref['p99']:.3f}", f"{ref['ns']:.0f}"]
        cells += [f"{simd['ns']:.1f}", f"{ref['ns'] / simd['ns']:.1f}x"] if simd else ["-", "-"]
        cells += [f"{oiio['rms']:.4f}", f"{oiio['ns']:.0f}"] if oiio else ["n/a", "n/a"]
        cells += [f"{gl['rms']:.4f}", f"{gl['ns']:.0f}"] if gl else ["n/a", "n/a"]
        body.append(cells)
    return chartlib.markdown_table(["filter", "RMS error (reference, simd)", "p99 error", "reference ns/lookup",
                                    "simd ns/lookup", "simd speed-up", "oiio RMS error", "oiio ns/lookup",
                                    "llvmpipe RMS error", "llvmpipe ns/lookup"], body)


def load_plane(csv):
    """lockstep_texture_study --plane: row,filter,threads,seconds,lookups,ns_per_lookup,setup_seconds."""
    return [dict(row=f[0], filter=f[1], threads=int(f[2]), s=float(f[3]), lookups=int(f[4]), ns=float(f[5]),
                 setup=float(f[6])) for f in fields(csv)]


def plane_table(rows):
    """The 1024^2 plane: ms a frame and ns a lookup per row, filter and thread count."""
    body = []
    for r in rows:
        body.append([r["filter"], r["row"], str(r["threads"]), f"{r['s'] * 1e3:.1f}", f"{r['ns']:.1f}",
                     f"{r['setup'] * 1e3:.1f}"])
    return chartlib.markdown_table(["filter", "row", "threads", "ms a frame (lookups alone)", "ns/lookup",
                                    "set-up ms (one-shot, apart)"], body)


def error_table(rows):
    """The simd row's error=E points (a filter per tile): markdown."""
    body = []
    for r in rows:
        if r["row"] == "simd" and r["filter"].startswith("error"):
            e = r["filter"][len("error"):]
            setup = f"{r['setup'] * 1e3:.0f} ms" if r["setup"] is not None else "-"
            body.append([e, f"{r['rms']:.4f}", "yes" if r["rms"] <= float(e) else "**no**", f"{r['p99']:.3f}",
                         f"{r['max']:.3f}", f"{r['ns']:.1f}", setup])
    return chartlib.markdown_table(["error E", "frame RMS error", "RMS <= E", "p99 error", "max error",
                                    "simd ns/lookup", "search (one-shot)"], body)


def targets(rows1, rows2, plane=None):
    """Issue #32's targets, evaluated over the one-thread and two-thread studies
    (and the 1024^2 plane where given): a markdown table of target, measured, verdict."""
    g1 = {(r["row"], r["filter"]): r for r in rows1}
    g2 = {(r["row"], r["filter"]): r for r in rows2}
    out = []

    def add(text, measured, met):
        out.append([text, measured, "**met**" if met else "**not met**"])

    ref, simd = g1[("reference", "trilinear")], g1[("simd", "trilinear")]
    add("simd trilinear at least 10x the reference, one thread (lookups alone): 192^2 zone plate",
        f"{ref['ns'] / simd['ns']:.1f}x ({simd['ns']:.1f} against {ref['ns']:.1f} ns)", ref["ns"] / simd["ns"] >= 10)
    if plane:
        gp = {(r["row"], r["filter"], r["threads"]): r for r in plane}
        pr, ps = gp.get(("reference", "trilinear", 1)), gp.get(("simd", "trilinear", 1))
        if pr and ps:
            add("the same on the issue's 1024^2 receding plane (a 1024^2 zone plate, 16 x 64 repeats)",
                f"{pr['ns'] / ps['ns']:.1f}x ({ps['ns']:.1f} against {pr['ns']:.1f} ns)", pr["ns"] / ps["ns"] >= 10)

    def best_at_or_below(g, row, err, prefix=("trilinear", "aniso", "mip_nearest", "bilinear", "point", "ewa", "super")):
        """row's fastest filter whose RMS error is at most err."""
        cand = [r for (rw, f), r in g.items() if rw == row and r["rms"] <= err * 1.02 and f.startswith(prefix)]
        return min(cand, key=lambda r: r["ns"]) if cand else None

    for peer in ("oiio", "llvmpipe"):
        pts = [r for (rw, f), r in g1.items() if rw == peer]
        if not pts:
            continue
        worst = None
        for r in pts:
            ours = best_at_or_below(g1, "simd", r["rms"])
            if ours:
                ratio = r["ns"] / ours["ns"]
                if worst is None or ratio < worst[0]:
                    worst = (ratio, r, ours)
        if peer == "oiio" and worst:
            ratio, r, ours = worst
            add("at equal error, simd at least 5x faster than OpenImageIO's TextureSystem (one thread; every OpenImageIO "
                "filter against simd's fastest filter at least as accurate)",
                f"{ratio:.1f}x at worst: OpenImageIO {r['filter']} (RMS {r['rms']:.4f}, {r['ns']:.0f} ns) against simd "
                f"{ours['filter']} (RMS {ours['rms']:.4f}, {ours['ns']:.1f} ns)", ratio >= 5)
        if peer == "llvmpipe":
            w2 = None
            for r in (r for (rw, f), r in g2.items() if rw == "llvmpipe"):
                ours = best_at_or_below(g2, "simd", r["rms"])
                if ours:
                    ratio = r["ns"] / ours["ns"]
                    if w2 is None or ratio < w2[0]:
                        w2 = (ratio, r, ours)
            if w2:
                ratio, r, ours = w2
                add("at equal error, simd faster than llvmpipe with two threads",
                    f"{ratio:.1f}x at worst: llvmpipe {r['filter']} (RMS {r['rms']:.4f}, {r['ns']:.1f} ns) against simd "
                    f"{ours['filter']} (RMS {ours['rms']:.4f}, {ours['ns']:.1f} ns)", ratio > 1)
    # simd's anisotropic curve below every peer anisotropic point: for each such
    # point, a simd anisotropic filter with lower error in less time.
    below = True
    detail = []
    for (rw, f), r in g1.items():
        if rw in ("oiio", "llvmpipe") and f.startswith("aniso"):
            ok = any(o["rms"] < r["rms"] and o["ns"] < r["ns"] for (w, ff), o in g1.items()
                     if w == "simd" and (ff.startswith("aniso") or ff == "ewa"))
            below = below and ok
            if not ok:
                detail.append(f"{rw} {f}")
    add("simd's anisotropic/EWA curve below both peers' anisotropic points (one thread)",
        "every peer anisotropic point has a simd anisotropic filter more accurate and faster" if below
        else "not below: " + ", ".join(detail), below)
    return chartlib.markdown_table(["target (issue #32)", "measured", ""], out).replace("|---|---|---:|", "|---|---|---|")


def main():
    a = chartlib.args(__doc__)
    rows = load(a.study_csv)
    print(table(rows))
    dat = os.path.join(a.out_dir, "texture_speed_accuracy.dat")
    def series_of(r):
        return r["row"] + (" error=E" if r["filter"].startswith("error") else "")

    series = []
    for r in rows:
        if series_of(r) not in series:
            series.append(series_of(r))
    with open(dat, "w") as f:
        for row in series:
            f.write(f"# {row}\n")
            for r in rows:
                if series_of(r) == row:
                    label = r["filter"].replace("error", "E=") if r["filter"].startswith("error") else r["filter"]
                    f.write(f"{r['ns']} {r['rms']} {label}\n")
            f.write("\n\n")
    palette = ["#555555", "#1f77b4", "#ff7f0e", "#d62728", "#2ca02c", "#9467bd"]
    plots = ", ".join(
        f"'{dat}' index {k} using 1:2 with points pt 7 lc rgb '{palette[k % len(palette)]}' title '{row}', "
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
