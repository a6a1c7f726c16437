#!/usr/bin/python3
"""The CI exports against the schemas CI systems and readers hold them to.

usage: validate.py run LOCKSTEP CORPUS_DIR OUT_DIR [verify args...]
       validate.py files FILE.xml|FILE.json...
       validate.py invalid FILE.xml|FILE.json...

run:     `lockstep verify CORPUS_DIR --no-report --json OUT/v.json --junit OUT/v.xml ...`
         (exit 0 or 1), then both files must validate, and the same files with a
         deliberate flaw (the first testcase's name dropped; the first row's impl
         dropped) must not;
files:   each file must validate;
invalid: each file must NOT validate (the validators can fail).
JUnit: `xmllint --noout --schema tests/schemas/junit-10.xsd` (Debian's
libxml2-utils), the Jenkins xUnit plugin's junit-10.xsd. JSON:
tests/schemas/lockstep-verify-1.schema.json (draft 2020-12) with Debian's
python3-jsonschema; a file named report.json (the report page's data) against
tests/schemas/lockstep-report-1.schema.json. A missing xmllint or jsonschema is a failure, not a skip.
"""
import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
XSD = os.path.join(HERE, "junit-10.xsd")
JSON_SCHEMA = os.path.join(HERE, "lockstep-verify-1.schema.json")
REPORT_SCHEMA = os.path.join(HERE, "lockstep-report-1.schema.json")


def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)


try:
    import jsonschema
except ImportError as e:
    fail(f"python3-jsonschema is missing (scripts/setup.sh installs it): {e}")


def junit_errors(path):
    try:
        run = subprocess.run(["xmllint", "--noout", "--schema", XSD, path], capture_output=True, text=True)
    except FileNotFoundError:
        fail("xmllint is missing (scripts/setup.sh installs libxml2-utils)")
    return [] if run.returncode == 0 else [run.stderr.strip() or f"xmllint exit {run.returncode}"]


def json_errors(path):
    """lockstep-verify/1 (--json, verify.json) or, for report.json, lockstep-report/1 (whose rows are verify's)."""
    verify = json.load(open(JSON_SCHEMA))
    report = json.load(open(REPORT_SCHEMA))
    for sch in (verify, report):
        jsonschema.Draft202012Validator.check_schema(sch)
    try:
        doc = json.load(open(path))
    except ValueError as e:
        return [f"not JSON: {e}"]
    schema = report if os.path.basename(path) == "report.json" else verify
    resolver = jsonschema.RefResolver.from_schema(schema, store={verify["$id"]: verify, report["$id"]: report})
    v = jsonschema.Draft202012Validator(schema, resolver=resolver)
    return [f"{'/'.join(map(str, e.absolute_path)) or '(root)'}: {e.message}" for e in v.iter_errors(doc)]


def errors(path):
    return junit_errors(path) if path.endswith(".xml") else json_errors(path)


def must_validate(path):
    e = errors(path)
    if e:
        fail(f"{path} does not validate:\n" + "\n".join(e[:10]))
    print("valid:", path)


def must_not_validate(path):
    e = errors(path)
    if not e:
        fail(f"{path} validates, but is broken on purpose: the validator cannot fail")
    print("invalid as it should be:", path, "--", e[0].splitlines()[0][:160])


def main():
    mode, args = sys.argv[1], sys.argv[2:]
    if mode == "files":
        for p in args:
            must_validate(p)
    elif mode == "invalid":
        for p in args:
            must_not_validate(p)
    elif mode == "run":
        lockstep, corpus, out = args[:3]
        os.makedirs(out, exist_ok=True)
        j, x = os.path.join(out, "v.json"), os.path.join(out, "v.xml")
        for p in (j, x):
            if os.path.exists(p):
                os.remove(p)
        run = subprocess.run([lockstep, "verify", corpus, "--no-report", "--json", j, "--junit", x] + args[3:],
                             capture_output=True, text=True)
        if run.returncode not in (0, 1):
            fail(f"verify exited {run.returncode}\n{run.stderr[-2000:]}")
        must_validate(x)
        must_validate(j)
        # The same files, each with one deliberate flaw.
        tree = ET.parse(x)
        case = tree.getroot().find("testsuite/testcase")
        del case.attrib["name"]
        bad_x = os.path.join(out, "v-testcase-without-name.xml")
        tree.write(bad_x, encoding="UTF-8", xml_declaration=True)
        must_not_validate(bad_x)
        doc = json.load(open(j))
        del doc["rows"][0]["impl"]
        bad_j = os.path.join(out, "v-row-without-impl.json")
        json.dump(doc, open(bad_j, "w"))
        must_not_validate(bad_j)
    else:
        fail("usage: validate.py run|files|invalid ...")


if __name__ == "__main__":
    main()
