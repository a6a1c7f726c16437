#!/usr/bin/env python3
"""Charts for BENCHMARKS.md from Google Benchmark JSON (+ the props accuracy CSV).

usage: charts.py BENCH_JSON [ACCURACY_CSV] OUT_DIR

  scaling.png   time per primary ray against primitive count (log-log), one
                line per implementation, 1 thread, with auto's crossover marked
  accuracy.png  speed against accuracy: time per ray-primitive test (kernel
                benchmarks) against max and p99 relative error of t vs the oracle
Also prints the markdown tables used in BENCHMARKS.md.
"""
import csv
import json
import os
import re
import subprocess

import chartlib


def load(path):
    with open(path) as f:
        data = json.load(f)
    # With --benchmark_repetitions, use each benchmark's median; else its one run.
    has_median = any(b.get("aggregate_name") == "median" for b in data["benchmarks"])
    rows = []
    for b in data["benchmarks"]:
        if has_median and b.get("aggregate_name") != "median":
            continue
        if not has_median and b.get("run_type") == "aggregate":
            continue
        name = re.sub(r"/(real_time|process_time|manual_time)", "", b.get("run_name", b["name"]))
        rows.append((name, b))
    return data.get("context", {}), rows


def auto_rule():
    """(crossover, triangle weight) from optimized/ray_cast_auto.cpp: auto picks
    embree when spheres + weight * triangles >= crossover."""
    src = os.path.join(os.path.dirname(__file__), "..", "..", "optimized", "ray_cast_auto.cpp")
    try:
        text = open(src).read()
    except OSError:
        return None, 1
    x = re.search(r"kCrossover\s*=\s*([0-9']+)", text)
    w = re.search(r"kTriangleWeight\s*=\s*([0-9']+)", text)
    num = lambda m: int(m.group(1).replace("'", ""))
    return (num(x) if x else None), (num(w) if w else 1)


def scene_size(b, weight):
    """auto's measure of a scene: sphere-equivalents."""
    if "spheres" in b and "triangles" in b:
        return b["spheres"] + weight * b["triangles"]
    return b["prims"]


def per_ray_ns(b):
    return 1e9 / b["items_per_second"] if b.get("items_per_second") else None


def ray_cast_frames(rows):
    """{(scene, impl, threads): benchmark} of the ray_cast frames, the
    implementations in run order, the scenes by auto's size measure, the most
    threads, auto's (crossover, triangle weight)."""
    frames = {}
    for name, b in rows:
        p = name.split("/")
        if p[0] != "frame" or p[1] != "ray_cast":
            continue
        scene, impl, threads = p[2], p[3], int(p[4].split(":")[1])
        frames[(scene, impl, threads)] = b
    x, weight = auto_rule()
    first = lambda s: frames[next(k for k in frames if k[0] == s)]
    scenes = sorted({s for s, _, _ in frames}, key=lambda s: scene_size(first(s), weight))
    impls = []
    for _, i, _ in frames:
        if i not in impls:
            impls.append(i)
    threads_all = max([t for _, _, t in frames] or [1])
    return frames, impls, scenes, threads_all, (x, weight)


def frames_table(rows):
    """The SPD frames: Mrays/s per implementation and thread count."""
    frames, impls, scenes, threads_all, _ = ray_cast_frames(rows)
    out = ["| scene | prims | " + " | ".join(f"{i} 1T (Mrays/s)" for i in impls) +
           f" | simd {threads_all}T | embree {threads_all}T | auto {threads_all}T | simd/ref 1T | embree/ref 1T | auto vs best 1T | auto vs best {threads_all}T | embree BVH build ms 1T |",
           "|---" * (2 + len(impls) + 8) + "|"]
    for s in scenes:
        get = lambda i, t: frames.get((s, i, t), {}).get("items_per_second")
        cells = [f"{get(i, 1) / 1e6:.2f}" if get(i, 1) else "-" for i in impls]
        cells_all = [f"{get(i, threads_all) / 1e6:.2f}" if get(i, threads_all) else "-" for i in ("simd", "embree", "auto")]
        ref = get("reference", 1)
        ratio = lambda i: f"{get(i, 1) / ref:.1f}x" if ref and get(i, 1) else "-"
        eb = frames.get((s, "embree", 1), {})
        build_ms = f"{eb['build_ms']:.1f}" if "build_ms" in eb else "-"
        def autovs(t):
            best = max(get("simd", t) or 0, get("embree", t) or 0)
            auto = get("auto", t)
            if not auto or not best:
                return "-"
            return f"{100 * (best - auto) / best:.1f}% slower" if auto < best else "fastest"
        prims = int(frames[next(k for k in frames if k[0] == s)]["prims"])
        out.append(f"| {s} | {prims} | " + " | ".join(cells + cells_all) + f" | {ratio('simd')} | {ratio('embree')} | {autovs(1)} | {autovs(threads_all)} | {build_ms} |")
    return "\n".join(out)


def scaling_chart(rows, out):
    frames, impls, scenes, _, (x, weight) = ray_cast_frames(rows)
    first = lambda s: frames[next(k for k in frames if k[0] == s)]
    with open(os.path.join(out, "scaling.dat"), "w") as f:
        f.write("# size " + " ".join(impls) + "  (size = spheres + %d x triangles; ns per primary ray, 1 thread)\n" % weight)
        for s in scenes:
            prims = scene_size(first(s), weight)
            vals = [per_ray_ns(frames[(s, i, 1)]) if (s, i, 1) in frames else None for i in impls]
            f.write(f"{prims:g} " + " ".join(f"{v:.3f}" if v else "NaN" for v in vals) + f"  # {s}\n")
    plot = ", ".join(f"'{out}/scaling.dat' using 1:{k + 2} with linespoints lw 2 title '{i}'" for k, i in enumerate(impls))
    gp = f"""set terminal pngcairo size 900,600 font ',11'
set output '{out}/scaling.png'
set logscale xy
set grid
set key top left
set xlabel 'scene size: spheres + {weight} x triangles (the measure auto uses)'
set ylabel 'time per primary ray, ns (1 thread)'
set title 'Ray casting SPD scenes: cost per ray against scene size'
{f"set arrow from {x},graph 0 to {x},graph 1 nohead dt 2 lw 2 lc rgb 'gray40'" if x else ""}
{f"set label 'auto crossover ({x})' at {x},graph 0.95 offset 1,0" if x else ""}
plot {plot}
"""
    subprocess.run(["gnuplot"], input=gp, text=True, check=True)


def kernels(rows):
    """{(kernel, impl): ns per test}; the in-scene throughput rows keyed
    ("throughput_" + primitive, impl)."""
    kern = {}
    for name, b in rows:
        p = name.split("/")
        if p[0] == "kernel":
            kern[(p[1], p[2])] = per_ray_ns(b)
        if p[0] == "throughput":
            kern[("throughput_" + p[1], p[2])] = per_ray_ns(b)
    return kern


def throughput_table(rows):
    out = ["| in a scene (4096 rays x 256 primitives, trace, 1 thread) | impl | ns per ray-primitive test | tests/s |",
           "|---|---|---|---|"]
    for (k, impl), ns in kernels(rows).items():
        if k.startswith("throughput_"):
            out.append(f"| {k[len('throughput_'):]} | {impl} | {ns:.3f} | {1 / ns:.2f} G |")
    return "\n".join(out)


def accuracy_table(rows, acc_csv):
    """Per kernel entry point: ns per test and the error of t against the
    oracle (max, p99) with the bound the properties enforce."""
    kern = kernels(rows)
    out = ["| kernel | impl | ns per test | bound (enforced) | max rel. error | p99 rel. error | cases |",
           "|---|---|---|---|---|---|---|"]
    for a in csv.DictReader(open(acc_csv)):
        ns = kern.get((a["kernel"], a["impl"]))
        out.append(f"| {a['kernel']} | {a['impl']} | {f'{ns:.2f}' if ns else '-'} | {a.get('bound') or '-'} | "
                   f"{float(a['max']):.3g} | {float(a['p99']):.3g} | {a['cases']} |")
    return "\n".join(out)


def accuracy_chart(rows, acc_csv, out):
    kern = kernels(rows)
    with open(os.path.join(out, "accuracy.dat"), "w") as f:
        f.write("# ns max p99 label\n")
        for a in csv.DictReader(open(acc_csv)):
            ns = kern.get((a["kernel"], a["impl"]))
            if ns:
                f.write(f"{ns} {max(float(a['max']), 1e-18)} {max(float(a['p99']), 1e-18)} \"{a['kernel']}/{a['impl']}\"\n")
    gp = f"""set terminal pngcairo size 900,600 font ',11' noenhanced
set output '{out}/accuracy.png'
set logscale xy
set grid
set xlabel 'time per ray, ns (kernel benchmark: one primitive, 4096 rays, 1 thread)'
set ylabel 'relative error of t against the oracle'
set title 'Speed against accuracy: error of t against the oracle on well-conditioned rays (accuracy property)'
set key top right
plot '{out}/accuracy.dat' using 1:2 with points pt 7 ps 1.5 title 'max error', \\
     '' using 1:3 with points pt 5 ps 1.2 title 'p99 error', \\
     '' using 1:2:4 with labels left offset 1,0.6 font ',9' notitle
"""
    subprocess.run(["gnuplot"], input=gp, text=True, check=True)


def main(a):
    bench_json, acc_csv, out = a.bench_json, a.accuracy_csv, a.out_dir
    os.makedirs(out, exist_ok=True)
    ctx, rows = load(bench_json)
    print(frames_table(rows))
    scaling_chart(rows, out)
    if acc_csv and os.path.exists(acc_csv):
        print("\n" + throughput_table(rows))
        print("\n" + accuracy_table(rows, acc_csv))
        accuracy_chart(rows, acc_csv, out)


# Error of each compositing path against the exact (Gmpq) oracle, absolute, in
# [0, 1] units: the deep-mode maxima of props/composite (props/composite/README.md):
# float 3.99 ulps (reference) / 3.23 ulps (simd, oiio) of values <= 1, i.e. at most
# that many times 2^-24; 8 bits 2.69 levels (every implementation), i.e. 2.69 / 255.
COMPOSITE_ERROR = {
    ("reference", "float"): 3.99 * 2**-24, ("simd", "float"): 3.23 * 2**-24, ("oiio", "float"): 3.23 * 2**-24,
    ("reference", "unorm8"): 2.69 / 255, ("simd", "unorm8"): 2.69 / 255, ("oiio", "unorm8"): 2.69 / 255,
}


def composite_frames(rows):
    """{(stack, impl, threads): benchmark} of the compositing frames, the
    stacks in run order, the thread counts."""
    fr = {}
    for name, b in rows:
        p = name.split("/")
        if p[0] != "frame" or p[1] != "composite":
            continue
        fr[(p[2], p[3], int(p[4].split(":")[1]))] = b
    stacks = []
    for s, _, _ in fr:
        if s not in stacks:
            stacks.append(s)
    return fr, stacks, sorted({t for _, _, t in fr})


def composite_table(rows):
    """Mpix/s and GB/s per stack, implementation and thread count, memcpy of the
    same bytes as the yardstick."""
    fr, stacks, threads = composite_frames(rows)
    cols = [(i, t) for t in threads for i in ("reference", "simd", "oiio") if (t == 1 or i != "reference")]
    out = ["| stack (4096 x 4096) | " + " | ".join(f"{i} {t}T Mpix/s (GB/s)" for i, t in cols) +
           " | memcpy 2T GB/s | simd / memcpy 2T | simd / oiio 2T | simd first run 2T ms |",
           "|---" * (1 + len(cols) + 4) + "|"]
    for s in stacks:
        def cell(i, t):
            b = fr.get((s, i, t))
            if not b:
                return "-"
            gb = f" ({b['bytes_per_second'] / 1e9:.1f})" if "bytes_per_second" in b else ""
            return f"{b['items_per_second'] / 1e6:.1f}{gb}"
        cells = [cell(i, t) for i, t in cols]
        tt = threads[-1]
        simd, oiio, mc = fr.get((s, "simd", tt)), fr.get((s, "oiio", tt)), fr.get((s, "memcpy", tt))
        mcs = f"{mc['bytes_per_second'] / 1e9:.1f}" if mc else "-"
        vs_mc = f"{100 * simd['bytes_per_second'] / mc['bytes_per_second']:.0f}%" if simd and mc else "-"
        vs_oiio = f"{simd['items_per_second'] / oiio['items_per_second']:.1f}x" if simd and oiio else "-"
        first = f"{simd['first_ms']:.0f}" if simd and "first_ms" in simd else "-"
        out.append(f"| {s} | " + " | ".join(cells) + f" | {mcs} | {vs_mc} | {vs_oiio} | {first} |")
    return "\n".join(out)


def composite(rows, out):
    """The compositing family's chart: speed against error."""
    fr, stacks, threads = composite_frames(rows)
    if not fr:
        return
    # speed against error: 2-layer stacks, the most threads
    tt = threads[-1]
    with open(os.path.join(out, "composite.dat"), "w") as f:
        f.write("# Mpix/s abs_error label; one block per implementation (gnuplot index)\n")
        for i in ("reference", "simd", "oiio"):
            f.write(f"# {i}\n")
            for k, (stack, storage, rep) in enumerate((("2-layers", "float", "premultiplied"),
                                                       ("2-layers-straight", "float", "straight"),
                                                       ("2-layers-unorm8", "unorm8", "premultiplied"))):
                b = fr.get((stack, i, tt)) or fr.get((stack, i, 1))
                if not b:
                    continue
                # the two float points of one implementation sit at the same error: stagger their labels
                short = "premult" if rep == "premultiplied" else rep
                f.write(f"{b['items_per_second'] / 1e6} {COMPOSITE_ERROR[(i, storage)]} \"{storage} {short}\" {k}\n")
            f.write("\n\n")
    gp = f"""set terminal pngcairo size 900,600 font ',11' noenhanced
set output '{out}/composite.png'
set logscale xy
set grid
set format y '%.0e'
set xlabel 'Mpix/s, 2-layer over at 4096 x 4096 (reference 1 thread, simd and oiio {tt})'
set ylabel 'max abs. error against the exact oracle (deep mode)'
set title 'Compositing: speed against accuracy (float vs 8-bit, straight vs premultiplied)'
set key top left
set yrange [1e-8:0.1]
plot for [i=0:2] '{out}/composite.dat' index i using 1:2 with points pt 7 ps 1.6 title word('reference simd oiio', i+1), \\
     for [i=0:2] '' index i using 1:($2*($4==1 ? 0.55 : 1.8)):3 with labels font ',9' notitle
"""
    subprocess.run(["gnuplot"], input=gp, text=True, check=True)


def stability_table(path):
    """Where each method breaks: per (check, generator, pair), each implementation's
    share of classified failures by label (explained = the oracle predicts it)."""
    rows = list(csv.DictReader(open(path)))
    impls, keys, cell = [], [], {}
    for r in rows:
        k = (r["check"], r["generator"], r["pair"])
        if r["check"] == "accuracy":
            continue
        if k not in keys:
            keys.append(k)
        if r["impl"] not in impls:
            impls.append(r["impl"])
        c = cell.setdefault((k, r["impl"]), {"rays": 0, "labels": {}})
        if r["label"] == "ok":
            c["rays"] = int(r["rays"])
        elif not r["label"].startswith("class:"):
            # rates divide by the rays of the label's class (per), else by all rays
            c["labels"][r["label"]] = (int(r["count"]), int(r["rays"]), r.get("per") or "")
    out = ["| check | generator | pair | " + " | ".join(impls) + " |", "|---" * (3 + len(impls)) + "|"]
    for k in keys:
        cells = []
        for i in impls:
            c = cell.get((k, i))
            if not c:
                cells.append("")
                continue
            wrong = {l: n for l, n in c["labels"].items() if l not in ("silhouette", "no_contact", "ill")}
            if not wrong:
                cells.append(f"right on all {c['rays']}")
            else:
                def share(v):
                    n, den, per = v
                    of = f" {per} rays" if per else ""
                    if 100 * n / den >= 0.1:
                        return f"{100 * n / den:.1f}%" + (f" of {den}{of}" if per else "")
                    return f"{n} of {den}{of}"
                cells.append(", ".join(f"{l} {share(v)}" for l, v in sorted(wrong.items(), key=lambda x: -x[1][0] / x[1][1])))
        out.append(f"| {k[0]} | {k[1]} | {k[2]} | " + " | ".join(cells) + " |")
    return "\n".join(out)


if __name__ == "__main__":
    args = chartlib.args(__doc__)
    main(args)
    rows = load(args.bench_json)[1]
    if composite_frames(rows)[0]:
        print("\n" + composite_table(rows))
    composite(rows, args.out_dir)
    if os.environ.get("LOCKSTEP_STABILITY_CSV") and os.path.exists(os.environ["LOCKSTEP_STABILITY_CSV"]):
        print("\n" + stability_table(os.environ["LOCKSTEP_STABILITY_CSV"]))
