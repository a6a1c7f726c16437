#!/usr/bin/env python3
"""Measured cost of each corpus case, for `lockstep verify --shard K/N`.

usage: python3 scripts/case_costs.py VERIFY.json > corpus/costs.txt
  VERIFY.json  from `lockstep verify --no-report --json VERIFY.json` (every case)
Writes 'case seconds' lines: the sum of the case's rows' times, which is what
a shard spends on it (inputs loaded apart). Shards split cases
longest-first by these (app/verify_shard.cpp).
"""
import json
import sys


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    doc = json.load(open(sys.argv[1]))
    cost = {}
    for r in doc["rows"]:
        cost[r["case"]] = cost.get(r["case"], 0.0) + r["seconds"]
    print("# lockstep verify's case costs (seconds, all rows of a case), measured by")
    print("# `lockstep verify --no-report --json v.json && python3 scripts/case_costs.py v.json`;")
    print("# --shard K/N balances the shards by them (app/verify_shard.cpp).")
    for name, s in cost.items():
        print(f"{name} {s:.4f}")


if __name__ == "__main__":
    main()
