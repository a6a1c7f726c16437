#!/usr/bin/env bash
# Every data path goes through the one resolver (registry/loaders.h): no code,
# CMake file or test script names ../shared by path except the CMake variable
# that is the resolver's build-time default (LOCKSTEP_SHARED_DIR), and no code
# but the resolver and the benchmarks' note reads an SPD file from spd_dir()
# itself (load_spd generates the scene when the file is not there; a direct
# read fails in a clone without ../shared, as bench/studies/cones_study.cpp did).
#   one_resolver.sh SOURCE_DIR
# Comment lines are not code; messages ("a clone without ../shared") are not paths.
set -uo pipefail
cd "$1" || exit 2
bad=0
paths=$(git ls-files '*.cpp' '*.h' '*CMakeLists.txt' '*.cmake' 'tests/*.sh' 'tests/*.py' 'props/*.sh' '.ci/*' 2>/dev/null |
        xargs grep -nE '(/|")\.\./shared|\.\./shared/' | grep -vE '^[^:]+:[0-9]+: *(//|#)' |
        grep -vE '^CMakeLists\.txt:[0-9]+:set\(LOCKSTEP_SHARED_DIR ')
if [[ -n $paths ]]; then
  echo "names ../shared by path instead of going through registry/loaders.h (spd_dir, volumes_dir, load_spd):"
  echo "$paths"
  bad=1
fi
direct=$(git ls-files '*.cpp' '*.h' | grep -vE '^(registry/loaders\.(h|cpp)|bench/bench_main\.cpp)$' |
         xargs grep -nE 'spd_dir\(\)' | grep -vE '^[^:]+:[0-9]+: *//')
if [[ -n $direct ]]; then
  echo "reads SPD files from spd_dir() itself instead of load_spd (which generates a missing scene):"
  echo "$direct"
  bad=1
fi
[[ $bad == 0 ]] && echo "ok: ../shared named only by LOCKSTEP_SHARED_DIR; spd_dir() only in the resolver"
exit $bad
