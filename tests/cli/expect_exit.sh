#!/usr/bin/env bash
# Runs a lockstep command and checks how it ends.
#   expect_exit.sh RC OUT STDERR_REGEX -- COMMAND...
# RC            the exit code the command must return
# OUT           a file the command is asked to write: it must exist afterwards when
#               RC is 0 and must NOT exist otherwise (no half-written output);
#               '-' when the command writes nothing
# STDERR_REGEX  an extended regex stderr must match ('' = anything); for RC 2
#               stderr must also be exactly one line
set -uo pipefail
want=$1 out=$2 pattern=$3
shift 3
[[ $1 == -- ]] && shift
[[ $out != - ]] && rm -f "$out"
err=$(mktemp)
"$@" >/dev/null 2>"$err"
rc=$?
fail() {
  echo "FAIL: $*"
  echo "  command: $*"
  echo "  stderr:"; sed 's/^/    /' "$err"
  rm -f "$err"
  exit 1
}
[[ $rc == "$want" ]] || fail "exit code $rc, expected $want: $*"
if [[ $out != - ]]; then
  if [[ $want == 0 ]]; then [[ -s $out ]] || fail "no output file $out"
  else [[ -e $out ]] && fail "output file $out left behind"; fi
  rm -f "$out"
fi
if [[ -n $pattern ]]; then grep -Eq -- "$pattern" "$err" || fail "stderr does not match /$pattern/"; fi
if [[ $want == 2 ]]; then
  lines=$(grep -c . "$err")
  [[ $lines == 1 ]] || fail "expected one error line on stderr, got $lines"
fi
echo "ok: exit $rc: $(head -c 300 "$err")"
rm -f "$err"
