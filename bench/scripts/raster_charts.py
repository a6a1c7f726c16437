#!/usr/bin/env python3
"""Charts and tables of the raster families for BENCHMARKS.md.

usage: raster_charts.py STUDY_CSV [BENCH_JSON] OUT_DIR

STUDY_CSV is the output of `lockstep_raster_study all` (bench/studies/raster_study.cpp);
BENCH_JSON Google Benchmark's JSON of `lockstep_bench --benchmark_filter=frame/(zbuffer|scanline|painter)`.

  raster_scaling.png        time per 1024^2 frame against triangle count, per
                            implementation and thread count (flat shading)
  raster_tessellation.png   speed against accuracy: time per frame against the
                            error of the z-buffer image vs ray casting, per
                            sphere tessellation target
  raster_supersampling.png  error against the exact box filter, against spp and time
  raster_zfight.png         the z-fighting failure map per depth format
  raster_painter.png        the painter's failure map: wrong pixels per case, sorted,
                            for cyclic triples and interpenetrating pairs
Prints the markdown tables used in BENCHMARKS.md.
"""
import json
import os
import re
import subprocess

import chartlib


def sections(path):
    """{study: (header fields, rows)} from the study's CSV (comment line, then rows)."""
    out, name = {}, None
    for line in open(path):
        line = line.strip()
        if not line:
            continue
        if line.startswith("#"):
            m = re.match(r"# (\w+): ([^ ]+)", line)
            name = m.group(1)
            out[name] = (m.group(2).split(","), [], line)
        elif name:
            out[name][1].append(line.split(","))
    return out


def gnuplot(script):
    subprocess.run(["gnuplot"], input=script, text=True, check=True)


def tessellation_table(sec):
    fields, rows, title = sec
    out = ["| scene | tess_error (px) | sphere triangles | ms/frame | mean error | pixels over 1/255 |",
           "|---|---:|---:|---:|---:|---:|"]
    for r in rows:
        scene, e, tris, ms, mean, pct = r[0], r[1], int(r[2]), float(r[3]), float(r[4]), float(r[5])
        out.append(f"| {scene} | {e} | {tris} | {ms:.1f} | {mean:.4f} | {pct:.2f}% |")
    return "\n".join(out)


def tessellation(sec, out):
    fields, rows, title = sec
    data = {}
    for r in rows:
        scene, e, tris, ms, mean = r[0], r[1], int(r[2]), float(r[3]), float(r[4])
        data.setdefault(scene, []).append((ms, mean, e, tris))
    dat = os.path.join(out, "raster_tessellation.dat")
    with open(dat, "w") as f:
        for scene, pts in data.items():
            f.write(f"# {scene}\n")
            for ms, mean, e, tris in pts:
                f.write(f"{ms} {mean} {e}\n")
            f.write("\n\n")
    plots = ", ".join(
        f"'{dat}' index {k} using 1:2 with linespoints title '{s}', '' index {k} using 1:2:3 with labels offset 1,0.6 notitle"
        for k, s in enumerate(data))
    gnuplot(f"""set terminal pngcairo size 800,500
set output '{out}/raster_tessellation.png'
set title "Speed against accuracy: sphere tessellation (labels: silhouette error target, px)"
set xlabel "ms per frame"; set ylabel "mean |z-buffer - ray cast|"
set logscale xy; set grid
plot {plots}
""")


def supersampling_table(sec):
    fields, rows, title = sec
    out = ["| grid | spp | ms/frame | mean error | max error |", "|---|---:|---:|---:|---:|"]
    for grid, spp, ms, mean, mx in rows:
        out.append(f"| {grid} | {spp} | {float(ms):.2f} | {float(mean):.5f} | {float(mx):.4f} |")
    return "\n".join(out)


def supersampling(sec, out):
    fields, rows, title = sec
    data = {}
    for grid, spp, ms, mean, mx in rows:
        data.setdefault(grid, []).append((spp, ms, mean, mx))
    dat = os.path.join(out, "raster_supersampling.dat")
    with open(dat, "w") as f:
        for grid, pts in data.items():
            f.write(f"# {grid}\n")
            for p in pts:
                f.write(" ".join(p) + "\n")
            f.write("\n\n")
    gnuplot(f"""set terminal pngcairo size 1000,450
set output '{out}/raster_supersampling.png'
set multiplot layout 1,2 title "Supersampling converging to the exact box filter"
set logscale xy; set grid
set xlabel "samples per pixel"; set ylabel "error"
plot '{dat}' index 0 using 1:3 with linespoints title 'regular mean', '' index 0 using 1:4 with linespoints title 'regular max', \
     '' index 1 using 1:3 with linespoints title 'rotated mean', '' index 1 using 1:4 with linespoints title 'rotated max', \
     0.01/sqrt(x) dashtype 2 title '1/n (n x n samples)'
set xlabel "ms per frame (64 x 64)"
plot '{dat}' index 0 using 2:3 with linespoints title 'regular mean', '' index 1 using 2:3 with linespoints title 'rotated mean'
unset multiplot
""")


def zfight_grid(sec):
    """(formats, near planes, separations, {(format, near, sep): share wrong})"""
    fields, rows, title = sec
    fmts = []
    grid = {}
    for fmt, near, ratio, sep, wrong in rows:
        if fmt not in fmts:
            fmts.append(fmt)
        grid[(fmt, float(near), float(sep))] = float(wrong)
    return fmts, sorted({k[1] for k in grid}), sorted({k[2] for k in grid}, reverse=True), grid


def zfight_table(sec):
    fmts, nears, seps, grid = zfight_grid(sec)
    out = ["| format | near | " + " | ".join(f"sep {s:g}" for s in seps) + " |", "|---|---:|" + "---:|" * len(seps)]
    for fmt in fmts:
        for n in nears:
            out.append(f"| {fmt} | {n:g} | " + " | ".join(f"{100 * grid[(fmt, n, s)]:.0f}%" for s in seps) + " |")
    return "\n".join(out)


def zfight(sec, out):
    fmts, nears, seps, grid = zfight_grid(sec)
    dat = os.path.join(out, "raster_zfight.dat")
    with open(dat, "w") as f:
        for fmt in fmts:
            f.write(f"# {fmt}\n")
            for i, n in enumerate(nears):
                for j, s in enumerate(seps):
                    f.write(f"{j} {i} {grid[(fmt, n, s)]}\n")
                f.write("\n")
            f.write("\n")
    xt = ", ".join(f'"{s:g}" {j}' for j, s in enumerate(seps))
    yt = ", ".join(f'"{n:g}" {i}' for i, n in enumerate(nears))
    plots = "\n".join(
        f"set title '{fmt}'\nplot '{dat}' index {k} using 1:2:3 with image notitle" for k, fmt in enumerate(fmts))
    gnuplot(f"""set terminal pngcairo size 1100,300
set output '{out}/raster_zfight.png'
set multiplot layout 1,{len(fmts)} title "Z-fighting: share of wrong pixels (black 0, white 1); far = 100"
set xtics ({xt}) rotate by 45 right; set ytics ({yt})
set xlabel "separation"; set ylabel "near"
set cbrange [0:1]; set palette gray; unset colorbox
{plots}
unset multiplot
""")


def gouraud_table(sec):
    fields, rows, title = sec
    out = ["| tess_error (px) | triangles | Phong peak | Gouraud peak | max error | mean error |",
           "|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        out.append("| " + " | ".join(r) + " |")
    return "\n".join(out)


def painter_cases(sec):
    """{kind: [(wrong pixel fraction, wrong pixels, reported, wrong pixels with split)]}"""
    fields, rows, title = sec
    kinds = {}
    for r in rows:
        kinds.setdefault(r[0], []).append((float(r[2]), int(r[3]), int(r[4]), int(r[5])))
    return kinds


def painter_summary(sec):
    """{kind: {cases, wrong, reported, median, mean, max, split}} (fractions of covered pixels)"""
    out = {}
    for kind, cs in painter_cases(sec).items():
        fr = sorted(c[0] for c in cs)
        out[kind] = dict(cases=len(cs), wrong=sum(1 for c in cs if c[1] > 0),
                         reported=sum(1 for c in cs if c[1] > 0 and c[2]), median=fr[len(fr) // 2],
                         mean=sum(fr) / len(fr), max=fr[-1], split=sum(c[3] for c in cs))
    return out


def painter_table(sec):
    out = ["| scenes | cases | drawn wrong | reported | wrong pixels (of covered): median | mean | max "
           "| wrong pixels with split |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for kind, p in painter_summary(sec).items():
        out.append(f"| {kind.replace('_', ' ')} | {p['cases']} | {p['wrong']} | {p['reported']} of {p['wrong']} "
                   f"| {100 * p['median']:.1f}% | {100 * p['mean']:.1f}% | {100 * p['max']:.1f}% | {p['split']} |")
    return "\n".join(out)


def painter(sec, out):
    kinds = painter_cases(sec)
    dat = os.path.join(out, "raster_painter.dat")
    with open(dat, "w") as f:
        for kind, cs in kinds.items():
            fr = sorted(c[0] for c in cs)
            f.write(f"# {kind}\n")
            for k, v in enumerate(fr):
                f.write(f"{100.0 * (k + 0.5) / len(fr)} {100 * v}\n")
            f.write("\n\n")
    plots = ", ".join(f"'{dat}' index {k} using 1:2 with lines lw 2 title '{kind.replace('_', ' ')}'"
                      for k, kind in enumerate(kinds))
    gnuplot(f"""set terminal pngcairo size 800,500
set output '{out}/raster_painter.png'
set title "Painter's algorithm: wrong pixels per scene (sorted), 64x64 flat, against the z-buffer"
set xlabel "scenes (percentile)"; set ylabel "wrong pixels, % of covered"
set grid; set key left top
plot {plots}
""")


def raster_frames(path):
    """The raster frames of a Google Benchmark JSON (medians): a row per
    (family, scene, shading, implementation, threads), the (scene, shading)
    pairs in run order, the implementations (family, impl, threads) in table
    order, and a lookup."""
    data = json.load(open(path))
    rows = []
    for b in data["benchmarks"]:
        if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
            continue
        m = re.match(r"frame/(\w+)/([\w.-]+)/(\w+)/(\w+)/threads:(\d+)", b["name"])
        if not m:
            continue
        fam, scene, shading, impl, threads = m.groups()
        ms = b["real_time"] if b.get("time_unit") == "ms" else b["real_time"] / 1e6
        mtris = b.get("triangles_per_s", 0) / 1e6
        mpix = b.get("items_per_second", 0) / 1e6
        drawn = mtris * 1e6 * ms / 1e3  # triangles per frame after tessellation (FrameStats::items)
        rows.append(dict(fam=fam, scene=scene, shading=shading, impl=impl, threads=int(threads), ms=ms, mtris=mtris,
                         mpix=mpix, drawn=drawn, first=b.get("first_ms", 0)))

    def get(fam, scene, shading, impl, t):
        hit = [r for r in rows if (r["fam"], r["scene"], r["shading"], r["impl"], r["threads"]) ==
               (fam, scene, shading, impl, t)]
        return hit[0] if hit else None

    scenes = []
    for r in rows:
        if (r["scene"], r["shading"]) not in scenes:
            scenes.append((r["scene"], r["shading"]))
    impls = sorted({(r["fam"], r["impl"], r["threads"]) for r in rows},
                   key=lambda k: (["zbuffer", "scanline", "painter"].index(k[0]) if k[0] in
                                  ("zbuffer", "scanline", "painter") else 9, k[1] != "reference", k[1], k[2]))
    return rows, scenes, impls, get


def zbuffer_table(path):
    """The z-buffer's ms per frame, warm (the cold first frame in brackets)."""
    rows, scenes, impls, get = raster_frames(path)
    out = ["| scene | shading | triangles (spheres tessellated) | reference 1T | simd 1T | simd 2T | llvmpipe 1T "
           "| llvmpipe 2T | simd / ref, 1T | simd 2T vs llvmpipe 2T |",
           "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for sc, sh in scenes:
        cells = [get("zbuffer", sc, sh, i, t) for i, t in
                 (("reference", 1), ("simd", 1), ("simd", 2), ("llvmpipe", 1), ("llvmpipe", 2))]
        if not any(cells):
            continue
        drawn = next(c["drawn"] for c in cells if c)
        txt = [f"{c['ms']:.2f} ({c['first']:.0f})" if c else "" for c in cells]
        ref, s1, s2, l2 = cells[0], cells[1], cells[2], cells[4]
        sp = f"{ref['ms'] / s1['ms']:.1f}x" if ref and s1 else ""
        vs = f"{l2['ms'] / s2['ms']:.1f}x faster" if l2 and s2 else ""
        out.append(f"| {sc} | {sh} | {drawn:.0f} | " + " | ".join(txt) + f" | {sp} | {vs} |")
    return "\n".join(out)


def every_impl_table(path):
    """Every raster implementation: Mtris/s / Mpix/s, warm."""
    rows, scenes, impls, get = raster_frames(path)
    out = ["| scene | shading | " + " | ".join(f"{f} {i} {t}T" for f, i, t in impls) + " |",
           "|---|---|" + "---:|" * len(impls)]
    for sc, sh in scenes:
        cells = []
        for f, i, t in impls:
            c = get(f, sc, sh, i, t)
            cells.append(f"{c['mtris']:.3g} / {c['mpix']:.0f}" if c else "")
        out.append(f"| {sc} | {sh} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def bench(path, out):
    rows, scenes, impls, get = raster_frames(path)
    dat = os.path.join(out, "raster_scaling.dat")
    series = [k for k in impls if k[0] == "zbuffer"] + [k for k in impls if k[0] != "zbuffer" and k[2] == 2]
    with open(dat, "w") as fh:
        for f, i, t in series:
            fh.write(f"# {f} {i} {t}\n")
            for r in sorted((r for r in rows if (r["fam"], r["impl"], r["threads"]) == (f, i, t) and
                             r["shading"] == "flat"), key=lambda r: r["drawn"]):
                fh.write(f"{r['drawn']} {r['ms']} {r['scene']}\n")
            fh.write("\n\n")
    plots = ", ".join(f"'{dat}' index {k} using 1:2 with linespoints title '{f} {i} {t}T'"
                      for k, (f, i, t) in enumerate(series))
    gnuplot(f"""set terminal pngcairo size 900,560
set output '{out}/raster_scaling.png'
set title "Time per 1024^2 frame against triangle count (flat, SPD scenes)"
set xlabel "triangles (spheres tessellated)"; set ylabel "ms per frame"
set logscale xy; set grid; set key outside right
plot {plots}
""")


def main():
    a = chartlib.args(__doc__)
    out = a.out_dir
    os.makedirs(out, exist_ok=True)
    sec = sections(a.study_csv)
    if "tessellation" in sec:
        print("\n### Tessellation: z-buffer (Phong per sample) against ray casting\n")
        print(tessellation_table(sec["tessellation"]))
        tessellation(sec["tessellation"], out)
    if "supersampling" in sec:
        print("\n### Supersampling against the exact box-filtered image\n")
        print(supersampling_table(sec["supersampling"]))
        supersampling(sec["supersampling"], out)
    if "zfight" in sec:
        print("\n### Z-fighting: share of pixels where the back plane wins (depth 10..100)\n")
        print(zfight_table(sec["zfight"]))
        zfight(sec["zfight"], out)
    if "gouraud" in sec:
        print("\n### Gouraud's missed highlights (shiny sphere, against Phong)\n")
        print(gouraud_table(sec["gouraud"]))
    if "painter" in sec:
        print("\n### The painter's failure map (random 64x64 flat scenes, against the z-buffer)\n")
        print(painter_table(sec["painter"]))
        painter(sec["painter"], out)
    if a.bench_json:
        print("\n### The z-buffer at 1024^2: ms per frame (warm; cold first frame in brackets)\n")
        print(zbuffer_table(a.bench_json))
        print("\n### Every raster implementation at 1024^2: Mtris/s / Mpix/s (warm)\n")
        print(every_impl_table(a.bench_json))
        bench(a.bench_json, out)


if __name__ == "__main__":
    main()
