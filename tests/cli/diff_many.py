#!/usr/bin/env python3
"""lockstep diff with many pairs: --list FILE and DIR_A DIR_B (issue #21, "One-shot cost").

usage: diff_many.py LOCKSTEP GOLDEN_DIR OUT_DIR
Builds list files and folder pairs from two different golden images (balls-1,
balls-2) and checks, for each: the exit code (0 all agree, 1 any differs,
2 bad input), one result line per pair (PASS/FAIL, both paths) in order, the
summary line's counts, and for bad input one stderr line naming the file (and
the list's line number) with nothing on stdout.
"""
import os
import shutil
import subprocess
import sys


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def run(lockstep, *args):
    r = subprocess.run([lockstep, "diff", *args], capture_output=True, text=True)
    return r.returncode, r.stdout.splitlines(), r.stderr.strip().splitlines()


def expect_pairs(name, got, want_rc, want):
    """want: [(PASS|FAIL, a, b)] in order."""
    rc, out, err = got
    if rc != want_rc:
        fail(f"{name}: exit {rc}, expected {want_rc}\n{out}\n{err}")
    if len(out) != len(want) + 2:
        fail(f"{name}: {len(out)} lines, expected {len(want)} results and a summary:\n" + "\n".join(out))
    for line, (verdict, a, b) in zip(out, want):
        words = line.split()
        if words[:3] != [verdict, a, b]:
            fail(f"{name}: line '{line}', expected '{verdict}  {a}  {b} ...'")
    n_fail = sum(1 for v, _, _ in want if v == "FAIL")
    summary = f"{len(want)} pairs: {len(want) - n_fail} pass, {n_fail} fail"
    if out[-2] != summary or out[-1] != ("FAIL" if n_fail else "PASS"):
        fail(f"{name}: summary '{out[-2]}' / '{out[-1]}', expected '{summary}'")
    print(f"ok: {name}: exit {rc}, {summary}")


def expect_bad(name, got, pattern):
    rc, out, err = got
    if rc != 2 or out or len(err) != 1 or pattern not in err[0]:
        fail(f"{name}: exit {rc}, stdout {out}, stderr {err}; expected exit 2, no stdout, one line with '{pattern}'")
    print(f"ok: {name}: {err[0]}")


def main():
    lockstep, golden, out = sys.argv[1:4]
    root = os.path.join(out, "diff_many")
    shutil.rmtree(root, ignore_errors=True)
    a_dir, b_dir = os.path.join(root, "a"), os.path.join(root, "b")
    for d in (a_dir, b_dir):
        os.makedirs(os.path.join(d, "sub"))
    g1, g2 = os.path.join(golden, "balls-1.exr"), os.path.join(golden, "balls-2.exr")
    # a/x.exr = b/x.exr; a/sub/y.exr differs from b/sub/y.exr; a/z.exr = b/z.exr.
    shutil.copy(g1, os.path.join(a_dir, "x.exr"))
    shutil.copy(g1, os.path.join(b_dir, "x.exr"))
    shutil.copy(g1, os.path.join(a_dir, "sub", "y.exr"))
    shutil.copy(g2, os.path.join(b_dir, "sub", "y.exr"))
    shutil.copy(g2, os.path.join(a_dir, "z.exr"))
    shutil.copy(g2, os.path.join(b_dir, "z.exr"))
    with open(os.path.join(a_dir, "notes.txt"), "w") as f:  # not an image: ignored
        f.write("not an image\n")

    # A list: comments, blank lines, a pair that differs.
    lst = os.path.join(root, "pairs.txt")
    with open(lst, "w") as f:
        f.write(f"# balls\n\n{g1} {g1}\n   # indented comment\n{g1}\t{g2}\n{g2} {g2}\n")
    expect_pairs("list.one_differs", run(lockstep, "--list", lst), 1,
                 [("PASS", g1, g1), ("FAIL", g1, g2), ("PASS", g2, g2)])
    same = os.path.join(root, "same.txt")
    with open(same, "w") as f:
        f.write(f"{g1} {g1}\n{g2} {g2}\n")
    expect_pairs("list.all_agree", run(lockstep, "--list", same), 0, [("PASS", g1, g1), ("PASS", g2, g2)])
    # Options apply to every pair: a threshold above the difference passes it.
    expect_pairs("list.options", run(lockstep, "--list", lst, "--fail", "2"), 0,
                 [("PASS", g1, g1), ("PASS", g1, g2), ("PASS", g2, g2)])

    # Folders: images of the same relative name, sorted; other files ignored.
    expect_pairs("folders.one_differs", run(lockstep, a_dir, b_dir), 1,
                 [("FAIL", f"{a_dir}/sub/y.exr", f"{b_dir}/sub/y.exr"), ("PASS", f"{a_dir}/x.exr", f"{b_dir}/x.exr"),
                  ("PASS", f"{a_dir}/z.exr", f"{b_dir}/z.exr")])

    # Bad input: exit 2, one line naming the file (and the list's line).
    bad = os.path.join(root, "bad.txt")
    with open(bad, "w") as f:
        f.write(f"# ok so far\n{g1} {g1}\n\n{g1} {g2} {g1}\n")
    expect_bad("list.three_fields", run(lockstep, "--list", bad), "bad.txt:4: expected two image paths 'A B', got 3 fields")
    missing = os.path.join(root, "missing.txt")
    with open(missing, "w") as f:
        f.write(f"{g1} {g1}\n{g1} {root}/nope.exr\n")
    expect_bad("list.missing_image", run(lockstep, "--list", missing), f"missing.txt:2: image {root}/nope.exr does not exist")
    expect_bad("list.no_list", run(lockstep, "--list", os.path.join(root, "no-list.txt")), "no-list.txt: cannot read the list")
    empty = os.path.join(root, "empty.txt")
    with open(empty, "w") as f:
        f.write("# nothing\n")
    expect_bad("list.empty", run(lockstep, "--list", empty), "empty.txt: the list names no pair")
    shutil.copy(g1, os.path.join(a_dir, "only-a.exr"))
    expect_bad("folders.one_side", run(lockstep, a_dir, b_dir), f"{b_dir}/only-a.exr: missing: {a_dir}/only-a.exr")
    os.remove(os.path.join(a_dir, "only-a.exr"))
    expect_bad("folders.folder_and_file", run(lockstep, a_dir, g1), f"{a_dir}: is a folder")
    expect_bad("list.with_images", run(lockstep, "--list", lst, g1), "--list takes no images")
    expect_bad("list.heatmap", run(lockstep, "--list", lst, "--heatmap", os.path.join(root, "h.png")), "--heatmap takes one pair")

    # The two-image form is unchanged: its report, not a result line.
    rc, out, _ = run(lockstep, g1, g2)
    if rc != 1 or not out[0].startswith("A  ") or out[-1] != "FAIL":
        fail(f"two images: exit {rc}, output {out}")
    print("ok: two images: the single-pair report as before")


main()
