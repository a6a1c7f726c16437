#!/usr/bin/env python3
"""lockstep merge-reports: four shards' reports merged are one run's report.

usage: merge_reports.py LOCKSTEP WHOLE SHARDS_DIR OUT_DIR

WHOLE is one unsharded run of the corpus (verify.corpus: WHOLE/ its report,
WHOLE.json its --json, WHOLE.xml its --junit); SHARDS_DIR holds the same
corpus verified as four shards (verify.shards: shard-K/ with --report and
shard-K.json with --json, K = 0..3). merges the shards into OUT/merged and checks:
  * merge-reports exits as the unsharded run does (0 all pass, 1 some fail);
  * OUT/merged/verify.json has exactly the unsharded JSON's rows, field for
    field except the timing fields (seconds, speedup), and its case count;
  * OUT/merged/verify.xml has the unsharded JUnit's testcases (suite,
    classname, name, failure or not), and suites whose counts add up;
  * OUT/merged/report.json has every case once, and every picture a row or
    a case names exists in OUT/merged (the shards' case folders were copied);
  * the shards' --json files (lockstep-verify/1) merged give the same rows
    but for the picture paths (none), and the same JUnit testcases;
  * errors: a missing shard, a malformed report.json (cut short), the same
    shard twice (also once as a folder, once as its --json), a report.json
    given where a --json file is expected, each exit 2 with one line naming the file, and write nothing
    (OUT_DIR is not created, no OUT_DIR.partial is left); an existing
    OUT_DIR that is not a report is not replaced.
Leaves OUT/merged for the tests that validate it (schemas.merged) and open it
in the browser (report.browser_merged).
"""
import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

TIMING = ("seconds", "speedup")


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def run(args, expect=None):
    r = subprocess.run(args, capture_output=True, text=True)
    if expect is not None and r.returncode != expect:
        fail(f"{' '.join(args)}: exit {r.returncode}, expected {expect}\n{r.stdout[-1500:]}\n{r.stderr[-1500:]}")
    return r


def testcases(path):
    root = ET.parse(path).getroot()
    out = []
    for s in root.findall("testsuite"):
        cases = s.findall("testcase")
        if int(s.get("tests")) != len(cases) or int(s.get("failures")) != sum(c.find("failure") is not None for c in cases):
            fail(f"{path}: suite {s.get('name')} counts do not add up")
        out += [(s.get("name"), c.get("classname"), c.get("name"), c.find("failure") is not None) for c in cases]
    if int(root.get("tests")) != len(out):
        fail(f"{path}: <testsuites tests> {root.get('tests')} but {len(out)} testcases")
    return sorted(out)


def untimed(rows):
    return sorted(json.dumps({k: v for k, v in r.items() if k not in TIMING}, sort_keys=True) for r in rows)


def main():
    lockstep, whole_dir, shards_dir, out = sys.argv[1:5]
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    p = lambda *a: os.path.join(out, *a)
    shards = [os.path.join(shards_dir, f"shard-{k}") for k in range(4)]
    for d in shards:
        if not os.path.isfile(os.path.join(d, "report.json")) or not os.path.isfile(d + ".json"):
            fail(f"{d}: no shard report (verify.shards writes them)")
    a = json.load(open(whole_dir + ".json"))
    # merge-reports exits as the one run did: 0 when every row passed, else 1.
    whole_exit = 0 if a["pass"] else 1
    merged = p("merged")
    m = run([lockstep, "merge-reports", merged] + shards, expect=whole_exit)

    b = json.load(open(p("merged", "verify.json")))
    if a["cases"] != b["cases"] or a["pass"] != b["pass"]:
        fail(f"merged cases/pass {b['cases']}/{b['pass']}, one run {a['cases']}/{a['pass']}")
    if untimed(a["rows"]) != untimed(b["rows"]):
        diff = set(untimed(a["rows"])) ^ set(untimed(b["rows"]))
        fail(f"merged rows differ from one run's ({len(a['rows'])} vs {len(b['rows'])}): {sorted(diff)[:3]}")
    ta, tb = testcases(whole_dir + ".xml"), testcases(p("merged", "verify.xml"))
    if ta != tb:
        fail(f"merged JUnit testcases differ: {sorted(set(ta) ^ set(tb))[:5]}")
    rep = json.load(open(p("merged", "report.json")))
    names = [c["case"] for c in rep["case_info"]]
    if len(names) != len(set(names)) or len(names) != a["cases"] or rep.get("merged_from") != 4:
        fail(f"merged report.json: {len(names)} cases ({len(set(names))} distinct), merged_from {rep.get('merged_from')}")
    files = [r[k] for r in rep["rows"] for k in ("view", "difference", "judged") if r[k]]
    files += [c["golden"] for c in rep["case_info"] if c["golden"]] + [n + "/pixels.js" for n in names]
    missing = [f for f in files if not os.path.isfile(os.path.join(merged, f))]
    if missing or not os.path.isfile(os.path.join(merged, "index.html")):
        fail(f"merged report lacks {len(missing)} of {len(files)} files: {missing[:3]}")

    # The shards' --json files merge into the same rows, without pictures.
    mj = p("merged-json")
    run([lockstep, "merge-reports", mj] + [d + ".json" for d in shards], expect=whole_exit)
    c = json.load(open(os.path.join(mj, "verify.json")))
    nopics = lambda rows: untimed([dict(r, view="", difference="", judged="") for r in rows])
    if c["cases"] != a["cases"] or nopics(a["rows"]) != nopics(c["rows"]) or any(
            r["view"] or r["difference"] or r["judged"] for r in c["rows"]):
        fail("the shards' --json files merged differ from one run's rows (pictures aside)")
    if testcases(os.path.join(mj, "verify.xml")) != ta:
        fail("the shards' --json files merged: JUnit testcases differ")

    # Errors: exit 2, one line naming the file, nothing written.
    bad = p("broken")
    shutil.copytree(shards[1], bad)
    text = open(os.path.join(bad, "report.json")).read()
    open(os.path.join(bad, "report.json"), "w").write(text[: len(text) // 2])
    for what, inputs, named in [("missing shard", [shards[0], p("no-such-shard")], p("no-such-shard", "report.json")),
                                ("malformed report.json", [shards[0], bad], os.path.join(bad, "report.json") + ":"),
                                ("same shard twice", [shards[0], shards[0]], "too"),
                                ("a shard as report and as --json", [shards[0], shards[0] + ".json"], "too"),
                                ("a report given as --json", [shards[0], os.path.join(shards[1], "report.json")],
                                 "not a verify --json file")]:
        target = p("bad-out")
        r = run([lockstep, "merge-reports", target] + inputs, expect=2)
        lines = r.stderr.strip().splitlines()
        if len(lines) != 1 or named not in lines[0]:
            fail(f"{what}: stderr should be one line naming {named}: {r.stderr!r}")
        if os.path.exists(target) or os.path.exists(target + ".partial"):
            fail(f"{what}: something was written")
    os.makedirs(p("not-a-report"))
    open(p("not-a-report", "keep.txt"), "w").write("mine\n")
    run([lockstep, "merge-reports", p("not-a-report")] + shards, expect=2)
    if not os.path.exists(p("not-a-report", "keep.txt")):
        fail("merge-reports replaced a folder that is not a report")
    print(f"ok: {len(b['rows'])} rows, {b['cases']} cases merged from 4 shards = one run's; {len(tb)} testcases; "
          f"{len(files)} files; errors named and nothing written. {m.stdout.strip()}")


if __name__ == "__main__":
    main()
