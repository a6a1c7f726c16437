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
