#!/usr/bin/env python3
"""bench/scripts/benchmarks_md.py on copies of bench/results: the verdicts follow the
data, a lockstep-table/1 file becomes a section with its targets in the
summary, a hand-edited page fails --check, and bad input is one clear error
(exit 2) with nothing written.

usage: benchmarks_md_test.py (run by the ctest benchmarks_md.generator)
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GEN = os.path.join(ROOT, "bench", "scripts", "benchmarks_md.py")


def read(path):
    with open(path) as f:
        return f.read()


def load(path):
    with open(path) as f:
        return json.load(f)


def save(path, d):
    with open(path, "w") as f:
        json.dump(d, f, indent=1)


def run(*args):
    return subprocess.run([sys.executable, GEN, *args], capture_output=True, text=True)


class Generator(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="benchmarks_md_")
        self.results = os.path.join(self.tmp, "results")
        shutil.copytree(os.path.join(ROOT, "bench", "results"), self.results)
        self.targets = os.path.join(self.tmp, "targets.json")
        shutil.copy(os.path.join(ROOT, "bench", "targets.json"), self.targets)
        self.out = os.path.join(self.tmp, "BENCHMARKS.md")

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def generate(self):
        r = run("--results", self.results, "--targets", self.targets, "--out", self.out)
        self.assertEqual(r.returncode, 0, r.stderr)
        return read(self.out)

    def row(self, page, text):
        hit = [ln for ln in page.splitlines() if ln.startswith("| #") and text in ln]
        self.assertEqual(len(hit), 1, f"one summary row for {text!r}")
        return hit[0]

    def test_same_as_committed(self):
        self.assertEqual(self.generate(), read(os.path.join(ROOT, "BENCHMARKS.md")))

    def test_verdict_follows_the_data(self):
        # balls-3's simd frame made 10x slower: issue #2's 8x target turns to not met, with the new figure.
        p = os.path.join(self.results, "latest.json")
        d = load(p)
        for b in d["benchmarks"]:
            if b["name"].startswith("frame/ray_cast/balls-3/simd/threads:1/"):
                b["items_per_second"] /= 10
        save(p, d)
        row = self.row(self.generate(), "simd >= 8x reference on balls-3")
        self.assertIn("2.4x", row)
        self.assertTrue(row.endswith("| **not met** |"), row)

    def test_lockstep_table_section(self):
        sample = {"schema": "lockstep-table/1", "title": "One-shot cost (sample)", "command": "lockstep --version",
                  "date": "2026-12-03", "machine": "this one", "note": "A sample | with a pipe.",
                  "columns": ["subcommand", "process start ms", "cold frame ms"],
                  "rows": [["version", 0.3, "-"], ["render", 12.5, 11.7]],
                  "targets": [{"text": "version no slower than idiff", "measured": "0.30 s against 0.23 s",
                               "met": False, "issue": 21}]}
        save(os.path.join(self.results, "sample_oneshot.json"), sample)
        page = self.generate()
        self.assertIn("## Other measurements", page)
        self.assertIn("### One-shot cost (sample)", page)
        self.assertIn("| render | 12.5 | 11.7 |", page)
        self.assertIn("Measured by `lockstep --version`, 2026-12-03, this one. A sample | with a pipe.", page)
        self.assertTrue(self.row(page, "version no slower than idiff").endswith("| 0.30 s against 0.23 s | **not met** |"))

    def test_missing_results_leave_tables_out(self):
        os.remove(os.path.join(self.results, "volume_bench.json"))
        page = self.generate()
        self.assertNotIn("### Frames: ms per frame", page)
        self.assertIn("not measured (volume_bench.json absent)", self.row(page, "with empty-space skipping"))

    def test_hand_edit_fails_check(self):
        page = self.generate()
        with open(self.out, "w") as f:
            f.write(page.replace("23.7x", "25.0x", 1))
        r = run("--check", "--results", self.results, "--targets", self.targets, "--out", self.out)
        self.assertEqual(r.returncode, 1)
        self.assertIn("differs from what bench/results makes", r.stderr)
        self.assertIn("+| #2 | ray casting | simd >= 8x", r.stderr)

    def assert_error(self, expect):
        with open(self.out, "w") as f:
            f.write("old page\n")
        r = run("--results", self.results, "--targets", self.targets, "--out", self.out)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertRegex(r.stderr, expect)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertEqual(read(self.out), "old page\n")
        self.assertFalse(os.path.exists(self.out + ".tmp"))

    def test_bad_json(self):
        with open(os.path.join(self.results, "raster.json"), "w") as f:
            f.write('{\n "context": {},\n "benchmarks": [\n')
        self.assert_error(r"/results/raster\.json:4: not JSON")

    def test_bad_lockstep_table(self):
        p = os.path.join(self.results, "mc_bench.json")
        d = load(p)
        d["rows"][0].pop()
        save(p, d)
        self.assert_error(r"/results/mc_bench\.json: row 1 is not a list of 8 cells")

    def test_bad_target(self):
        t = load(self.targets)
        t[0]["value"] = "simd.__class__"
        save(self.targets, t)
        self.assert_error(r"targets\.json:\d+: 'simd\.__class__': Attribute is not allowed in a target")
        t[0]["value"] = "simd / "
        save(self.targets, t)
        self.assert_error(r"targets\.json:\d+: 'simd / ': invalid syntax")

    def test_partial_results(self):
        """A target whose expression fails on the results (a quick run's: no such rows) is an
        error, and with --partial (bench/run.sh --quick) a target not measured; a disallowed
        expression stays an error."""
        t = load(self.targets)
        t[0]["value"] = "[simd][1]"
        save(self.targets, t)
        self.assert_error(r"targets\.json:\d+: '\[simd\]\[1\]': IndexError")
        r = run("--partial", "--results", self.results, "--targets", self.targets, "--out", self.out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("not measured (partial results:", self.row(read(self.out), t[0]["text"]))
        t[0]["value"] = "simd.__class__"
        save(self.targets, t)
        r = run("--partial", "--results", self.results, "--targets", self.targets, "--out", self.out)
        self.assertEqual(r.returncode, 2, r.stderr)


if __name__ == "__main__":
    unittest.main()
