#!/usr/bin/env bash
# The floors of the house (README, Layout): each folder may include only from
# the folders listed for it. A file in a folder of C++ code not listed here
# fails too, so a new folder has to be given its floor.
#
#   bash tests/layering.sh SOURCE_DIR [FLOOR]     (no FLOOR: every floor)
set -uo pipefail
cd "$1" || exit 2
only=${2:-}
# floor: the folders its files may include from (itself always).
table='
core:
io: core
kinds: core io
reference: core io kinds
optimized: core io kinds
registry: core io kinds reference optimized spd
spd:
# props/ is below bench/ (the studies use the oracles, not the other way).
props: core io kinds reference optimized registry
bench: core io kinds reference optimized registry props
app: core io kinds reference optimized registry spd
corpus: core io kinds reference
cmake:
tests: core io kinds reference optimized registry props spd
'
status=0
declare -A floor_of
while read -r line; do
  [[ -z $line ]] && continue
  floor_of[${line%%:*}]="${line#*:}"
done <<< "$table"
# Every folder holding C++ files has a floor.
for dir in $(git ls-files '*.cpp' '*.h' | cut -d/ -f1 | grep -v '\.' | sort -u); do
  if [[ -z ${floor_of[$dir]+x} ]]; then
    echo "layering: $dir/ holds C++ files but has no floor in tests/layering.sh"
    status=1
  fi
done
for floor in "${!floor_of[@]}"; do
  [[ -n $only && $floor != "$only" ]] && continue
  ok=" $floor ${floor_of[$floor]} "
  while IFS=: read -r file lineno text; do
    [[ -z $file ]] && continue
    dir=$(sed -E 's/.*#include "([a-z_]+)\/.*/\1/' <<< "$text")
    [[ $ok == *" $dir "* ]] && continue
    echo "layering: $file:$lineno includes from $dir/, above the $floor floor (may use:${floor_of[$floor]:- nothing else})"
    status=1
  done < <(git ls-files "$floor/*.cpp" "$floor/*.h" "$floor/**/*.cpp" "$floor/**/*.h" | sort -u |
           xargs -r grep -nE '^#include "[a-z_]+/' /dev/null | grep -v ':#include "hwy/')
done
[[ $status == 0 ]] && echo "layering: every include runs downward${only:+ ($only)}"
exit $status
