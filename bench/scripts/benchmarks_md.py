#!/usr/bin/env python3
"""Write BENCHMARKS.md from bench/results/ and bench/targets.json.

usage: benchmarks_md.py [--check] [--partial] [--results DIR] [--targets FILE] [--out FILE]

The page is generated, never edited: every table comes from a results file
(Google Benchmark JSON, the studies' CSVs, lockstep-table/1 JSON), every
verdict from bench/targets.json evaluated over those files. The tables are
made by the chart scripts' own table functions (charts.py, raster_charts.py,
volume_charts.py, mc_chart.py), so that the page and the charts read the data
the same way. Standard library only; /usr/bin/python3 runs it.

  --check   write nothing; exit 1 (with a diff) if OUT differs from what the
            results make (the ctest benchmarks_md.current)
  --partial results of a quick run (bench/run.sh --quick): a target whose
            expression fails on them (an empty list indexed, max() of
            nothing) is stated "not measured" instead of an error

Results files that are absent leave their tables out (a clone without a
benchmark run still gets a page); a malformed one is an error naming the file
(exit 2, nothing written). The page is written to OUT.tmp, then renamed.

bench/targets.json is a list of targets, each {"issue", "family", "text",
"vars": {name: expression}, "value": expression, "min" and/or "max",
"measured": a str.format template over the vars and value}: "met" when min <=
value <= max. Expressions are Python arithmetic (comprehensions, f-strings, no
attributes) over gb(file, benchmark, counter="ms") (a Google Benchmark median;
"ms" is its real time), names(file, regex) (the regex's groups of the matching
benchmark names), column(file, col) and cell(file, first_cell, col) (a
lockstep-table/1 file), rows(csv_file, column=value...) (a CSV's rows as dicts
of strings), painter() (raster_study.csv's painter summary) and min, max, sum,
len, zip, sorted, float, int, abs, round, all, any. A target whose data is
absent is stated "not measured", never met.

A lockstep-table/1 file (bench/results/*.json with "schema": "lockstep-table/1")
is rendered as a section: {"title", "command", "date", "machine", "note",
"columns": [...], "rows": [[...]], "targets": [{"text", "measured", "met"}]};
optional "family" (ray_cast, composite, raster, marching_cubes, volume,
ray_trace) puts it in that family's section (else under "Other measurements"),
"order" sorts it there, "issue" numbers its targets in the summary, "source" is
provenance, "chart" ([png in bench/charts, alt text]) shows its chart.
"""
import ast
import csv
import difflib
import json
import os
import re
import sys

SCRIPTS = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(SCRIPTS))
sys.path.insert(0, SCRIPTS)
import charts  # noqa: E402
import mc_chart  # noqa: E402
import radiosity_chart  # noqa: E402
import texture_chart  # noqa: E402
import texture_map_chart  # noqa: E402
import raster_charts  # noqa: E402
import volume_charts  # noqa: E402

FAMILIES = ["ray_cast", "composite", "raster", "marching_cubes", "volume", "ray_trace", "radiosity"]


class InputError(Exception):
    """A results or targets file that cannot be read: exit 2, nothing written."""

    def __init__(self, path, msg, line=None):
        rel = os.path.relpath(path, ROOT)
        where = (path if rel.startswith("..") else rel) + (f":{line}" if line else "")
        super().__init__(f"{where}: {msg}")


class Missing(Exception):
    """Data a target needs is not in the results (file absent, benchmark not run)."""


class EvalError(InputError):
    """A target's expression failed on the results (an error unless --partial)."""


class Results:
    """bench/results/, each file read once, on demand."""

    def __init__(self, folder):
        self.dir = folder
        self.cache = {}

    def path(self, name):
        return os.path.join(self.dir, name)

    def has(self, name):
        return os.path.exists(self.path(name))

    def read(self, name, how):
        key = (name, how.__name__)
        if key not in self.cache:
            p = self.path(name)
            if not os.path.exists(p):
                raise Missing(f"{name} absent")
            try:
                self.cache[key] = how(p)
            except json.JSONDecodeError as e:
                raise InputError(p, f"not JSON: {e.msg}", e.lineno)
            except (KeyError, IndexError, ValueError, TypeError, AttributeError, csv.Error) as e:
                raise InputError(p, f"unexpected content ({type(e).__name__}: {e})")
        return self.cache[key]

    def bench(self, name):
        """Google Benchmark JSON: (context, {name: median benchmark})."""
        ctx, rows = self.read(name, charts.load)
        return ctx, dict(rows)

    def table(self, name):
        def load_table(p):
            d = json.load(open(p))
            for k in ("title", "columns", "rows"):
                if k not in d:
                    raise InputError(p, f'lockstep-table/1 without "{k}"')
            for i, r in enumerate(d["rows"]):
                if not isinstance(r, list) or len(r) != len(d["columns"]):
                    raise InputError(p, f"row {i + 1} is not a list of {len(d['columns'])} cells")
            for t in d.get("targets", []):
                if not isinstance(t, dict) or not all(k in t for k in ("text", "measured", "met")):
                    raise InputError(p, f'a target needs "text", "measured" and "met": {json.dumps(t)[:80]}')
            c = d.get("chart")
            if c is not None and not (isinstance(c, list) and len(c) == 2 and all(isinstance(x, str) for x in c)):
                raise InputError(p, '"chart" is not [png name, alt text]')
            return d
        return self.read(name, load_table)

    def csv_rows(self, name):
        return self.read(name, lambda p: list(csv.DictReader(open(p))))

    def lockstep_tables(self):
        out = []
        for f in sorted(os.listdir(self.dir)):
            if f.endswith(".json"):
                try:
                    with open(self.path(f)) as fh:
                        head = json.load(fh)
                except json.JSONDecodeError as e:
                    raise InputError(self.path(f), f"not JSON: {e.msg}", e.lineno)
                if isinstance(head, dict) and head.get("schema") == "lockstep-table/1":
                    out.append((f, self.table(f)))
        return out


# ---- targets: checkable expressions over the results

def ms_of(b):
    return b["real_time"] * {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b.get("time_unit", "ns")]


def helpers(res):
    def gb(file, name, counter="ms"):
        rows = res.bench(file)[1]
        if name not in rows:
            raise Missing(f"{name} not in {file}")
        b = rows[name]
        if counter == "ms":
            return ms_of(b)
        if counter not in b:
            raise Missing(f"{name} in {file} has no {counter}")
        return b[counter]

    def names(file, pattern):
        out = []
        for n in res.bench(file)[1]:
            m = re.fullmatch(pattern, n)
            if m:
                out.append(m.group(1) if len(m.groups()) == 1 else m.groups())
        return out

    def column(file, col):
        t = res.table(file)
        if col not in t["columns"]:
            raise Missing(f"no column {col!r} in {file}")
        k = t["columns"].index(col)
        return [r[k] for r in t["rows"]]

    def cell(file, row, col):
        keys = column(file, res.table(file)["columns"][0])
        if row not in keys:
            raise Missing(f"no row {row!r} in {file}")
        return column(file, col)[keys.index(row)]

    def rows(file, **eq):
        return [r for r in res.csv_rows(file) if all(r.get(k) == v for k, v in eq.items())]

    def painter():
        """The painter study's kinds of scene: [{cases, wrong, reported, ..., split}]."""
        return list(raster_charts.painter_summary(res.read("raster_study.csv", raster_charts.sections)["painter"]).values())

    return dict(gb=gb, names=names, column=column, cell=cell, rows=rows, painter=painter, min=min, max=max, sum=sum,
                len=len, float=float, int=int, abs=abs, all=all, any=any, sorted=sorted, round=round, zip=zip)


ALLOWED = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.BoolOp, ast.Compare, ast.Call, ast.Name, ast.Load, ast.Store,
           ast.Constant, ast.Tuple, ast.List, ast.Subscript, ast.GeneratorExp, ast.ListComp, ast.comprehension,
           ast.JoinedStr, ast.FormattedValue, ast.IfExp, ast.keyword, ast.operator, ast.unaryop, ast.cmpop,
           ast.boolop)


def safe_eval(expr, env, where):
    """An arithmetic expression over the helpers: no attributes, no lambdas,
    calls to named helpers only."""
    try:
        tree = ast.parse(expr, mode="eval")
    except SyntaxError as e:
        raise InputError(where[0], f"{expr!r}: {e.msg}", where[1]) from None
    for node in ast.walk(tree):
        if not isinstance(node, ALLOWED):
            raise InputError(where[0], f"{expr!r}: {type(node).__name__} is not allowed in a target", where[1])
    try:
        return eval(compile(tree, "<target>", "eval"), {"__builtins__": {}, **env})
    except (Missing, InputError):
        raise
    except Exception as e:  # a wrong expression is the targets file's error, not a crash
        raise EvalError(where[0], f"{expr!r}: {type(e).__name__}: {e}", where[1])


def line_of(path, text):
    for i, line in enumerate(open(path), 1):
        if json.dumps(text) in line:
            return i
    return None


def evaluate_targets(path, res, partial=False):
    """[(issue, family, text, measured, verdict)] from bench/targets.json."""
    if not os.path.exists(path):
        return []
    try:
        targets = json.load(open(path))
    except json.JSONDecodeError as e:
        raise InputError(path, f"not JSON: {e.msg}", e.lineno)
    if not isinstance(targets, list):
        raise InputError(path, "expected a list of targets")
    out = []
    for t in targets:
        if not isinstance(t, dict) or not all(k in t for k in ("issue", "text", "value", "measured")):
            raise InputError(path, f"a target needs issue, text, value and measured: {json.dumps(t)[:80]}")
        where = (path, line_of(path, t["text"]))
        env = helpers(res)
        try:
            for name, expr in t.get("vars", {}).items():
                env[name] = safe_eval(expr, env, where)
            value = safe_eval(t["value"], env, where)
        except Missing as e:
            out.append((t["issue"], t.get("family", ""), t["text"], f"not measured ({e})", "no data"))
            continue
        except EvalError as e:
            if not partial:
                raise
            out.append((t["issue"], t.get("family", ""), t["text"], f"not measured (partial results: {e})", "no data"))
            continue
        if not isinstance(value, (int, float)):
            raise InputError(path, f"value of {t['text']!r} is not a number: {value!r}", where[1])
        met = ("min" not in t or value >= t["min"]) and ("max" not in t or value <= t["max"])
        try:
            measured = t["measured"].format(value=value, **{k: env[k] for k in t.get("vars", {})})
        except (KeyError, IndexError, ValueError, TypeError, AttributeError) as e:
            raise InputError(path, f"measured of {t['text']!r}: {e}", where[1])
        out.append((t["issue"], t.get("family", ""), t["text"], measured, "**met**" if met else "**not met**"))
    return out


# ---- rendering

def esc(v):
    if isinstance(v, float):
        v = format(v, "g")
    return str(v).replace("|", "\\|")


def md_table(columns, rows):
    out = ["| " + " | ".join(esc(c) for c in columns) + " |", "|---" * len(columns) + "|"]
    out += ["| " + " | ".join(esc(c) for c in r) + " |" for r in rows]
    return "\n".join(out)


def when(ctx):
    """A Google Benchmark context's date as 2026-11-25 18:44 UTC."""
    d = ctx.get("date", "")
    m = re.match(r"(\d{4}-\d\d-\d\d)T(\d\d:\d\d)", d)
    return f"{m.group(1)} {m.group(2)} UTC" if m else d


class Page:
    def __init__(self, res):
        self.res = res
        self.parts = []

    def add(self, *text):
        self.parts.extend(text)

    def chart(self, name, alt):
        if os.path.exists(os.path.join(ROOT, "bench", "charts", name)):
            self.add(f"![{alt}](bench/charts/{name})")

    def table(self, title, fn, files, note="", chart=None):
        """A section: title, note, the table made by fn(*paths) from the files
        it needs, its chart; left out when one of the files is absent."""
        if not all(self.res.has(f) for f in files):
            return
        try:
            body = fn(*[self.res.path(f) for f in files])
        except (KeyError, IndexError, ValueError, TypeError, StopIteration, ZeroDivisionError) as e:
            raise InputError(self.res.path(files[0]), f"unexpected content ({type(e).__name__}: {e})")
        self.add(f"### {title}", note, body)
        if chart:
            self.chart(*chart)

    def lockstep_table(self, d):
        """A lockstep-table/1 file: its title, one paragraph of provenance and
        note, the table, its own targets."""
        meta = [f"`{d['command']}`" if d.get("command") else "", d.get("date", ""), d.get("machine", "")]
        about = ("Measured by " + ", ".join(m for m in meta if m) + ". ") if any(meta) else ""
        about += (d.get("note") or "") + (f" (Source: {d['source']}.)" if d.get("source") else "")
        self.add(f"### {d['title']}", about.strip(), md_table(d["columns"], d["rows"]))
        if d.get("chart"):
            self.chart(*d["chart"])
        for t in d.get("targets", []):
            self.add(f"* {t['text']}: {t['measured']} (**{'met' if t['met'] else 'not met'}**)")

    def text(self):
        """Prose paragraphs on one line each (they are wrapped in this
        script's source), tables and headings as they are."""
        keep = ("|", "#", "![", "<!--")
        return "\n\n".join(p if p.startswith(keep) else " ".join(p.split("\n")) for p in self.parts if p) + "\n"


def volume_table(path):
    """The volume families' frames: reference at its own size, simd warm (its
    first frame in brackets), the per-pixel speed-up, the volpack row."""
    ctx, rows = charts.load(path)
    b = dict(rows)
    keys = []
    for n in b:
        m = re.fullmatch(r"frame/(volume|volume_iso)/([^/]+)/([^/]+)/\w+/threads:\d+", n)
        if m and m.groups() not in keys:
            keys.append(m.groups())
    out = ["| frame | reference 1T ms (at its size) | simd 1T ms (first frame) | simd 2T ms | speed-up per pixel 1T "
           "| speed-up per pixel 2T | volpack 1T ms (of which classification) |", "|---|---:|---:|---:|---:|---:|---:|"]
    for fam, vol, what in keys:
        get = lambda impl, t: b.get(f"frame/{fam}/{vol}/{what}/{impl}/threads:{t}")
        ref, s1, s2, vp = get("reference", 1), get("simd", 1), get("simd", 2), get("volpack", 1)
        up = lambda s: f"{s['pixels_per_s'] / ref['pixels_per_s']:.1f}x" if s and ref else ""
        cells = [f"{ms_of(ref):.1f} ({ref['size']:.0f}^2)" if ref else "",
                 f"{ms_of(s1):.1f} ({s1['first_ms']:.1f})" if s1 else "", f"{ms_of(s2):.1f}" if s2 else "",
                 up(s1), up(s2), f"{ms_of(vp):.1f} ({vp['build_ms']:.1f})" if vp else ""]
        label = ("ray cast" if fam == "volume" else "isosurface") + f", {vol}, {what}"
        out.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def machine_line(res):
    if not res.has("machine.txt"):
        return ""
    lines = [ln.strip() for ln in open(res.path("machine.txt")) if ln.strip()]
    cpu = lines[0].split(":", 1)[1].strip() if lines and ":" in lines[0] else ""
    rest = [ln for ln in lines[1:] if not ln.startswith(("ray_cast", "composite", "zbuffer", "scanline", "painter",
                                                         "marching", "volume", "splat"))]
    return f"**Machine:** {cpu}, " + "; ".join(rest) + " (bench/results/machine.txt, written by `bash bench/run.sh`, step machine)."


def reproduce(cmd, ctx_date=""):
    return f"**Reproduce:** `{cmd}`" + (f" (this run: {ctx_date})." if ctx_date else ".")


def build(res, targets_path, partial=False):
    page = Page(res)
    tables = res.lockstep_tables()
    by_family = {}
    for f, d in sorted(tables, key=lambda x: (x[1].get("order", 0), x[0])):
        by_family.setdefault(d.get("family") if d.get("family") in FAMILIES else "other", []).append(d)
    targets = evaluate_targets(targets_path, res, partial)
    for d in (d for ds in by_family.values() for d in ds):
        for t in d.get("targets", []):
            targets.append((t.get("issue", d.get("issue", "")), d.get("family", ""), t["text"], t["measured"],
                            "**met**" if t["met"] else "**not met**"))

    page.add("# lockstep benchmarks", GENERATED, INTRO, machine_line(res), GENERAL)
    page.add("## Targets", "Every target the issues set, evaluated over the results files by `bench/targets.json`'s "
             "expressions (a one-off table's own targets are stated in its file).",
             md_table(["issue", "family", "target", "measured", ""],
                      [[f"#{i}" if i != "" else "", FAMILY_TITLE.get(f, f), t, m, v] for i, f, t, m, v in targets]))

    def extra(fam):
        for d in by_family.get(fam, []):
            page.lockstep_table(d)

    def date_of(name):
        return when(res.bench(name)[0]) if res.has(name) else ""

    # ray casting
    latest = lambda fn: (lambda p: fn(charts.load(p)[1]))
    page.add("## Ray casting", RAY_CAST,
             reproduce("bash bench/run.sh --only ray_cast_composite,accuracy,charts,page",
                       date_of("latest.json")))
    page.table("Frames: SPD scenes at 512 x 512, primary rays per second", latest(charts.frames_table),
               ["latest.json"], FRAMES_NOTE, ("scaling.png", "frame time per ray against scene size"))
    page.table("Kernels in a scene: ray-primitive tests per second", latest(charts.throughput_table), ["latest.json"],
               "4096 rays from one eye against 256 random unit spheres or triangles, each row's `trace`, one thread.")
    page.table("Kernels alone: speed against accuracy", lambda p, a: charts.accuracy_table(charts.load(p)[1], a),
               ["latest.json", "accuracy.csv"], ACCURACY_NOTE, ("accuracy.png", "speed against accuracy"))
    page.table("Where each method breaks", charts.stability_table, ["stability.csv"], BREAKS_NOTE)
    extra("ray_cast")

    page.add("## Compositing", COMPOSITE,
             reproduce("bash bench/run.sh --only ray_cast_composite,charts,page", date_of("latest.json")))
    page.table("4096 x 4096 stacks: output pixels per second", latest(charts.composite_table), ["latest.json"],
               COMPOSITE_NOTE, ("composite.png", "compositing speed against accuracy"))
    extra("composite")

    page.add("## Rasterization", RASTER, reproduce("bash bench/run.sh --only raster,raster_study,page", date_of("raster.json")))
    page.table("The z-buffer at 1024 x 1024: ms per frame (warm; the first frame in brackets)",
               raster_charts.zbuffer_table, ["raster.json"])
    page.table("Every raster implementation at 1024 x 1024: Mtris/s / Mpix/s (warm)",
               raster_charts.every_impl_table, ["raster.json"], "",
               ("raster_scaling.png", "time per frame against triangle count"))
    study = lambda key, fn: (lambda p: fn(raster_charts.sections(p)[key]))
    for key, title, fn, png, note in RASTER_STUDY:
        page.table(title, study(key, fn), ["raster_study.csv"], note, (png, title) if png else None)
    extra("raster")

    page.add("## Marching cubes", MC, reproduce(MC_BENCH))
    extra("marching_cubes")
    page.table("Speed against accuracy", lambda p: mc_chart.table(mc_chart.load(p)), ["mc_study.csv"], MC_STUDY_NOTE,
               ("mc_accuracy.png", "marching cubes: error against time"))
    if res.has("mc_topology.txt"):
        page.add("### Topology against the trilinear interpolant", MC_TOPOLOGY_NOTE,
                 "\n".join(ln.rstrip() for ln in open(res.path("mc_topology.txt")) if ln.startswith("|")))

    page.add("## Volume rendering", VOLUME, reproduce(VOLUME_BENCH, date_of("volume_bench.json")))
    page.table("Frames: ms per frame", volume_table, ["volume_bench.json"], VOLUME_NOTE)
    extra("volume")
    step = lambda key, fn: (lambda p: fn(volume_charts.sections(p)[key]))
    page.table("Speed against accuracy: the step", step("step", volume_charts.step_table), ["volume_step.csv"],
               STEP_NOTE, ("volume_step.png", "volume ray casting: error against time"))
    page.table("Cross-check: marching cubes through the z-buffer against the ray-cast isosurface",
               step("cross", volume_charts.cross_table), ["volume_cross.csv"], CROSS_NOTE,
               ("volume_cross.png", "mesh against ray-cast isosurface"))

    if by_family.get("ray_trace"):
        page.add("## Ray tracing", RAY_TRACE)
        extra("ray_trace")

    page.add("## Texture filtering", TEXTURE, reproduce(TEXTURE_STUDY))
    page.table("Targets", lambda a, b, c: texture_chart.targets(texture_chart.load(a), texture_chart.load(b),
                                                                texture_chart.load_plane(c)),
               ["texture_study.csv", "texture_study_2t.csv", "texture_plane.csv"], TEXTURE_TARGETS_NOTE)
    page.table("Speed against accuracy: every filter of every row, one thread",
               lambda p: texture_chart.table(texture_chart.load(p)), ["texture_study.csv"], TEXTURE_NOTE,
               ("texture_speed_accuracy.png", "texture filtering: error against time per lookup"))
    page.table("The same on two threads", lambda p: texture_chart.table(texture_chart.load(p)),
               ["texture_study_2t.csv"], TEXTURE_2T_NOTE)
    page.table("error=E: a filter per tile", lambda p: texture_chart.error_table(texture_chart.load(p)),
               ["texture_study.csv"], TEXTURE_ERROR_NOTE)
    page.table("The issue's 1024^2 receding plane", lambda p: texture_chart.plane_table(texture_chart.load_plane(p)),
               ["texture_plane.csv"], TEXTURE_PLANE_NOTE)
    page.table("Where each filter breaks: viewing angle against minification",
               lambda p: texture_map_chart.table(texture_map_chart.load(p)), ["texture_map.csv"], TEXTURE_MAP_NOTE,
               ("texture_failure_maps.png", "texture filtering: failure maps"))

    if by_family.get("radiosity"):
        page.add("## Radiosity", RADIOSITY)
        extra("radiosity")
    page.table("Radiosity: form-factor error against time",
               lambda p: radiosity_chart.form_factor_table(radiosity_chart.load(p)[0]), ["radiosity_study.csv"],
               RADIOSITY_FF_NOTE, ("radiosity_form_factors.png", "radiosity: form-factor error against time"))
    page.table("Radiosity: solver residual against time",
               lambda p: radiosity_chart.solver_table(radiosity_chart.load(p)[1]), ["radiosity_study.csv"],
               RADIOSITY_SOLVE_NOTE, ("radiosity_solvers.png", "radiosity: residual against time per solver"))
    page.table("Radiosity: where the point-to-area methods break",
               lambda p: radiosity_chart.map_table(radiosity_chart.load_maps(p)), ["radiosity_study.csv"],
               RADIOSITY_MAP_NOTE, ("radiosity_failure_map.png", "radiosity: failure map of two facing plates"))
    page.table("Radiosity: light leaks at an unmeshed contact", radiosity_chart.leak_table, ["radiosity_study.csv"],
               RADIOSITY_LEAK_NOTE)
    page.table("Radiosity: refined meshes (--error) against uniform ones", radiosity_chart.refinement_table,
               ["radiosity_study.csv"], RADIOSITY_REFINE_NOTE,
               ("radiosity_refinement.png", "radiosity: image error against patch count, uniform and refined"))

    if by_family.get("other"):
        page.add("## Other measurements")
        extra("other")
    return page.text()


FAMILY_TITLE = {"ray_cast": "ray casting", "composite": "compositing", "raster": "rasterization",
                "marching_cubes": "marching cubes", "volume": "volume rendering", "ray_trace": "ray tracing",
                "texture": "texture filtering", "radiosity": "radiosity"}

RADIOSITY = """The radiosity family (issue #33, [docs/radiosity.md](docs/radiosity.md)): the
Cornell box solved and drawn whole, the textbook reference (rays tested against
every triangle in double, one thread) against the simd row (Lambert's factors 8
patches a vector; visibility by shadow polygons, the reference's own test only
where a shade may hide a segment; the solve's rows in Highway over a float
copy of the factors; TBB)."""

RADIOSITY_FF_NOTE = """`./build/bench/lockstep_radiosity_study > bench/results/radiosity_study.csv && python3 bench/scripts/radiosity_chart.py bench/results/radiosity_study.csv bench/charts`
(`bash bench/run.sh --only radiosity_study,page`; `ctest -R radiosity_study` checks its claims on 305
patches). The form-factor matrix alone of the Cornell box, reference (one thread) and simd (two threads),
best of 2, against F*: the exact area-to-area factor (Sparrow's contour integral, core/radiosity.h) times
the share of 16 x 16 rays from a patch's centre that arrive: exact for every pair nothing occludes, the
centre's visibility for the others. Row error: sum_j |F_ij - F*_ij|, the share of patch i's gathered
light that is wrong; the largest (a few patches at the room's corners and the blocks' feet, where a
point's view is not the patch's) and the mean. rays stays near its point-to-area floor whatever k; exact
converges with k; the hemicube's mean error falls as its resolution doubles, its largest does not (the
proximity failure). The rows' errors are equal: the same method, the same oracle."""

RADIOSITY_MAP_NOTE = """The same study: two facing unit plates at distance d, one patch each; the relative
error of F_01 against Howell's closed form. The centre point (the rays method's factor, whatever k: no
occluder) is off by up to 33% where the plates are about as far apart as they are wide (proximity:
the centre's view is not the plate's), 0.5% at d = 8, falling as 1/d^2; near contact both tend to 1
and the error shrinks again. The hemicube follows the point until the far plate covers few pixels
(aliasing): at d = 16 a 16-pixel hemicube misses it entirely (error 100%), 64 pixels are within 0.2%.
Patches should be small against their distances: the mesh, not the method, is the cure."""

RADIOSITY_LEAK_NOTE = """The same study: a cube of a quarter of the floor's side standing on a unit floor under an
emitting ceiling, the floor cut N x N, the cube's footprint moved by a phase (in patches) against the
grid. No light reaches under the cube, but a floor patch whose centre sees the ceiling carries its light
under it (leaked: the light shown on the footprint, over the lit floor's mean times the footprint's
area), and a patch whose centre is under the cube is black where it shows (darkened: its visible area
over the footprint's). Where the footprint's edges follow the grid (x0 N whole: N = 16 at phase 0, N = 4
at phase 1/2) both are 0: a meshed contact does not leak. Elsewhere about a patch's width of the
perimeter leaks or darkens, so the worst phase falls with the patches (claimed: to below half from N = 4
to the finest)."""

RADIOSITY_REFINE_NOTE = """The same study: the Cornell box at 96 x 96, the simd row, each image against a uniform
solution of 8,014 patches (patch area 250); uniform meshes, and meshes refined from 305 patches by
`--error E` (cut where a neighbour's radiosity jumps by more than E of the largest reflected radiosity,
weighted by the patch's side). Refinement spends its patches on shadow boundaries and the blocks' feet:
its largest pixel error is below that of every uniform mesh with up to 1.5 times its patches (claimed),
its rms about the same; past ~1,500 patches its largest error stays near 0.12 (the blocks' feet, the
T-junctions' steps) while uniform meshes keep falling. Its frames cost more per patch (a solve per round).
T-junctions: corners of cut patches inside a neighbour's uncut edge, where the display's colour steps
by the difference between that corner's radiosity and the edge's interpolation (over the largest
reflected radiosity); a uniform mesh has none."""

RADIOSITY_SOLVE_NOTE = """The same study: Jacobi and Gauss-Seidel sweep by sweep, progressive refinement after 2^m
shots, on the exact factors of the Cornell box (1,078 patches), one thread; residual
max |B - E - rho F B| over the largest emission. Gauss-Seidel reaches 1e-6 in fewer sweeps than
Jacobi. Progressive refinement shoots by reciprocity (A_i F_ij = A_j F_ji), which the centre's
visibility breaks for partly occluded pairs: it converges to a neighbouring system and its residual in
this one stalls near 5e-3. On the closed box (exact factors, nothing occluded: reciprocal) the same
solver reaches 2e-14 in 16,384 shots (the study's `enclosure` line)."""

GENERATED = """<!-- Generated by bench/scripts/benchmarks_md.py from bench/results/ and bench/targets.json: do not edit by hand
(the ctest benchmarks_md.current fails when this page differs from what the results make). -->"""

INTRO = """Every family's implementations, benchmarked side by side in the same run with
the production peers: a textbook *reference* (scalar, one thread), an
optimized *simd* row (Highway SIMD, TBB threads) and, where one exists, a
library peer (Embree, OpenImageIO, OSMesa llvmpipe, VTK, VolPack). Tables are
Google Benchmark medians of 3 repetitions (`--benchmark_min_time=0.3`) unless a
table says otherwise; warm frames reuse their buffers, as a renderer does.
How each figure was reached (what changed, what was tried and dropped) is in
the commit log: `git log -- BENCHMARKS.md bench/results`."""

GENERAL = """**Regenerate this page:** `python3 bench/scripts/benchmarks_md.py`; rerun every measurement on it first, then regenerate it: `bash bench/run.sh` (`--quick` checks that every step still runs, into a temp dir).
The machine is a KVM guest whose speed drifts by up to 30% over minutes:
ratios measured in one run are steadier than absolute times."""

RAY_TRACE = """Whitted ray tracing (issue #22): reference (double, brute force, a fixed
self-intersection offset eps along the normal from the hit moved onto its
surface) and embree (float BVH in a frame at the eye moved to the scene, the robust
offset by default: the hit's error bound, core/ray_trace.h; issue #30)."""

RAY_CAST = """reference (textbook, scalar, one thread), simd (Highway 8-ray packets, TBB
tiles), embree (Embree 3 BVH, rtcIntersect8, TBB tiles) and auto (simd or
embree by scene size). Frames are whole `render()` calls (camera rays, nearest
hit, Phong shading, the image); embree's and auto's BVH build is included and
also shown on its own."""

FRAMES_NOTE = """The reference renders scenes above 5000 primitives at 128 x 128 (its rate per
ray does not depend on the image size). "prims" counts spheres and the
polygons' triangles. In the chart the x axis is auto's own measure of a scene,
spheres + 6 x triangles (a watertight triangle test costs simd about six sphere
tests): simd's cost per ray grows with the scene, embree's with its logarithm;
auto switches where they cross."""

ACCURACY_NOTE = """One primitive against 4096 rays through each row's kernel entry point, and the
relative error of t against the oracle (113-bit `__float128`, CGAL exact
predicates) on rays well-conditioned in the frame each implementation computes
in (props/README.md, "The frame"); the bound is what the accuracy property
enforces (`Impl::accuracy` in `registry/ray_cast_row.cpp`). simd's kernel entry
converts every ray into its float frame first, which is what a single
primitive measures; inside a scene (the table above) that set-up is shared by
every primitive. The ray_cone rows (one open cone, nearest visible root) were
measured later, 2026-12-03, on a loaded machine (load 7): compare them with
each other (CPU time: simd 3.4x careful, the scalar form it reproduces bit for
bit; the reference ray_sphere measured beside them ran 9% below its row here)."""

BREAKS_NOTE = """Deep mode (`LOCKSTEP_DEEP=1`, 1000 cases per property) of the stability,
watertightness and degenerate-polygon properties, each ray judged against the
oracle; a cell gives the share of rays whose answer differs from the exact one,
by cause as classified from the oracle's conditioning: `cancellation` (the
quadratic's discriminant loses its digits), `translation` (coordinates far
from the origin), `sliver` (a plane from nearly collinear vertices),
`grazing`/`parallel`/`near_edge`/`near_tmin` (within a few ulps of a tangent,
the plane, an edge or the ray's start: either answer is within rounding),
`leak_edge`/`leak_vertex` (a ray through a closed mesh's shared edge or vertex
hits nothing; rates per ray of that class). Nothing is unexplained: an
unexplained deviation fails the property."""

COMPOSITE = """reference (textbook, scalar, one thread), simd (Highway, TBB bands, every
layer streamed once, early termination per 64-pixel block) and oiio
(OpenImageIO's `ImageBufAlgo::over`, chained). memcpy copies the same bytes
with the same threads in the same run: the bandwidth yardstick."""

COMPOSITE_NOTE = """Mpix/s counts output pixels, GB/s every layer read once plus the output
written (for stacks that stop early simd reads less, so its GB/s there is
nominal). Float stacks are premultiplied unless "straight"; unorm8 stacks use
8-bit premultiplied arithmetic. "opaque-early": layers from the third on are
opaque but for small holes, so front-to-back compositing can stop. The chart
puts each 2-layer stack's speed against its measured error (the deep-mode
maxima of the accuracy table below)."""

RASTER = """The zbuffer, scanline and painter families (issue #7): reference (textbook,
scalar, one thread), simd (Highway edge functions, TBB tiles, SIMD shading)
and, for the z-buffer, llvmpipe (Mesa's software rasterizer through OSMesa;
flat and Gouraud only). Frames are whole `render()` calls at 1024 x 1024:
viewing, culling, clipping, sphere tessellation, lighting, rasterization,
shading, the float RGBA image and its depth plane. The llvmpipe row creates
its context, compiles its shaders and reads back a float buffer on every call.
"triangles" counts the scene's triangles plus the spheres' tessellation,
before culling. The studies below come from `lockstep_raster_study all`
(bench/studies/raster_study.cpp; `ctest -R raster_study` checks the claims they make)."""

RASTER_STUDY = [
    ("tessellation", "Speed against accuracy: sphere tessellation against ray casting", raster_charts.tessellation_table,
     "raster_tessellation.png",
     "The same frame (Phong per sample) drawn by the simd z-buffer (512 x 512, both threads) and ray-cast; the "
     "difference is the tessellation's error, for silhouette error targets from 8 down to 1/8 pixel (`--tess_error`)."),
    ("supersampling", "Speed against accuracy: supersampling against the exact box filter",
     raster_charts.supersampling_table, "raster_supersampling.png",
     "Flat triangles (64 x 64, simd) against the exact box-filtered image (each visible polygon clipped against "
     "each pixel square in exact arithmetic); `SupersamplingConverges` enforces the 1/n bound per pixel."),
    ("zfight", "Failure map: z-fighting", raster_charts.zfight_table, "raster_zfight.png",
     "Two parallel planes a relative distance `sep` apart (far plane at 100): the share of pixels where the back "
     "plane wins, per depth format and near plane."),
    ("painter", "Failure map: the painter's algorithm", raster_charts.painter_table, "raster_painter.png",
     "Random 64 x 64 flat scenes of three triangles that overlap cyclically and of two that interpenetrate, drawn "
     "by the reference painter without and with `split=1`, against the z-buffer; a wrong scene must be reported."),
    ("gouraud", "Failure map: Gouraud's missed highlights", raster_charts.gouraud_table, None,
     "A shiny sphere (shininess 200) lit from the front: Gouraud interpolates colours lit at the vertices, so the "
     "highlight shows only where a vertex falls near it."),
]

MC = """reference (textbook, cube by cube, one thread), simd (flying-edges passes,
each cut edge once, Highway classification, TBB slabs) and vtk
(vtkFlyingEdges3D, VTK 9.1). Reference and simd give the same surface vertex
for vertex (`Agreement.marching_cubes__simd`)."""

TEXTURE = """The texture family (issue #32, [docs/texture.md](docs/texture.md)): every
filter of the reference, the simd row, OpenImageIO's TextureSystem (the oiio
row: point, bilinear, one level, trilinear, anisotropic) and Mesa's llvmpipe
(GL's filters), each judged against the pixel's exact box filter of the
texel-constant texture (props/texture/oracle.h), on the receding zone plate
(corpus/textures/zoneplate_plane.texscene) at 192 x 192, warm, lookups alone:
every row's one-shot set-up (its pyramid; OpenImageIO's make_texture,
0.05-0.06 s for this 256^2 texture; llvmpipe's context, shader compilation
and upload, about 0.3 s) is measured apart and not in these figures, and
the peers run through their sessions (the .tx and TextureSystem, the GL
context and texture kept across frames, as an application keeps them)."""

TEXTURE_TARGETS_NOTE = """Evaluated by bench/scripts/texture_chart.py over the tables below. Every
row's figure is its frame less its own one-shot set-up, timed inside that
frame (build_seconds: the pyramid, or the reference's copy of level 0 for
bilinear), best of 15 frames (of 3 where a frame takes over 50 ms), frames
from the heap as in bench/. Runs before 2026-12-05 took the reference's
pyramid timed apart, cold, best of 3 (1.42 ms in one run against 0.45-0.48 ms
inside its frames), which understated its lookups by about a quarter: their
8.3-8.6x at 192^2 (with a simd row 9% slower than now). This VM's speed moves
by a third within an hour, both rows alike: in alternated runs of
`lockstep_texture_timing` (bench/timing/texture_timing.cpp) this code gave
simd trilinear 7.3-8.7 ns and the reference 88-113 ns a lookup, 12.1-13.0x
(main's before it: 7.2-11.7 ns, within minutes). On the issue's 1024^2 plane (a 22 MB pyramid) every row waits on
memory, the reference most; a second `--plane` run the same hour gave 12.9x
(10.3 against 133 ns)."""

TEXTURE_ERROR_NOTE = """`lockstep texture SCENE --error E` (registry/texture_row.cpp): per 64 x 16
tile, the cheapest of point, trilinear, aniso2, aniso4, aniso8 and aniso16
whose largest error at 18 sample pixels of the tile (RGB RMS against area
sampling, the average of the texels over each footprint) is at most E, else
area sampling. The search is its one-shot cost (the lookups at the samples:
the reference's filters, the simd row's area sampling; search column); the frame is then drawn once, a filter per
tile. E bounds the samples, not every pixel: the frame's RMS against the
pixel's exact box filter stays under E (checked by `ctest -R
texture_study`), single pixels do not (max column). Between aniso16 and
area sampling no single filter has a point; error=E fills that stretch, and
at E = 0.1-0.2 it is cheaper than the single filters of the same error. The
search grows with the footprints: 16 ms at 192^2, 0.5 s on two threads for
the 1024^2 plane below (its yardstick is the simd row's area sampling;
horizon samples cover thousands of texels)."""

TEXTURE_PLANE_NOTE = """`./build/bench/lockstep_texture_study --plane > bench/results/texture_plane.csv`:
the registry's benchmark input (the scene of the issue's peer figures),
warm, best of 15 (3 for frames over 50 ms), lookups alone (each row's one-shot set-up apart; the peers
through their sessions). llvmpipe at one thread only (it reads its thread
count once per process: `--two-threads` of the study above has its two-thread
figures)."""

TEXTURE_2T_NOTE = """`lockstep_texture_study --two-threads` (a process of its own: llvmpipe reads
its thread count once per process, at its first context). At 192 x 192 a frame
is 36 tiles of 23,130 lookups: two threads gain 1.6-1.9x for simd's costlier
filters (anisotropic, supersampling, EWA, area) and nothing for point,
bilinear and trilinear (such a frame is 0.2 ms); the 1024^2 plane below
scales 1.7-2x for simd and not at all for OpenImageIO's trilinear (its tile
cache's locks)."""

TEXTURE_MAP_NOTE = """`./build/bench/lockstep_texture_map_study > bench/results/texture_map.csv && python3 bench/scripts/texture_map_chart.py bench/results/texture_map.csv bench/charts`
(`ctest -R texture_map_study` checks its claims on three cells). A
checkerboard (8-texel checks) on a large plane, 48 x 48 pixels, 45 degrees,
seen from distance 10 at an elevation of 5-90 degrees; the tiling makes a
pixel at the image's centre cover m texels across (0.5: magnified; past 8 a
pixel holds more than a whole check). RMS error of the reference against
the pixel's exact box filter over the image's interior pixels (those whose
footprint spans at most 20,000 texels; near a grazing view's horizon the
oracle's cost is the footprint's texel count). The table: the minifications
at which each filter's RMS stays under 0.05. Point sampling never does:
even at one texel a pixel it takes the check a pixel's centre sees where the
box filter mixes two, and past m = 2 it aliases (RMS 0.5: noise). Trilinear
holds straight down and breaks below 60 degrees (its level follows the
longer side of the footprint: the short side is blurred); anisotropic
filtering holds from 1 texel a pixel on at 10-45 degrees, and at 5 degrees
from 2 (at m = 1 even 16 probes are too few). At 60 degrees, m = 4-8, it is
worse than trilinear (0.058-0.063 against 0.043-0.029): the footprint is
1.15 times longer than wide, ceil(1.15) = 2 probes, each at the level of half
the long side, finer than the short side needs: aliasing across (the
EXT_texture_filter_anisotropic rule, followed by the reference and simd). EWA blurs more than the box (a
Gaussian two pixels across): under 0.05 mostly once the checks average out
(m >= 16). Magnified (m = 0.5) every filter but supersampling interpolates
between texels that the box filter keeps sharp."""

TEXTURE_STUDY = ("./build/bench/lockstep_texture_study > bench/results/texture_study.csv && "
                 "./build/bench/lockstep_texture_study --two-threads > bench/results/texture_study_2t.csv && "
                 "./build/bench/lockstep_texture_study --plane > bench/results/texture_plane.csv && "
                 "python3 bench/scripts/texture_chart.py bench/results/texture_study.csv bench/charts")

TEXTURE_NOTE = """RMS: over the interior pixels (all four corners on the quad), RGB; the
simd row's error equals the reference's within 1e-5 for every filter (checked
by `ctest -R texture_study`, with the claims that supersampling converges and
that anisotropic filtering and EWA beat trilinear). ns per lookup: the warm
frame less its one-shot set-up, over the pixels that see the quad (23,130),
best of 3. Area sampling is the most accurate (RMS 0.0014: it is the box filter but
for the perspective weighting) and by far the slowest (tens of us a lookup:
near the horizon a footprint covers thousands of texels). llvmpipe's
anisotropic modes give one image whatever N (2-16) on this scene."""

MC_STUDY_NOTE = """`./build/bench/lockstep_mc_study > bench/results/mc_study.csv && python3 bench/scripts/mc_chart.py bench/results/mc_study.csv bench/charts`
(`ctest -R mc_study` checks its claims up to n = 64). The sphere |p| = 0.5 and
the torus of radii 0.5 and 0.25 sampled on [-1, 1]^3 at n samples a side, h =
2 / (n - 1); time per extraction on one thread (the least of three runs of
best of 5: single measurements, noisier than the tables above), and the two-sided Hausdorff
distance to the analytic surface; c = distance R / h^2 (R the sphere's radius,
the torus's tube radius): the error falls as h^2 while the time grows as n^3."""

MC_TOPOLOGY_NOTE = """`/usr/bin/python3 tests/topology_skimage.py build/lockstep` (output in
bench/results/mc_topology.txt; `ctest -R topology.skimage` runs it quick).
Each case's Euler characteristics against scikit-image's Lewiner marching
cubes (MC33: the trilinear interpolant's topology); every difference is
classified by the field's ambiguous faces ("face") or interiors ("interior");
a difference with neither fails, and caps near the measured rates are
enforced per class."""

VOLUME = """Volume ray casting and its isosurface (issue #20): reference (textbook: one
ray per pixel, trilinear samples at dt = 0.5 voxel, double), simd (16-ray
packets on AVX-512, the transfer function in registers, early termination,
empty-space skipping over macro cells kept with the volume; the isosurface
redoes near decisions in double) and volpack (VolPack's shear-warp, one
thread, classifying on every call). The CT head (256 x 256 x 113) and the MRI
brain come from ../shared/volumes."""

MC_BENCH = ("build/bench/lockstep_bench --benchmark_filter='frame/marching_cubes/' --benchmark_min_time=0.3 "
            "--benchmark_repetitions=3 --benchmark_report_aggregates_only=true")

VOLUME_BENCH = ("build/bench/lockstep_bench --benchmark_filter='frame/volume(_iso)?/' --benchmark_min_time=0.3 "
                "--benchmark_repetitions=3 --benchmark_report_aggregates_only=true "
                "--benchmark_out=bench/results/volume_bench.json")

VOLUME_NOTE = """View -90,-15,180. simd draws 512 x 512; the reference draws the same frames at
128 x 128 (its cost per pixel does not depend on the size), so the speed-up is
per pixel. `noskip` turns empty-space skipping off. The first frame builds the
macro cells; volpack's classification is its `build_ms`, paid on every call."""

STEP_NOTE = """`./build/bench/lockstep_volume_study step > bench/results/volume_step.csv && python3 bench/scripts/volume_charts.py bench/results/volume_step.csv bench/charts`
(single timed runs). 512 x 512, the frames' own early termination; the truth
is simd at step 1/16 (within 6e-4 of the reference per channel); ms per frame
and mean error per channel. volpack takes one sample per slice whatever the
step: one point, its classification included."""

CROSS_NOTE = """`./build/bench/lockstep_volume_study cross > bench/results/volume_cross.csv && python3 bench/scripts/volume_charts.py bench/results/volume_cross.csv bench/charts`
(`ctest -R volume_study` checks its claims up to n = 48). The sphere and torus
at n samples a side: the marching-cubes mesh drawn by the reference z-buffer at
256 x 256 against the isosurface ray-cast by `volume_iso`'s reference;
coverage compared pixel for pixel, depth along the z-buffer's own rays. Both
approximate the trilinear interpolant's level set: the depth difference falls
as h^2, the pixels covered by one only are silhouette pixels."""


def main(argv):
    args = {"--results": os.path.join(ROOT, "bench", "results"), "--targets": os.path.join(ROOT, "bench", "targets.json"),
            "--out": os.path.join(ROOT, "BENCHMARKS.md")}
    check = partial = False
    i = 0
    while i < len(argv):
        if argv[i] == "--check":
            check = True
        elif argv[i] == "--partial":
            partial = True
        elif argv[i] in args and i + 1 < len(argv):
            args[argv[i]] = os.path.abspath(argv[i + 1])
            i += 1
        else:
            print(__doc__, file=sys.stderr)
            return 2
        i += 1
    try:
        text = build(Results(args["--results"]), args["--targets"], partial)
    except InputError as e:
        print(f"benchmarks_md: {e}", file=sys.stderr)
        return 2
    out = args["--out"]
    if check:
        old = open(out).read() if os.path.exists(out) else ""
        if old == text:
            return 0
        diff = list(difflib.unified_diff(old.splitlines(), text.splitlines(), out, "generated", lineterm=""))
        print(f"{os.path.relpath(out, ROOT)} differs from what bench/results makes "
              f"(edit the results or the generator, then run python3 bench/scripts/benchmarks_md.py):", file=sys.stderr)
        print("\n".join(diff[:60]), file=sys.stderr)
        return 1
    with open(out + ".tmp", "w") as f:
        f.write(text)
    os.replace(out + ".tmp", out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
