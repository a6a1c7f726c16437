#!/usr/bin/env python3
"""Nothing dropped silently (issue #22), through the CLI, on the scenes in tests/dropped/.

    dropped.py LOCKSTEP SCENE_DIR OUT_DIR

Every row that draws .nff scenes (ray casting, ray tracing, the three rasterizers,
each implementation `lockstep render --help` lists) renders each scene; the ray-cast
reference (double) is the yardstick. A row's image must match it (lockstep diff,
1/255, no pixel over) unless the row's stats line says what it dropped and why
("N dropped (reason)"). Per scene the expectation is stricter:
  plane-1e25   every rasterizer and the reference ray caster and tracer draw it (no drop);
               the float ray casters (simd, embree) may drop it, saying so;
  far-1e25     the rows in double draw it; the simd rasterizers, lighting in float,
               and the float ray casters may report it;
  plane-1e200  every row says it dropped the polygon (its normal overflows double).
Exit 0 when all hold, 1 otherwise (each failure printed).
"""
import os
import re
import subprocess
import sys

lockstep, scene_dir, out_dir = sys.argv[1:4]
os.makedirs(out_dir, exist_ok=True)

ROWS = [("raycast", "reference"), ("raycast", "simd"), ("raycast", "embree"), ("ray_trace", "reference"),
        ("ray_trace", "embree"), ("zbuffer", "reference"), ("zbuffer", "simd"), ("scanline", "reference"),
        ("scanline", "simd"), ("painter", "reference"), ("painter", "simd")]
# Must draw it, with nothing dropped: the rows that work in double. The simd
# rasterizers clip in double too (plane-1e25), but light in float lanes: a
# surface 1e25 from the eye (far-1e25) they may only report.
DOUBLE = {("raycast", "reference"), ("ray_trace", "reference"), ("zbuffer", "reference"), ("scanline", "reference"),
          ("painter", "reference"), ("painter", "simd")}
MUST_DRAW = {"plane-1e25": DOUBLE | {("zbuffer", "simd"), ("scanline", "simd")}, "far-1e25": DOUBLE}
DROPPED = re.compile(r"(\d+) dropped \((.*?)\)(?=; \d+ dropped|, |\s*->|$)")

failures = []


def render(scene, algo, impl):
    out = os.path.join(out_dir, f"{os.path.basename(scene)[:-4]}-{algo}-{impl}.exr")
    extra = ["--shadows", "none", "--depth", "1"] if algo == "ray_trace" else []
    p = subprocess.run([lockstep, "render", scene, "--algo", algo, "--impl", impl, "-o", out] + extra,
                       capture_output=True, text=True)
    if p.returncode != 0:
        failures.append(f"{scene} {algo}/{impl}: exit {p.returncode}: {p.stderr.strip()}")
        return None, []
    return out, DROPPED.findall(p.stderr)


def same(a, b):
    p = subprocess.run([lockstep, "diff", a, b, "--fail", "1/255", "--failpercent", "0"], capture_output=True, text=True)
    return p.returncode == 0


for name in ("plane-1e25", "far-1e25", "plane-1e200"):
    scene = os.path.join(scene_dir, name + ".nff")
    yard, yard_drops = render(scene, "raycast", "reference")
    for algo, impl in ROWS:
        out, drops = render(scene, algo, impl)
        if out is None:
            continue
        said = "; ".join(f"{n} ({why})" for n, why in drops)
        if name == "plane-1e200":
            if not any("normal out of double range" in why for _, why in drops):
                failures.append(f"{name} {algo}/{impl}: the overflowing polygon was not reported dropped")
            print(f"{name:12} {algo:9} {impl:10} dropped: {said}")
            continue
        ok = same(yard, out)
        if (algo, impl) in MUST_DRAW[name] and (drops or not ok):
            failures.append(f"{name} {algo}/{impl}: must draw it: {'differs from the ray-cast reference' if not ok else ''} {said}")
        elif not ok and not drops:
            failures.append(f"{name} {algo}/{impl}: differs from the ray-cast reference and reported nothing dropped")
        print(f"{name:12} {algo:9} {impl:10} {'same' if ok else 'DIFFERS'}{'; dropped: ' + said if said else ''}")

# The llvmpipe peer (where built) draws Gouraud only: against the reference z-buffer's Gouraud image.
for name in ("plane-1e25", "far-1e25"):
    scene = os.path.join(scene_dir, name + ".nff")
    outs = {}
    for impl in ("reference", "llvmpipe"):
        out = os.path.join(out_dir, f"{name}-gouraud-{impl}.exr")
        p = subprocess.run([lockstep, "render", scene, "--algo", "zbuffer", "--impl", impl, "--shading", "gouraud",
                            "-o", out], capture_output=True, text=True)
        outs[impl] = (p.returncode, out, DROPPED.findall(p.stderr), p.stderr)
    rc, out, drops, err = outs["llvmpipe"]
    if rc != 0:
        print(f"{name:12} zbuffer   llvmpipe   not run: {err.strip()}")
        continue
    ok = same(outs["reference"][1], out)
    said = "; ".join(f"{n} ({why})" for n, why in drops)
    if not ok and not drops:
        failures.append(f"{name} zbuffer/llvmpipe: differs from the reference z-buffer and reported nothing dropped")
    print(f"{name:12} zbuffer   llvmpipe   {'same' if ok else 'DIFFERS'}{'; dropped: ' + said if said else ''}")

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
