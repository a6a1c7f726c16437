#!/usr/bin/env python3
"""Write docs/families.md: where everything of each registered family lives.

  python3 scripts/family_index.py LOCKSTEP_BINARY            # writes docs/families.md
  python3 scripts/family_index.py LOCKSTEP_BINARY --out -    # to stdout
  python3 scripts/family_index.py LOCKSTEP_BINARY --check    # ctest families.index

The families are the registry's (`lockstep families`, one name a line). A
family's parts are found in the tree (git ls-files), never listed by hand:
a file belongs to a family when its basename, or else its nearest folder below
the top one, holds one of the family's stems (STEMS below, the one table to
edit) as whole words ("_", "-" and "." separate words; a trailing "s" is
allowed: shadow_maps matches shadow_map). Of several matching stems the longest
wins; equally long ones from several families claim the file for each. On top
of the names, two facts are read from the code: the row file is the registry/
file that defines `Family <stem>_family(`, and the property provider is the
props/ folder of the namespace props/families.cpp names for the family.
Corpus cases come from the corpus manifest (its first field, when it is a
family, else the manifest's default family).

What a file is follows from its top folder (core/: contract, reference/,
optimized/, registry/: row, docs/, tests/, ...) and, in the measurement folders
(props/, bench/, scripts/), from its name and kind: a name with
"study" is a study, a C++ file that includes <benchmark/benchmark.h> a Google
Benchmark, other C++ files in props/ properties and elsewhere timing programs,
.py/.sh files scripts, data and pictures results and charts. So files may
move between folders below the top one without an edit here.

--check fails (exit 1, saying what) when
  (a) docs/families.md differs from what this script writes (stale index);
  (b) a registered family lacks a contract or reference file, a registry row,
      a properties file, its docs page or a corpus case;
  (c) a C++ source of reference/, optimized/ or registry/ is claimed by no
      family and is not in SHARED (a new file must be indexed).
"""
import difflib
import os
import re
import subprocess
import sys

# ---- the one table: each family's file stems (key: the family, spelt either
# way, with or without underscores). Keep it short: a stem is a word of file
# names, not a file.
STEMS = {
    "ray_cast": ["ray_cast", "ray_sphere", "ray_plane", "ray_polygon", "ray_cone", "cone",
                 "embree", "simd_scene", "shade_simd"],
    "ray_trace": ["ray_trace", "embree", "povray"],
    "composite": ["composite", "layers", "synthetic_stack", "stack"],
    "zbuffer": ["zbuffer", "raster", "shadow", "shadow_map", "shadow_volume", "llvmpipe"],
    "scanline": ["scanline"],
    "painter": ["painter"],
    "marching_cubes": ["marching_cubes", "mc"],
    "volume": ["volume", "volume_raycast", "volume_render", "volpack"],
    "splat": ["volume_splat", "splat"],
    "volume_iso": ["volume_iso"],
    "texture": ["texture", "texture_filter", "texture_scene", "textures"],
    "radiosity": ["radiosity"],
}
# C++ sources of reference/, optimized/ and registry/ that belong to no one
# family (basename without extension: what uses them).
SHARED = {
    "registry": "the registry's one list of families",
    "loaders": "inputs shared by families (NFF scenes)",
    "tiling": "every simd row's 2D tiles over TBB",
    "peer_module": "every peer row's module (llvmpipe, vtk, volpack)",
    "refine": "the optimized ray casters and tracers (simd, embree)",
    "mask_bytes": "simd rows' vector masks as bytes (texture, radiosity)",
}
# Words of optimized/ file names that name a row (an implementation).
VARIANTS = ["simd", "embree", "auto", "llvmpipe", "vtk", "volpack", "povray", "oiio"]

CPP = (".cpp", ".h", ".cc", ".hpp", ".inl")
DATA = (".json", ".csv", ".dat", ".txt", ".png", ".svg", ".md", ".html")
MEASURE_TOPS = ("props", "bench", "tools", "scripts")
ROLES = [  # (key, title) in the order a family's section lists them
    ("contract", "contract (core/)"),
    ("io", "formats and output kinds (io/, kinds/)"),
    ("reference", "reference"),
    ("optimized", "optimized rows"),
    ("row", "registry row"),
    ("properties", "properties"),
    ("studies", "studies"),
    ("timing", "timing programs"),
    ("benchmarks", "Google Benchmark"),
    ("scripts", "bench, chart and table scripts"),
    ("results", "results and charts"),
    ("docs", "docs"),
    ("tests", "tests"),
    ("other", "elsewhere"),
]


def squash(name):
    return name.replace("_", "").lower()


def words(name):
    return [w for w in re.split(r"[_.\-]+", name.lower()) if w]


def stem_len(stem_words, name_words):
    """len(stem_words) when they occur in name_words in a row, else 0."""
    k = len(stem_words)
    for i in range(len(name_words) - k + 1):
        if all(name_words[i + j] in (s, s + "s") for j, s in enumerate(stem_words)):
            return k
    return 0


def best(name, table):
    """The families whose stems match name best (longest), and the length."""
    nw = words(name)
    top, fams = 0, []
    for fam, stems in table.items():
        n = max(stem_len(words(s), nw) for s in stems)
        if n > top:
            top, fams = n, [fam]
        elif n and n == top:
            fams.append(fam)
    return fams


def base_noext(path):
    b = os.path.basename(path)
    return b.split(".", 1)[0] if not b.startswith(".") else b


def tracked_files(src):
    try:
        out = subprocess.run(["git", "-C", src, "ls-files", "-z"], check=True,
                             capture_output=True).stdout.decode()
        files = [f for f in out.split("\0") if f]
    except (OSError, subprocess.CalledProcessError):
        files = []
        for root, dirs, names in os.walk(src):
            dirs[:] = [d for d in dirs if not d.startswith(".") and not d.startswith("build")]
            files += [os.path.relpath(os.path.join(root, n), src) for n in names]
    return sorted(f for f in files if os.path.isfile(os.path.join(src, f)))


def read(src, path):
    try:
        with open(os.path.join(src, path), encoding="utf-8", errors="replace") as f:
            return f.read()
    except OSError:
        return ""


def role(src, path):
    top = path.split("/", 1)[0]
    name = os.path.basename(path).lower()
    ext = os.path.splitext(name)[1]
    fixed = {"core": "contract", "io": "io", "kinds": "io", "reference": "reference",
             "optimized": "optimized", "registry": "row", "docs": "docs", "tests": "tests"}
    if top in fixed:
        return fixed[top]
    if top not in MEASURE_TOPS:
        return "other"
    if "study" in name and ext in CPP:
        return "studies"
    if ext in CPP:
        if re.search(r"#\s*include\s*[<\"]benchmark/benchmark\.h", read(src, path)):
            return "benchmarks"
        return "properties" if top == "props" else "timing"
    if ext in (".py", ".sh"):
        return "scripts"
    if top == "props":
        return "properties"
    return "results"


def variant(src, path, files):
    """The row an optimized/ file serves: a variant word of its name, else the
    variants of the variant-named optimized/ files it includes (transitively
    through unnamed ones), else "common" (shared by the family's rows)."""
    def named(p):
        return [w for w in words(base_noext(p)) if w in VARIANTS][:1]
    found, seen, todo = set(), {path}, [path]
    while todo:
        p = todo.pop()
        v = named(p)
        if v:
            found.update(v)
            if p != path:
                continue
            break
        for inc in re.findall(r'#\s*include\s*"([^"]+)"', read(src, p)):
            if inc in files and inc.split("/", 1)[0] == "optimized" and inc not in seen:
                seen.add(inc)
                todo.append(inc)
    return "+".join(v for v in VARIANTS if v in found) or "common"


def family_rows(src, files, keys):
    """family key -> (registry files defining `Family <stem>_family(`, headers of
    reference/ and optimized/ declaring a function that function's body names
    as ref::fn or opt::variant::fn, when only one header of reference/, resp.
    optimized/, declares it)."""
    rows, used = {}, {}
    headers = [f for f in files if f.split("/", 1)[0] in ("reference", "optimized")
               and f.endswith((".h", ".hpp"))]
    for f in files:
        if f.split("/", 1)[0] != "registry" or not f.endswith(CPP):
            continue
        text = read(src, f)
        for m in re.finditer(r"\bFamily\s+(\w+)_family\s*\(\s*\)\s*\{", text):
            end = text.find("\n}\n", m.end())
            body = text[m.end():end if end > 0 else len(text)]
            fns = {("reference" if ns == "ref" else "optimized", fn) for ns, fn in
                   re.findall(r"\b(ref|opt::\w+)::(\w+)\b", body)}
            for k in keys:
                if squash(m.group(1)) in {squash(s) for s in STEMS[k]}:
                    rows.setdefault(k, set()).update(
                        g for g in files if os.path.splitext(g)[0] == os.path.splitext(f)[0])
                    for top, fn in fns:  # a name only one header of its floor declares
                        hs = [h for h in headers if h.startswith(top + "/") and
                              re.search(r"\b%s\s*\(" % fn, read(src, h))]
                        if len(hs) == 1:
                            used.setdefault(k, set()).add(hs[0])
    return rows, used


def providers(src, files, keys):
    """family key -> (namespace, folder) of its property provider, read from the
    props/ file that names each family's `ns::properties`."""
    dirs = {}
    for f in files:
        parts = f.split("/")
        if parts[0] == "props":
            for i in range(2, len(parts)):
                dirs.setdefault(parts[i - 1], "/".join(parts[:i]))
    out = {}
    for f in files:
        if f.split("/", 1)[0] != "props" or not f.endswith(".cpp"):
            continue
        for m in re.finditer(r'\{\s*"(\w+)"\s*,\s*(\w+)::properties\s*\}', read(src, f)):
            for k in keys:
                if squash(m.group(1)) == squash(k) and m.group(2) in dirs:
                    out[k] = (m.group(2), dirs[m.group(2)], f)
    return out


def manifest_cases(src, files, names):
    """(manifest path, {registered name: [case, ...]}) from the corpus manifest."""
    manifests = [f for f in files if f.startswith("corpus/") and
                 os.path.basename(f).startswith("manifest")]
    cases = {n: [] for n in names}
    if not manifests:
        return None, cases
    path = manifests[0]
    text = read(src, path)
    m = re.search(r"a line that does not start with one is (\w+)", text)
    default = m.group(1) if m else "ray_cast"
    by_squash = {squash(n): n for n in names}
    for line in text.splitlines():
        fields = line.split("#", 1)[0].split()
        if not fields:
            continue
        fam = by_squash.get(squash(fields[0]))
        if fam and len(fields) > 1:
            cases[fam].append(fields[1])
        elif not fam:
            cases.setdefault(by_squash.get(squash(default), default), []).append(fields[0])
    return path, cases


def index(src, binary):
    names = subprocess.run([binary, "families"], check=True, capture_output=True,
                           text=True).stdout.split()
    key_of = {}
    for n in names:
        k = [k for k in STEMS if squash(k) == squash(n)]
        key_of[n] = k[0] if k else None
    table = {k: STEMS[k] for k in key_of.values() if k}
    files = tracked_files(src)
    fileset = set(files)

    claims = {}  # path -> [family key]
    for f in files:
        parts = f.split("/")
        if parts[0] == "corpus" or len(parts) < 2:
            continue
        fams = best(base_noext(f), table)
        for folder in reversed(parts[1:-1]):
            if fams:
                break
            fams = best(folder, table)
        if fams:
            claims[f] = fams
    rows, used = family_rows(src, files, table)
    provs = providers(src, files, table)
    manifest, cases = manifest_cases(src, files, names)
    corpus_dirs = {}
    for f in files:
        parts = f.split("/")
        if parts[0] == "corpus" and len(parts) > 2:
            for fam in best(parts[1], table) or []:
                corpus_dirs.setdefault(fam, set()).add(parts[1])

    parts = {}  # name -> role -> [path]
    for n in names:
        k = key_of[n]
        p = {r: [] for r, _ in ROLES}
        for f, fams in claims.items():
            if k in fams:
                p[role(src, f)].append(f)
        for f in sorted(rows.get(k, set()) | used.get(k, set())):
            r = role(src, f)
            if f not in p[r]:
                p[r].append(f)
        for r in p:
            p[r].sort()
        parts[n] = p

    sharers = {}
    for n in names:
        k = key_of[n]
        s = set()
        for m in names:
            km = key_of[m]
            if m == n or not k or not km:
                continue
            if rows.get(k, set()) & rows.get(km, set()):
                s.add(m)
            if k in provs and km in provs and provs[k][1] == provs[km][1]:
                s.add(m)
        sharers[n] = sorted(s, key=names.index)

    out = []
    w = out.append
    w("# Where everything of a family lives")
    w("")
    w("Generated by `python3 scripts/family_index.py build/lockstep` from the")
    w("registry (`lockstep families`) and the tree; `ctest -R families.index` fails")
    w("when it is stale, when a family lacks a part, or when a source of reference/,")
    w("optimized/ or registry/ belongs to no family. How a file is matched to a")
    w("family (file-name stems, one table in the script) is said at the top of the")
    w("script. Back to [the docs index](README.md).")
    w("")
    w("Families: " + ", ".join("[%s](#%s)" % (n, n) for n in names) + ".")
    w("")
    for n in names:
        k = key_of[n]
        p = parts[n]
        w("## %s" % n)
        w("")
        w("Stems: %s." % (", ".join("`%s`" % s for s in STEMS[k]) if k else "(none: add the family to STEMS)"))
        if sharers[n]:
            w("Shares its row or property provider with %s." % ", ".join(sharers[n]))
        w("")
        for r, title in ROLES:
            if r == "optimized":
                if not p[r]:
                    continue
                w("* %s:" % title)
                byv = {}
                for f in p[r]:
                    byv.setdefault(variant(src, f, fileset), []).append(f)
                for v in sorted(byv, key=lambda v: ([VARIANTS.index(x) for x in v.split("+")]
                                                    if v != "common" else [len(VARIANTS)])):
                    w("  * %s: %s" % (v, ", ".join(byv[v])))
                continue
            items = list(p[r])
            if r == "properties" and k in provs:
                ns, folder, where = provs[k]
                items = ["provider `%s::properties` in %s/ (%s)" % (ns, folder, where)] + \
                    [f for f in items]
            if not items:
                continue
            if r in ("tests", "results") and len(items) > 8:
                dirs = {}
                for f in items:
                    dirs.setdefault(os.path.dirname(f), []).append(f)
                items = []
                for d in sorted(dirs):
                    if len(dirs[d]) > 3 and "/" in d:
                        items.append("%s/ (%d files)" % (d, len(dirs[d])))
                    else:
                        items += dirs[d]
            w("* %s: %s" % (title, ", ".join(items)))
        c = cases.get(n, [])
        if c:
            w("* corpus cases (%s): %d: %s" % (manifest, len(c), ", ".join(c)))
        else:
            w("* corpus cases: none")
        for d in sorted(corpus_dirs.get(k, ())):
            cnt = sum(1 for f in files if f.startswith("corpus/%s/" % d))
            w("* corpus files: corpus/%s/ (%d files)" % (d, cnt))
        w("")
    w("## Shared")
    w("")
    w("Sources of reference/, optimized/ and registry/ that no one family owns")
    w("(SHARED in the script), and the Google Benchmark sources that run every")
    w("family's rows from the registry:")
    w("")
    shared = [f for f in files if f.split("/", 1)[0] in ("reference", "optimized", "registry")
              and f.endswith(CPP) and base_noext(f) in SHARED and f not in claims]
    for s in SHARED:
        fs = [f for f in shared if base_noext(f) == s]
        if fs:
            w("* %s: %s" % (", ".join(fs), SHARED[s]))
    gb = [f for f in files if f.endswith(CPP) and f not in claims and
          f.split("/", 1)[0] in MEASURE_TOPS and role(src, f) == "benchmarks"]
    if gb:
        w("* Google Benchmark, every family: %s" % ", ".join(gb))
    w("")
    text = "\n".join(out)

    problems = []
    for n in names:
        k, p = key_of[n], parts[n]
        miss = []
        if not k:
            miss.append("a row in scripts/family_index.py STEMS")
        if not p["contract"] and not p["reference"]:
            miss.append("a contract (core/) or reference file")
        if not p["row"]:
            miss.append("a registry row (registry/, `Family %s_family()`)" % (k or n))
        if not p["properties"] and k not in provs:
            miss.append("a properties file (props/)")
        pages = {"docs/%s.md" % s for s in [n] + (STEMS[k] if k else [])}
        if not pages & set(p["docs"]):
            miss.append("a docs page (docs/%s.md)" % n)
        if not cases.get(n):
            miss.append("a corpus case (%s)" % (manifest or "corpus/manifest.txt"))
        if miss:
            problems.append("family %s lacks %s" % (n, "; ".join(miss)))
    for f in files:
        if f.split("/", 1)[0] in ("reference", "optimized", "registry") and f.endswith(CPP) \
                and f not in claims and f not in [r for v in rows.values() for r in v] \
                and base_noext(f) not in SHARED:
            problems.append("unclaimed: %s (no family's stem in its name or folder: "
                            "add a stem or a SHARED entry in scripts/family_index.py)" % f)
    return text, problems


def main(argv):
    args = [a for a in argv[1:] if not a.startswith("--")]
    opts = [a for a in argv[1:] if a.startswith("--")]
    out = None
    if "--out" in argv:
        i = argv.index("--out")
        out = argv[i + 1]
        args.remove(out)
    if len(args) != 1 or any(o not in ("--out", "--check") for o in opts):
        print(__doc__.strip(), file=sys.stderr)
        return 2
    src = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    target = os.path.join(src, "docs", "families.md")
    text, problems = index(src, args[0])
    if "--check" in opts:
        old = read(src, "docs/families.md")
        if old != text:
            sys.stdout.writelines(difflib.unified_diff(
                old.splitlines(True), text.splitlines(True),
                "docs/families.md", "generated"))
            problems.insert(0, "docs/families.md is stale: run "
                               "'python3 scripts/family_index.py build/lockstep' and commit it")
        for p in problems:
            print("families.index: " + p)
        if problems:
            return 1
        print("families.index: docs/families.md is current; %d families, each complete; "
              "every source of reference/, optimized/, registry/ claimed" % len(text.split("\n## ")[1:-1]))
        return 0
    for p in problems:
        print("family_index: warning: " + p, file=sys.stderr)
    if out == "-":
        sys.stdout.write(text)
    else:
        with open(out or target, "w", encoding="utf-8") as f:
            f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
