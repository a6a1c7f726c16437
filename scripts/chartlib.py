"""What the chart scripts share (scripts/*_chart.py): the machine line and the
Markdown table they print beside the lockstep-table/1 JSON they write."""
import os
import platform


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
