"""What the chart and table scripts share (bench/scripts/*_chart.py, *_charts.py,
*_table.py): their command line, the machine line and the Markdown table they print
beside the lockstep-table/1 JSON they write."""
import os
import platform
import re
import sys
import types


def args(doc, argv=None):
    """The command line (argv, default sys.argv[1:]) as the usage line of doc (the
    script's __doc__) names it: "usage: x.py STUDY_CSV [BENCH_JSON] OUT_DIR" gives
    .study_csv, .bench_json and .out_dir (names lower case, other than letters,
    digits and _ made _). Optional ([NAME]) arguments take what is given beyond the
    required ones, left to right; those not given are None. Any other count of
    arguments exits (status 1) with doc."""
    argv = sys.argv[1:] if argv is None else argv
    usage = next(line for line in doc.splitlines() if line.startswith("usage:"))
    words = usage.split()[2:]
    spare = len(argv) - sum(not w.startswith("[") for w in words)  # optional ones given
    if not 0 <= spare <= sum(w.startswith("[") for w in words):
        sys.exit(doc)
    given = iter(argv)
    out = types.SimpleNamespace()
    for word in words:
        value = None
        if not word.startswith("["):
            value = next(given)
        elif spare > 0:
            value, spare = next(given), spare - 1
        setattr(out, re.sub(r"\W", "_", word.strip("[]")).lower(), value)
    return out


def machine():
    """The CPU, as /proc/cpuinfo names it, and the core count (bench/results/machine.txt's first line)."""
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip() + f", {os.cpu_count()} cores"
    except OSError:
        pass
    return platform.machine()


def markdown_table(cols, body):
    """cols: header cells; body: rows of cell strings. The first two columns left-aligned, the rest right."""
    out = ["| " + " | ".join(cols) + " |", "|---|---|" + "---:|" * (len(cols) - 2)]
    out += ["| " + " | ".join(r) + " |" for r in body]
    return "\n".join(out)


def write_table(doc, path):
    """A lockstep-table/1 document to path, through path.tmp and a rename (never half written)."""
    import json

    tmp = path + ".tmp"
    with open(tmp, "w") as fh:
        json.dump(doc, fh, indent=1)
        fh.write("\n")
    os.replace(tmp, path)


def load_csv(path, convert):
    """The rows of a study's CSV, each passed through convert(dict of header -> cell).
    The header is the first line that is neither blank nor a '#' comment; blank
    lines, comments and repeated headers (one tool run per scene, appended) are
    skipped. A row of the wrong width, or one convert rejects (KeyError,
    ValueError), exits naming the file and line."""
    head, rows = None, []
    with open(path) as fh:
        for n, line in enumerate(fh, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            cells = line.split(",")
            if head is None or cells == head:
                head = cells
                continue
            if len(cells) != len(head):
                sys.exit(f"{path}:{n}: {len(cells)} cells, the header has {len(head)}")
            try:
                rows.append(convert(dict(zip(head, cells))))
            except (KeyError, ValueError) as e:
                sys.exit(f"{path}:{n}: bad row ({e!r})")
    return rows


def bench_keys(rows, pattern, key):
    """The distinct keys, in first-seen order, of the Google Benchmark names that
    fully match pattern: key(match) for each (e.g. (scene, depth))."""
    keys = []
    for name in rows:
        m = re.fullmatch(pattern, name)
        if m and key(m) not in keys:
            keys.append(key(m))
    return keys
