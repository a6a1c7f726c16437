#!/usr/bin/env bash
# ctest cli.doc: docs/cli.md is what scripts/cli_doc.sh writes from this
# build's --help texts. Fails (with the diff) when a help text changed and
# docs/cli.md was not regenerated.
#   bash tests/cli_doc_check.sh SOURCE_DIR LOCKSTEP_BINARY
set -euo pipefail
src=$1
bin=$2
# docs/cli.md lists every peer row; a build without one of them prints other
# implementation lists and cannot check it (skipped, exit 77, saying which).
missing=$("$bin" --version | sed -n 's/^ *\([a-z]*\) row: not built.*/\1/p' | tr '\n' ' ')
if [ -n "$missing" ]; then
  echo "cli.doc: skipped: this build lacks the peer rows $missing(docs/cli.md is written with every peer: scripts/setup.sh --peers)"
  exit 77
fi
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
bash "$src/scripts/cli_doc.sh" "$bin" - >"$tmp"
if ! diff -u "$src/docs/cli.md" "$tmp"; then
  echo "cli.doc: docs/cli.md is stale: run 'bash scripts/cli_doc.sh' and commit it" >&2
  exit 1
fi
echo "cli.doc: docs/cli.md matches the help of $bin ($(wc -l <"$tmp") lines)"
