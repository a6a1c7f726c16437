#!/usr/bin/python3
"""One-shot against warm, huge pages against 4 KiB pages (issue #35).

    /usr/bin/python3 bench/scripts/oneshot_pages.py [--runs N] [--quick] [--build DIR] [--out FILE]

Each call is a fresh process, as a user runs the CLI, the calls alternated run
by run (A B C ... A B C ...) so that a shared machine's load falls on all
alike; every figure is the median of the runs (the frame's range beside it).
Per call: the frame as the stats line gives it (marching cubes: the
extraction), the whole process's wall, minor page faults and system time
(/usr/bin/time -v). Memory: "huge pages" is lockstep as a user gets it (large
buffers advised onto transparent huge pages where the kernel's mode allows,
core/large_buffer.h); "4 KiB pages" the same binary with LOCKSTEP_HUGE_PAGES=0
(the fallback where the mode is `never`). Warm: the last of five frames drawn
in one process (--repeat 5: each frame's memory is the one before's).

The peer, vtkFlyingEdges3D (VTK 9.1 through Python, a fresh filter per call,
Update() alone: bench/scripts/vtk_flying_edges_oneshot.py), is measured the
same way: its default (glibc's allocator as VTK gets it: large blocks mmapped
and unmapped, fresh pages every call) and with glibc's huge pages
(GLIBC_TUNABLES=glibc.malloc.hugetlb=1), one-shot (the first Update in a fresh
process) and warm (the third).

The peers that run inside lockstep's process (Embree, llvmpipe, VolPack,
OpenImageIO) are measured with their own allocations as glibc gives them by
default and with glibc's huge pages.

The gyroid: sin(kx)cos(ky) + sin(ky)cos(kz) + sin(kz)cos(kx), 4 periods across
[-1, 1]^3, 256^3 float samples written as a raw NRRD (2,521,956 triangles at
iso 0; --quick: 64^3). Writes bench/results/oneshot_pages.json
(lockstep-table/1, with its targets) and checks that both memory modes write
the same bytes.
"""
import argparse
import datetime
import filecmp
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def gyroid(path, n, periods=4):
    t = np.linspace(-1.0, 1.0, n)
    k = 2 * np.pi * periods / 2.0
    x, y, z = t[None, None, :] * k, t[None, :, None] * k, t[:, None, None] * k
    g = (np.sin(x) * np.cos(y) + np.sin(y) * np.cos(z) + np.sin(z) * np.cos(x)).astype("<f4")
    with open(path, "wb") as f:
        f.write(f"NRRD0004\n# gyroid, {periods} periods across [-1, 1]^3 (bench/scripts/oneshot_pages.py)\n"
                f"type: float\ndimension: 3\nsizes: {n} {n} {n}\nendian: little\nencoding: raw\n\n".encode())
        f.write(g.tobytes())


def timed(cmd, env):
    r = subprocess.run(["/usr/bin/time", "-v", *cmd], capture_output=True, text=True, env=env)
    if r.returncode != 0:
        sys.exit(f"oneshot_pages: {' '.join(cmd)}: exit {r.returncode}\n{r.stderr[-2000:]}")
    wall = re.search(r"Elapsed \(wall clock\) time.*: (?:(\d+):)?(\d+):([\d.]+)", r.stderr)
    secs = (int(wall.group(1) or 0) * 60 + int(wall.group(2))) * 60 + float(wall.group(3))
    faults = int(re.search(r"Minor \(reclaiming a frame\) page faults: (\d+)", r.stderr).group(1))
    system = float(re.search(r"System time \(seconds\): ([\d.]+)", r.stderr).group(1))
    return {"wall": secs, "faults": faults, "system": system, "out": r.stdout, "err": r.stderr}


def frame_of(err):
    """The stats line's frame seconds ('wall X s': build and run; marching cubes builds nothing, so its
    extraction; composite: 'N layers (...), X s')."""
    m = re.search(r", wall ([\d.]+) s", err) or re.search(r" layers \([^)]*\), ([\d.]+) s", err)
    return float(m.group(1)) if m else None


def first_of(err):
    m = re.search(r"the first: wall ([\d.]+) s", err)
    return float(m.group(1)) if m else None


def med(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=9)
    ap.add_argument("--quick", action="store_true", help="one run, a 64^3 gyroid: that it still runs")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "oneshot_pages.json"))
    a = ap.parse_args()
    runs = 1 if a.quick else a.runs
    L = os.path.join(os.path.abspath(a.build), "lockstep")
    spd = os.environ.get("LOCKSTEP_SPD_DIR", os.path.join(ROOT, "..", "shared", "spd"))
    vols = os.environ.get("LOCKSTEP_VOLUMES_DIR", os.path.join(ROOT, "..", "shared", "volumes"))
    tmp = tempfile.mkdtemp(prefix="oneshot-pages-")
    n = 64 if a.quick else 256
    g = os.path.join(tmp, "gyroid.nrrd")
    gyroid(g, n)
    base = dict(os.environ, LOCKSTEP_NO_SAVE="1")
    mem = {"huge pages": dict(base), "4 KiB pages": dict(base, LOCKSTEP_HUGE_PAGES="0")}
    vtk_env = {"default": dict(base), "glibc huge pages": dict(base, GLIBC_TUNABLES="glibc.malloc.hugetlb=1")}
    have_vtk = subprocess.run(["/usr/bin/python3", "-c", "import vtk"], capture_output=True).returncode == 0
    vtk_script = os.path.join(ROOT, "bench", "scripts", "vtk_flying_edges_oneshot.py")

    # name: (command without -o, output extension, verb of the stats line, threads)
    size = "256x256" if a.quick else "1024x1024"
    lock = {f"isosurface simd gyroid {n}^3": (["isosurface", g, "--iso", "0", "--impl", "simd"], "ply", "extract")}
    renders = {}
    if os.path.exists(os.path.join(spd, "sombrero-2.nff")):
        renders[f"render zbuffer simd sombrero-2 {size}"] = (
            ["render", os.path.join(spd, "sombrero-2.nff"), "--algo", "zbuffer", "--impl", "simd", "--shading", "flat",
             "--size", size], "exr", "draw")
    if os.path.exists(os.path.join(spd, "balls-4.nff")):
        renders[f"render ray_cast simd balls-4 {size}"] = (
            ["render", os.path.join(spd, "balls-4.nff"), "--impl", "simd", "--size", size], "exr", "cast")
    if os.path.exists(os.path.join(vols, "cthead.nhdr")):
        vs = "128x128" if a.quick else "512x512"
        renders[f"volume simd cthead ct-bone {vs}"] = (
            ["volume", os.path.join(vols, "cthead.nhdr"), "--tf", "ct-bone", "--view", "-90,-15,180", "--impl", "simd",
             "--size", vs], "exr", "cast")
    # The other families, each its simd (or embree) row on one of its benchmark inputs.
    others = {}
    if os.path.exists(os.path.join(spd, "sombrero-2.nff")):
        for algo in ("scanline", "painter"):
            others[f"render {algo} simd sombrero-2 {size}"] = (
                ["render", os.path.join(spd, "sombrero-2.nff"), "--algo", algo, "--impl", "simd", "--shading", "flat",
                 "--size", size], "exr", "draw")
    if os.path.exists(os.path.join(spd, "balls-3.nff")):
        rs = "128x128" if a.quick else "512x512"
        others[f"render ray_trace embree balls-3 {rs}"] = (
            ["render", os.path.join(spd, "balls-3.nff"), "--algo", "ray_trace", "--impl", "embree", "--size", rs],
            "exr", "trace")
    if os.path.exists(os.path.join(vols, "cthead.nhdr")):
        for algo, extra in (("splat", ["--tf", "ct-bone"]), ("iso", ["--iso", "1200"])):
            others[f"volume {algo} simd cthead {vs}"] = (
                ["volume", os.path.join(vols, "cthead.nhdr"), "--algo", algo, *extra, "--view", "-90,-15,180",
                 "--impl", "simd", "--size", vs], "exr", "cast")
    # Compositing: two layers rendered here (the z-buffer's sombrero-2 over balls-1), 2048^2 float.
    cs = "256x256" if a.quick else "2048x2048"
    layers = []
    for scene in ("sombrero-2", "balls-1"):
        if os.path.exists(os.path.join(spd, scene + ".nff")):
            layers.append(os.path.join(tmp, f"layer-{scene}.exr"))
            subprocess.run([L, "render", os.path.join(spd, scene + ".nff"), "--algo", "zbuffer", "--size", cs, "-o",
                            layers[-1]], check=True, capture_output=True)
    if len(layers) == 2:
        others[f"composite simd 2 layers {cs}"] = (["composite", *layers, "--impl", "simd"], "exr", "composite")
    renders.update(others)
    # The production peers that run inside lockstep's process (a row each):
    # their own allocations are glibc's as they get it ("huge pages": lockstep's
    # buffers on huge pages, the peer's as its default) or with glibc's huge
    # pages too ("glibc huge pages"). POV-Ray runs as a process of its own.
    version = subprocess.run([L, "--version"], capture_output=True, text=True).stdout
    peers = {}
    if os.path.exists(os.path.join(spd, "balls-4.nff")):
        peers[f"render ray_cast embree balls-4 {size} (peer)"] = (
            ["render", os.path.join(spd, "balls-4.nff"), "--impl", "embree", "--size", size], "exr", "cast")
    if "llvmpipe row: built" in version and os.path.exists(os.path.join(spd, "sombrero-2.nff")):
        peers[f"render zbuffer llvmpipe sombrero-2 {size} (peer)"] = (
            ["render", os.path.join(spd, "sombrero-2.nff"), "--algo", "zbuffer", "--impl", "llvmpipe", "--shading",
             "flat", "--size", size], "exr", "draw")
    if "volpack row: built" in version and os.path.exists(os.path.join(vols, "cthead.nhdr")):
        peers[f"volume volpack cthead ct-bone {vs} (peer)"] = (
            ["volume", os.path.join(vols, "cthead.nhdr"), "--tf", "ct-bone", "--view", "-90,-15,180", "--impl",
             "volpack", "--size", vs], "exr", "cast")
    if len(layers) == 2:
        peers[f"composite oiio 2 layers {cs} (peer)"] = (["composite", *layers, "--impl", "oiio"], "exr", "composite")
    peer_mem = {"huge pages": mem["huge pages"],
                "glibc huge pages": dict(mem["huge pages"], GLIBC_TUNABLES="glibc.malloc.hugetlb=1")}
    calls = []  # (row name, memory, threads, argv, env, verb, kind)
    for name, (cmd, ext, verb) in {**lock, **renders, **peers}.items():
        for t in ((1, 2) if name.startswith("isosurface") else (1,)):
            for m, env in (peer_mem if name in peers else mem).items():
                out = os.path.join(tmp, f"{len(calls)}.{ext}")
                calls.append((name, m, t, [L, *cmd, "--threads", str(t), "-o", out], env, verb, "oneshot", out))
            out = os.path.join(tmp, f"{len(calls)}.{ext}")
            calls.append((name, "huge pages", t, [L, *cmd, "--threads", str(t), "--repeat", "5", "-o", out],
                          mem["huge pages"], verb, "warm", out))
    if have_vtk:
        for t in (1, 2):
            for m, env in vtk_env.items():
                calls.append((f"vtkFlyingEdges3D gyroid {n}^3 (peer, Python VTK 9.1)", m, t,
                              ["/usr/bin/python3", vtk_script, g, "0", str(t), "3"], env, "update", "vtk", None))
    calls.append(("lockstep --version (process start)", "huge pages", 1, [L, "--version"], mem["huge pages"], None,
                  "start", None))

    res = {i: {"frame": [], "first": [], "wall": [], "faults": [], "system": []} for i in range(len(calls))}
    outputs = {}
    for k in range(runs):
        for i, (name, m, t, cmd, env, verb, kind, out) in enumerate(calls):
            r = timed(cmd, env)
            d = res[i]
            d["wall"].append(r["wall"])
            if kind == "vtk":
                ups = re.findall(r"update ([\d.]+) s \((\d+) page faults, system ([\d.]+) s\)", r["out"])
                d["frame"].append(float(ups[0][0]))   # one-shot: the first Update of the process
                d["first"].append(float(ups[-1][0]))  # warm: the last
                d["faults"].append(int(ups[0][1]))
                d["system"].append(float(ups[0][2]))
            else:
                d["frame"].append(frame_of(r["err"]) if verb else None)
                d["first"].append(first_of(r["err"]))
                d["faults"].append(r["faults"])
                d["system"].append(r["system"])
            if out and kind == "oneshot":
                outputs.setdefault((name, t), []).append(out)
        print(f"oneshot_pages: run {k + 1} of {runs}", file=sys.stderr, flush=True)
    # Both memory modes write the same meshes byte for byte and the same
    # pixels (an EXR's header holds the time it was written: compared by
    # `lockstep diff`, every channel equal).
    def same(x, y):
        if x.endswith(".exr"):
            r = subprocess.run([L, "diff", x, y, "--fail", "0", "--warn", "0"], capture_output=True, text=True)
            return r.returncode == 0 and re.search(r"max error +0 ", r.stdout) is not None
        return filecmp.cmp(x, y, shallow=False)

    for (name, t), files in outputs.items():
        if name in peers:
            continue  # a peer's output need not be bit-identical run to run (llvmpipe's threads)
        for f in files[1:]:
            if not same(files[0], f):
                sys.exit(f"oneshot_pages: {name} ({t} thread(s)): {files[0]} and {f} differ")

    def fig(i, key):
        return med(res[i][key])

    def rng(i):
        xs = [x for x in res[i]["frame"] if x is not None]
        return f"{min(xs):.3f}-{max(xs):.3f}" if xs else "n/a"

    r3 = lambda x: None if x is None else round(x, 3)
    start = fig(len(calls) - 1, "wall")
    rows, at = [], {}
    for i, (name, m, t, cmd, env, verb, kind, out) in enumerate(calls):
        if kind == "warm":
            continue
        warm = None
        if kind == "vtk":
            warm = fig(i, "first")
        else:
            for j, c in enumerate(calls):
                if c[6] == "warm" and c[0] == name and c[2] == t:
                    warm = fig(j, "frame")
        row = [name, m, t, r3(fig(i, "frame")) if kind != "start" else "n/a", rng(i) if kind != "start" else "n/a",
               r3(warm) if warm is not None else "n/a",
               r3(fig(i, "wall")) if kind != "vtk" else "n/a", int(fig(i, "faults")), r3(fig(i, "system"))]
        at[(name, m, t)] = row
        rows.append(row)

    targets = []
    mc = f"isosurface simd gyroid {n}^3"
    vtk = f"vtkFlyingEdges3D gyroid {n}^3 (peer, Python VTK 9.1)"
    if not a.quick:
        for t, limit in ((1, 0.10), (2, 0.07)):
            e = at[(mc, "huge pages", t)][3]
            targets.append({"issue": 35, "text": f"marching cubes, 256^3 gyroid, fresh process: extract <= {limit} s on {t} thread(s)",
                            "measured": f"{e:.3f} s (median; range {at[(mc, 'huge pages', t)][4]})", "met": e <= limit})
        if have_vtk:
            for t in (1, 2):
                e = at[(mc, "huge pages", t)][3]
                vd, vh = at[(vtk, "default", t)][3], at[(vtk, "glibc huge pages", t)][3]
                targets.append({"issue": 35, "text": f"marching cubes one-shot >= 3x faster than vtkFlyingEdges3D's default one-shot ({t} thread(s))",
                                "measured": f"{vd:.3f} / {e:.3f} s = {vd / e:.1f}x", "met": vd / e >= 3})
                targets.append({"issue": 35, "text": f"marching cubes one-shot faster than vtkFlyingEdges3D one-shot given huge pages ({t} thread(s))",
                                "measured": f"{e:.3f} s vs {vh:.3f} s", "met": e < vh})
        w = at[(mc, "huge pages", 1)][6]
        targets.append({"issue": 35, "text": "marching cubes, the whole call (read the NRRD, extract on one thread, write the PLY) <= 0.4 s",
                        "measured": f"{w:.3f} s (median wall)", "met": w <= 0.4})
        # The one-shot frame (the stats line's, in a fresh process) against the
        # warm frame plus a process's start; the whole call also reads the
        # input and writes the image, which no warm frame includes.
        for name in [n for n in renders if n not in others]:
            row = at[(name, "huge pages", 1)]
            limit = 1.5 * (start + row[5])
            targets.append({"issue": 35, "text": f"one-shot {name}: its frame in a fresh process within 1.5x of the warm frame plus process start",
                            "measured": f"{row[3]:.3f} s vs 1.5 x ({start:.3f} + {row[5]:.3f}) = {limit:.3f} s "
                                        f"(the whole call, reading the input and writing the image: {row[6]:.3f} s)",
                            "met": row[3] <= limit})

    # The one-thread extraction's spread, said in the note: its frames are
    # bimodal on a VM whose host backs guest memory as it is first touched.
    spread = ""
    if not a.quick:
        i1 = next(i for i, c in enumerate(calls) if c[0] == mc and c[1] == "huge pages" and c[2] == 1 and c[6] != "warm")
        xs = [x for x in res[i1]["frame"] if x is not None]
        over = sum(1 for x in xs if x > 0.10)
        spread = (f"The one-thread extraction is bimodal on this VM: near its warm frame when the 2 MiB pages the "
                  f"kernel hands out are already backed by the VM's host, 0.1-0.15 s of system time more when they "
                  f"are not (its 33 fresh huge pages): this run {over} of {len(xs)} calls over 0.10 s (median "
                  f"{med(xs):.3f} s, warm {at[(mc, 'huge pages', 1)][5]:.3f} s), so its target is met by the "
                  f"median, not by every call. ")
    load = os.getloadavg()
    machine = subprocess.run("lscpu | sed -n 's/^Model name: *//p'", shell=True, capture_output=True,
                             text=True).stdout.strip()
    thp = open("/sys/kernel/mm/transparent_hugepage/enabled").read().strip()
    doc = {
        "schema": "lockstep-table/1",
        "title": "One-shot and warm, huge pages and 4 KiB pages (issue #35)",
        "command": "/usr/bin/python3 bench/scripts/oneshot_pages.py" + (" --quick" if a.quick else ""),
        "date": datetime.date.today().isoformat(),
        "order": 90,
        "machine": f"{machine}, {os.cpu_count()} cores, load average {load[0]:.1f} at the end; THP: {thp}",
        "note": (f"Medians of {runs} runs, the calls alternated run by run; each call a fresh process. frame s: "
                 "the stats line's frame (marching cubes: the extraction; the peer: its first Update() in the "
                 "process), its range over the runs beside it; warm: the fifth frame of `--repeat 5` (the "
                 "peer: its third Update); call wall, minor faults, system s: the whole process (/usr/bin/time "
                 "-v; the peer: its Update alone, Python's start is not VTK's cost). huge pages: lockstep as "
                 "a user gets it (core/large_buffer.h); 4 KiB pages: LOCKSTEP_HUGE_PAGES=0, the fallback where "
                 "the kernel's mode is never; both write the same bytes (checked: meshes byte for byte, images pixel for pixel). The peer's default is glibc's "
                 "allocator as VTK gets it; glibc huge pages: GLIBC_TUNABLES=glibc.malloc.hugetlb=1. The peers that "
                 "run inside lockstep's process (Embree, llvmpipe, VolPack, OpenImageIO; rows marked peer): huge "
                 "pages is lockstep's buffers on huge pages and the peer's own allocations as glibc gives them by "
                 "default, glibc huge pages the same with GLIBC_TUNABLES=glibc.malloc.hugetlb=1; POV-Ray runs as a "
                 "process of its own and is not measured here. Where huge pages lose a frame: composite simd's output, on "
                 "4 KiB pages, takes the memory the layer reader has just freed (warm), while a huge-page buffer "
                 "needs room to align and gets fresh 2 MiB pages (several ms each on this VM, whose host backs "
                 "guest memory as it is first touched); the call is still faster. " + spread
                 + os.environ.get("ONESHOT_NOTE", "")),
        "columns": ["call", "memory", "threads", "frame s", "frame range s", "warm frame s", "call wall s",
                    "minor faults", "system s"],
        "rows": rows,
        "targets": targets,
    }
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out + ".tmp", "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    os.replace(a.out + ".tmp", a.out)
    shutil.rmtree(tmp, ignore_errors=True)
    for r in rows:
        print(" | ".join(str(c) for c in r))
    for t in targets:
        print(("MET     " if t["met"] else "NOT MET ") + t["text"] + ": " + t["measured"])


if __name__ == "__main__":
    main()
