#!/usr/bin/env python3
"""ctest layout.readme: the README's Layout section names the tree and the registry.

  python3 tests/layout_check.py SOURCE_DIR LOCKSTEP_BINARY

Fails (exit 1, one line per finding) when
  * a top-level folder of the repository (git ls-files; dot folders and build
    excluded) is not named in README.md's "## Layout" section (a line of its
    code block starting with "NAME/"); the section may name folders that do
    not exist yet (a layout being moved to);
  * a family the binary registers (`lockstep families`, one name a line) has
    no page docs/<family>.md, is not named in the Layout section, or is not
    linked from the docs index (docs/README.md).
A family's name matches with or without underscores (marching_cubes,
marchingcubes).
"""
import os
import re
import subprocess
import sys


def squash(name):
    return name.replace("_", "").lower()


def main():
    if len(sys.argv) != 3:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    src, binary = sys.argv[1], sys.argv[2]
    problems = []

    readme = open(os.path.join(src, "README.md"), encoding="utf-8").read()
    m = re.search(r"^## Layout\s*$(.*?)(?=^## |\Z)", readme, re.M | re.S)
    if not m:
        print("layout.readme: README.md has no '## Layout' section")
        return 1
    layout = m.group(1)
    named = set()
    in_block = False
    for line in layout.splitlines():
        if line.startswith("```"):
            in_block = not in_block
            continue
        if in_block:
            w = re.match(r"^([^\s/]+)/(\s|$)", line)
            if w:
                named.add(w.group(1))
    if not named:
        problems.append("the Layout section's code block names no folder ('NAME/  what it holds')")

    files = subprocess.run(["git", "-C", src, "ls-files"], check=True, capture_output=True,
                           text=True).stdout.splitlines()
    top = sorted({f.split("/", 1)[0] for f in files if "/" in f})
    top = [d for d in top if not d.startswith(".") and not d.startswith("build")]
    for d in top:
        if d not in named:
            problems.append(f"top folder {d}/ is not named in README.md's Layout section")

    out = subprocess.run([binary, "families"], check=True, capture_output=True, text=True).stdout
    families = [l.strip() for l in out.splitlines() if l.strip()]
    if not families:
        problems.append(f"'{binary} families' printed no family")
    docs = os.path.join(src, "docs")
    pages = {squash(f[:-3]): f for f in os.listdir(docs) if f.endswith(".md")} if os.path.isdir(docs) else {}
    layout_words = {squash(w) for w in re.findall(r"[A-Za-z0-9_]+", layout)}
    index_path = os.path.join(docs, "README.md")
    index = open(index_path, encoding="utf-8").read() if os.path.exists(index_path) else ""
    linked = {squash(l[:-3]) for l in re.findall(r"\]\(([A-Za-z0-9_]+\.md)\)", index)}
    for fam in families:
        if squash(fam) not in pages:
            problems.append(f"family {fam} has no page docs/{fam}.md")
        if squash(fam) not in layout_words:
            problems.append(f"family {fam} is not named in README.md's Layout section")
        if squash(fam) not in linked:
            problems.append(f"family {fam}'s page is not linked from docs/README.md")

    for p in problems:
        print("layout.readme: " + p)
    if problems:
        return 1
    print(f"layout.readme: {len(top)} top folders named ({', '.join(top)}); "
          f"{len(families)} families with pages ({', '.join(families)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
