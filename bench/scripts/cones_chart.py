#!/usr/bin/env python3
"""NFF cones tessellated against exact, for BENCHMARKS.md (issue #22).

usage: cones_chart.py STUDY_CSV OUT_DIR [JSON_OUT]

STUDY_CSV is the output of `lockstep_cones_study` (bench/studies/cones_study.cpp):
  ./build/bench/lockstep_cones_study > bench/results/cones_tess.csv
  python3 bench/scripts/cones_chart.py bench/results/cones_tess.csv bench/charts bench/results/cones_tess.json

  cones_tess.png   left: pixels wrong at the cones' silhouettes (the primitive
                   seen differs from the exact ray-cast image and one of the
                   two is a cone) against the cones' triangle count, one curve
                   per scene as tess_error goes 8 .. 1/16 pixel, with the
                   coverage error (background or not) of the same frames and
                   of the SPD's own -t files; right: time per frame against
                   all triangles, with the exact ray casters' times as lines
Writes JSON_OUT (a lockstep-table/1 file that BENCHMARKS.md renders) when
given, through JSON_OUT.tmp and a rename; prints the markdown table.
"""
import datetime
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import chartlib  # noqa: E402

COMMAND = ("./build/bench/lockstep_cones_study > bench/results/cones_tess.csv && python3 "
           "bench/scripts/cones_chart.py bench/results/cones_tess.csv bench/charts bench/results/cones_tess.json")


def load(path):
    rows, head, size = [], None, ""
    with open(path) as fh:
        for n, line in enumerate(fh, 1):
            line = line.strip()
            if not line:
                continue
            if line.startswith("#"):
                size = line.lstrip("# ")
                continue
            cells = line.split(",")
            if head is None:
                head = cells
                continue
            if len(cells) != len(head):
                sys.exit(f"{path}:{n}: expected {len(head)} fields, got {len(cells)}")
            r = dict(zip(head, cells))
            try:
                rows.append(dict(scene=r["scene"], kind=r["kind"], e=float(r["tess_error"]),
                                 cone_tris=int(r["cone_tris"]), tris=int(r["triangles"]), ms=float(r["ms"]),
                                 over=float(r["pct_over_1_255"]), coverage=int(r["coverage_px"]),
                                 silhouette=int(r["cone_silhouette_px"])))
            except (KeyError, ValueError) as e:
                sys.exit(f"{path}:{n}: bad row ({e})")
    return size, rows


def table_rows(rows):
    cols = ["scene", "drawn as", "tess_error (px)", "cone triangles", "all triangles", "ms / frame",
            "% pixels over 1/255", "coverage px", "cone silhouette px"]
    body = []
    for r in rows:
        kind = {"adaptive": "z-buffer, adaptive", "spd-tess": "z-buffer, SPD -t file"}.get(
            r["kind"], r["kind"].replace("exact-", "ray cast, exact: "))
        tess = r["kind"] == "adaptive"
        body.append([r["scene"], kind, f"{r['e']:g}" if tess else "", str(r["cone_tris"]) if tess else "",
                     str(r["tris"]) if r["tris"] else "", f"{r['ms']:.1f}", f"{r['over']:.2f}",
                     str(r["coverage"]), str(r["silhouette"]) if r["silhouette"] >= 0 else "n/a"])
    return cols, body


def table(rows):
    return chartlib.markdown_table(*table_rows(rows))


def summary(rows):
    """Per scene: the exact times, the tessellation that first brings the cone
    silhouette under 0.1% of the pixels, and the SPD -t file's figures."""
    out = {}
    for s in dict.fromkeys(r["scene"] for r in rows):
        rs = [r for r in rows if r["scene"] == s]
        exact = {r["kind"][6:]: r["ms"] for r in rs if r["kind"].startswith("exact-")}
        ad = [r for r in rs if r["kind"] == "adaptive"]
        tess = next((r for r in rs if r["kind"] == "spd-tess"), None)
        out[s] = dict(exact=exact, adaptive=ad, tess=tess)
    return out


def write_json(size, rows, path):
    cols, body = table_rows(rows)
    notes = []
    for s, d in summary(rows).items():
        ad = d["adaptive"]
        if not ad:
            continue
        best = min(d["exact"].values()) if d["exact"] else float("nan")
        fine = next((r for r in ad if r["e"] <= 0.25), ad[-1])
        t = d["tess"]
        notes.append(f"{s}: exact ray casting {best:.0f} ms; tessellated at tess_error {fine['e']:g} "
                     f"({fine['cone_tris']} cone triangles) {fine['ms']:.1f} ms with {fine['silhouette']} cone "
                     f"silhouette pixels, from {ad[0]['silhouette']} at tess_error {ad[0]['e']:g} "
                     f"({ad[0]['cone_tris']} cone triangles)"
                     + (f"; the SPD's -t file ({t['tris']} triangles) {t['ms']:.1f} ms, coverage off on "
                        f"{t['coverage']} pixels against {fine['coverage']} for tess_error {fine['e']:g}" if t else ""))
    doc = {
        "schema": "lockstep-table/1",
        "family": "raster",
        "title": "NFF cones: tessellated against exact",
        "command": COMMAND,
        "date": datetime.date.today().isoformat(),
        "machine": chartlib.machine(),
        "issue": 22,
        "note": (f"{size.replace('cones: ', '')}. The SPD's untessellated lattice-2 (54 cylinders, 27 spheres) and tree-2 (7 cones, 7 "
                 "spheres): the exact image is the reference ray caster's (cones in double, "
                 "core/cone_quadric.h); the exact rows are the optimized ray casters (simd: a scalar double "
                 "pass over the cones each tile's culling keeps; embree: a user geometry), which match it "
                 "(0 pixels over 1/255). Tessellated: the simd z-buffer, Phong per sample, reversed float depth, "
                 "cones (and spheres) tessellated by tess_error (core/viewing.cpp cone_segments: the fewest "
                 "facets around the axis whose inscribed polygon is within tess_error pixels of the circle, "
                 "3..512; open ends, smooth normals). Cone silhouette px: pixels where the primitive seen differs "
                 "from the exact image's and one of the two is a cone; coverage px: background in one image and "
                 "not in the other; % over 1/255 also counts shading (interpolated normals on spheres and cones). "
                 "Times are the best of 5 on one thread on a machine shared with other builds (load 10+): "
                 "ratios, not absolute rates. " + "; ".join(notes) + "."),
        "chart": ["cones_tess.png", "silhouette error and frame time of tessellated cones against facets"],
        "columns": cols,
        "rows": body,
    }
    chartlib.write_table(doc, path)


def main():
    a = chartlib.args(__doc__)
    size, rows = load(a.study_csv)
    out = a.out_dir
    print(table(rows))
    if a.json_out:
        write_json(size, rows, a.json_out)
    dat = os.path.join(out, "cones_tess.dat")
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    floor = 0.5  # zero pixels on the log axis: drawn at the floor
    with open(dat + ".tmp", "w") as f:
        for s in scenes:  # index 2k: adaptive; 2k+1: the SPD -t file
            f.write(f"# {s} adaptive: cone_tris tris ms silhouette coverage tess_error\n")
            for r in rows:
                if r["scene"] == s and r["kind"] == "adaptive":
                    f.write(f"{r['cone_tris']} {r['tris']} {r['ms']} {max(r['silhouette'], floor)} "
                            f"{max(r['coverage'], floor)} {r['e']}\n")
            f.write("\n\n")
            f.write(f"# {s} spd-tess: tris ms coverage\n")
            for r in rows:
                if r["scene"] == s and r["kind"] == "spd-tess":
                    f.write(f"{r['tris']} {r['ms']} {max(r['coverage'], floor)}\n")
            f.write("\n\n")
    os.replace(dat + ".tmp", dat)
    colors = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"]
    left, right = [], []
    for k, s in enumerate(scenes):
        c = colors[k % len(colors)]
        left.append(f"'{dat}' index {2 * k} using 1:4 with linespoints lc rgb '{c}' pt 7 title '{s}: cone silhouette px'")
        left.append(f"'{dat}' index {2 * k} using 1:5 with linespoints lc rgb '{c}' dt 2 pt 6 "
                    f"title '{s}: coverage px'")
        right.append(f"'{dat}' index {2 * k} using 2:3 with linespoints lc rgb '{c}' pt 7 "
                     f"title '{s}: z-buffer, adaptive'")
        right.append(f"'{dat}' index {2 * k + 1} using 1:2 with points lc rgb '{c}' pt 5 ps 1.5 "
                     f"title '{s}: SPD -t file'")
        for r in rows:
            if r["scene"] == s and r["kind"].startswith("exact-"):
                right.append(f"{r['ms']} with lines lc rgb '{c}' dt {2 if r['kind'].endswith('simd') else 3} "
                             f"title '{s}: ray cast exact ({r['kind'][6:]})'")
    # The -t files' coverage against their triangle count is on the right-hand
    # chart's x axis, not the cones': drawn as labels in the note instead.
    subprocess.run(["gnuplot"], text=True, check=True, input=f"""set terminal pngcairo size 1400,560 noenhanced
set output '{out}/cones_tess.png.tmp'
set multiplot layout 1,2 title "NFF cones tessellated against exact ray casting ({size.replace('cones: ', '').split(',')[0]})"
set logscale xy; set grid; set key top right font ",8"
set title "error at the silhouette as the cones' facets grow (tess_error 8 .. 1/16 px)"
set xlabel "cone triangles in the scene"; set ylabel "pixels differing from the exact image ({floor} = none)"
plot {", ".join(left)}
set title "time per frame (1 thread, best of 5)"
set xlabel "triangles drawn (cones + spheres + polygons)"; set ylabel "ms per frame"
set key top left font ",8"
plot {", ".join(right)}
unset multiplot
""")
    os.replace(f"{out}/cones_tess.png.tmp", f"{out}/cones_tess.png")


if __name__ == "__main__":
    main()
