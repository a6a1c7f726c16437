#!/usr/bin/env python3
"""Compare two NFF files entity by entity, numbers to their printed precision.

usage: compare_nff.py EXPECTED ACTUAL

Both files are read as lines of whitespace-separated tokens (blank lines and
'#' comments skipped). Line i of one must have the same words as line i of
the other, and numbers must agree within the last digit the EXPECTED file
printed: %g prints six significant digits, so 0.272166 stands for any value
in [0.2721655, 0.2721665] and a difference of up to one unit of that digit
(1e-6 here) is rounding, not disagreement. Values printed as 1.11022e-16
(a zero computed as a rounding residue) carry no digits that mean anything
at the scene's scale: two numbers both below 1e-9 in magnitude are equal.

Exit 0 when the files agree; 1 with the first difference (both line numbers,
both lines) on stdout; 2 when a file cannot be read.
"""
import re
import sys

NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")
TINY = 1e-9


def lines(path):
    with open(path, encoding="ascii", errors="replace") as f:
        for number, line in enumerate(f, 1):
            words = line.split()
            if words and not words[0].startswith("#"):
                yield number, line.rstrip("\n"), words


def last_digit(token):
    """The value of one unit in the last printed digit of a %g number."""
    mantissa, _, exponent = token.lower().partition("e")
    mantissa = mantissa.lstrip("+-")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return 10.0 ** (int(exponent or 0) - decimals)


def same(expected, actual):
    if NUMBER.match(expected) and NUMBER.match(actual):
        e, a = float(expected), float(actual)
        if abs(e) < TINY and abs(a) < TINY:
            return True
        return abs(e - a) <= last_digit(expected) * 1.0000001
    return expected == actual


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        exp, act = list(lines(sys.argv[1])), list(lines(sys.argv[2]))
    except OSError as e:
        print(f"compare_nff: {e}", file=sys.stderr)
        return 2
    for (en, el, ew), (an, al, aw) in zip(exp, act):
        if len(ew) != len(aw) or not all(same(x, y) for x, y in zip(ew, aw)):
            print(f"first difference: {sys.argv[1]}:{en}: {el}")
            print(f"              vs  {sys.argv[2]}:{an}: {al}")
            return 1
    if len(exp) != len(act):
        shorter, longer = (sys.argv[1], sys.argv[2]) if len(exp) < len(act) else (sys.argv[2], sys.argv[1])
        print(f"{shorter} ends after {min(len(exp), len(act))} entity lines; {longer} has {max(len(exp), len(act))}")
        return 1
    print(f"{sys.argv[2]} equals {sys.argv[1]}: {len(exp)} lines")
    return 0


if __name__ == "__main__":
    sys.exit(main())
