#!/usr/bin/env python3
"""lockstep verify --json/--junit: the files CI dashboards read.

usage: ci_exports.py LOCKSTEP CORPUS_DIR OUT_DIR EXPECT_RC [verify args...]

Runs `lockstep verify CORPUS_DIR --no-report --json OUT/v.json --junit OUT/v.xml ...`
and checks:
  * the exit code is EXPECT_RC;
  * the JSON parses, has schema "lockstep-verify/1", one row per row of the
    summary line on stdout ("N cases, M rows"), every documented key with its
    type, and "pass" equal to every row passing;
  * the JUnit XML parses, <testsuites tests> = M, one <testsuite> per family
    whose tests/failures add up, one <testcase> per row (classname
    lockstep.<family>, name <case>.<impl>, a non-negative time), a <failure>
    exactly on the rows the JSON says fail, failures = their count.
Prints what differs and exits 1; exits 0 when everything holds.
"""
import json
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def main():
    lockstep, corpus, out, expect_rc = sys.argv[1:5]
    extra = sys.argv[5:]
    os.makedirs(out, exist_ok=True)
    jpath, xpath = os.path.join(out, "v.json"), os.path.join(out, "v.xml")
    for p in (jpath, xpath):
        if os.path.exists(p):
            os.remove(p)
    run = subprocess.run([lockstep, "verify", corpus, "--no-report", "--json", jpath, "--junit", xpath] + extra,
                         capture_output=True, text=True)
    if run.returncode != int(expect_rc):
        fail(f"exit code {run.returncode}, expected {expect_rc}\n{run.stdout[-2000:]}\n{run.stderr[-2000:]}")
    m = re.search(r"^(\d+) cases, (\d+) rows:", run.stdout, re.M)
    if not m:
        fail("no summary line on stdout")
    ncases, nrows = int(m.group(1)), int(m.group(2))

    doc = json.load(open(jpath))
    if doc.get("schema") != "lockstep-verify/1":
        fail(f"schema {doc.get('schema')!r}")
    if doc.get("cases") != ncases or len(doc.get("rows", [])) != nrows:
        fail(f"json: {doc.get('cases')} cases, {len(doc.get('rows', []))} rows; stdout: {ncases}, {nrows}")
    types = {"case": str, "family": str, "impl": str, "ran": bool, "pass": bool, "samples": int, "over": int,
             "over_hard": int, "worst": (int, float, type(None)), "score": (int, float, type(None)),
             "seconds": (int, float), "speedup": (int, float, type(None)), "note": str, "detail": str, "view": str,
             "difference": str, "judged": str, "dropped": int, "dropped_why": str}
    for i, r in enumerate(doc["rows"]):
        for k, t in types.items():
            if k not in r or not isinstance(r[k], t) or (t is int and isinstance(r[k], bool)):
                fail(f"json row {i}: key {k!r} missing or not {t}: {r}")
        if set(r) != set(types):
            fail(f"json row {i}: keys {sorted(set(r) ^ set(types))} not documented")
        if (r["dropped"] > 0) != (r["dropped_why"] != ""):
            fail(f"json row {i}: dropped {r['dropped']} with reason {r['dropped_why']!r}")
    failing = {(r["case"], r["impl"]) for r in doc["rows"] if not r["pass"]}
    if doc.get("pass") != (not failing):
        fail(f"json pass {doc.get('pass')} with {len(failing)} failing rows")

    root = ET.parse(xpath).getroot()
    if root.tag != "testsuites" or int(root.get("tests")) != nrows:
        fail(f"junit root {root.tag} tests={root.get('tests')}, expected testsuites with {nrows}")
    if int(root.get("failures")) != len(failing):
        fail(f"junit failures={root.get('failures')}, json has {len(failing)} failing rows")
    seen, suites = set(), root.findall("testsuite")
    if sum(int(s.get("tests")) for s in suites) != nrows:
        fail("the suites' tests do not add up")
    for s in suites:
        cases = s.findall("testcase")
        if len(cases) != int(s.get("tests")) or sum(1 for c in cases if c.find("failure") is not None) != int(
                s.get("failures")):
            fail(f"suite {s.get('name')}: tests/failures do not match its testcases")
        for c in cases:
            fam = c.get("classname")
            if fam != s.get("name") or not fam.startswith("lockstep.") or float(c.get("time")) < 0:
                fail(f"testcase {c.attrib}")
            seen.add((c.get("name"), c.find("failure") is not None))
    rows_named = {(r["case"] + "." + r["impl"], not r["pass"]) for r in doc["rows"]}
    if seen != rows_named:
        fail(f"junit and json disagree: {sorted(seen ^ rows_named)[:5]}")
    print(f"ok: {ncases} cases, {nrows} rows, {len(failing)} failing, {len(suites)} suites")


if __name__ == "__main__":
    main()
