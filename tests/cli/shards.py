#!/usr/bin/env python3
"""lockstep verify --shard: four shards together give exactly the rows of one run.

usage: shards.py LOCKSTEP CORPUS_DIR OUT_DIR WHOLE_JSON
WHOLE_JSON is one unsharded run's --json (verify.corpus writes it: the corpus
is not verified a second time here). Runs verify as 4 shards (shards 0 and 1
through --shard K/4, shards 2 and 3 through GTEST_TOTAL_SHARDS/
GTEST_SHARD_INDEX, which must touch GTEST_SHARD_STATUS_FILE), each with
--report OUT_DIR/shard-K and --json OUT_DIR/shard-K.json, and checks: every
shard exits 0, no (case, impl) row is in two shards, their union is the
unsharded run's rows exactly, and no shard's measured cost (corpus/costs.txt)
exceeds the largest case's or 1.5x the mean shard's, whichever is larger.
Prints the shards' sizes. Leaves the shards' reports for verify.merge_reports.
"""
import json
import os
import shutil
import subprocess
import sys


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


def rows_of(path):
    return [(r["case"], r["impl"]) for r in json.load(open(path))["rows"]]


def rows(lockstep, corpus, out, name, args=(), env=None):
    path = os.path.join(out, name + ".json")
    report = os.path.join(out, name)
    for old in (path, report):
        if os.path.isdir(old):
            shutil.rmtree(old)
        elif os.path.exists(old):
            os.remove(old)
    run = subprocess.run([lockstep, "verify", corpus, "--report", report, "--json", path, *args],
                         capture_output=True, text=True, env=env)
    if run.returncode != 0:
        fail(f"{name}: exit {run.returncode}\n{run.stdout[-1500:]}\n{run.stderr[-1500:]}")
    return rows_of(path)


def main():
    lockstep, corpus, out, whole_json = sys.argv[1:5]
    os.makedirs(out, exist_ok=True)
    whole = rows_of(whole_json)
    shards = []
    for k in range(4):
        if k < 2:
            shards.append(rows(lockstep, corpus, out, f"shard-{k}", ["--shard", f"{k}/4"]))
        else:
            status = os.path.join(out, f"status{k}")
            if os.path.exists(status):
                os.remove(status)
            env = dict(os.environ, GTEST_TOTAL_SHARDS="4", GTEST_SHARD_INDEX=str(k), GTEST_SHARD_STATUS_FILE=status)
            shards.append(rows(lockstep, corpus, out, f"shard-{k}", env=env))
            if not os.path.exists(status):
                fail(f"shard {k}: GTEST_SHARD_STATUS_FILE not touched")
    seen = {}
    for k, rs in enumerate(shards):
        for r in rs:
            if r in seen:
                fail(f"row {r} in shards {seen[r]} and {k}")
            seen[r] = k
    if sorted(seen) != sorted(whole) or len(whole) != len(set(whole)):
        fail(f"the shards' rows differ from one run's: {sorted(set(seen) ^ set(whole))[:5]}")
    cost = {}
    for line in open(os.path.join(corpus, "costs.txt")):
        w = line.split("#")[0].split()
        if w:
            cost[w[0]] = float(w[1])
    loads = [sum(cost.get(c, 0) for c in {case for case, _ in rs}) for rs in shards]
    bound = max(max(cost.values()), 1.5 * sum(loads) / 4)
    if max(loads) > bound:
        fail(f"unbalanced shards: costs {loads}, bound {bound:.3f}")
    print("ok:", len(whole), "rows;", "shards:", [len(s) for s in shards], "rows, costs", [round(x, 2) for x in loads])


if __name__ == "__main__":
    main()
