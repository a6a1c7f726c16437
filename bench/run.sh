#!/usr/bin/env bash
# Rerun everything BENCHMARKS.md shows and regenerate the page: the Google
# Benchmark runs (bench_main.cpp), the studies (studies/), the timing programs
# (timing/), the charts and tables (scripts/), in order, one progress line per
# step; then BENCHMARKS.md through bench/scripts/benchmarks_md.py. Full: hours on 2
# cores; run it on an idle machine (the figures are the machine's).
#
#   bash bench/run.sh                    every step, into bench/results, bench/charts, BENCHMARKS.md
#   bash bench/run.sh --only raster,page some steps (--list names them)
#   bash bench/run.sh --quick [DIR]      every step on its smallest sizes, one repetition, into DIR
#                                        (default a fresh temp dir): bench/results, bench/charts
#                                        and BENCHMARKS.md are not touched; each step's outputs are
#                                        checked (the ctest bench.rerun_quick)
#   --build DIR      the build folder (default build; configured and built first unless --no-build)
#   --no-build       use DIR as it is (the ctest)
#   -- ARGS...       extra arguments to every lockstep_bench run (e.g. --benchmark_min_time=0.1)
#
# A step whose data or peer is missing (../shared, OSMesa, skimage, strace)
# is skipped with the reason printed; a step that fails, or does not write its
# outputs, fails the run (exit 1) after the others ran. The results no step
# makes are kept as they are (listed by --list: tables transcribed from the
# hand-written page, and the A/B of two builds, bench/scripts/ray_trace_packets_ab.sh).
set -euo pipefail
here=$PWD
cd "$(dirname "$0")/.."
ROOT=$PWD
abs() { case "$1" in /*) echo "$1" ;; *) echo "$here/$1" ;; esac; }

STEPS=(machine ray_cast_composite accuracy charts raster raster_study cones shadow_map shadows mc_study mc_topology
       volume volume_study ray_trace ray_trace_study ray_trace_depth embree_raw oneshot oneshot_pages radiosity radiosity_study page)
# Results no step writes (the page shows them as committed).
KEPT=(composite_accuracy.json llvmpipe_warm.json mc_bench.json raster_deep.json ray_cast_known.json
      volpack_agreement.json volpack_peer.json ray_trace_packets.json)

quick=0 build=$ROOT/build do_build=1 only="" out="" extra=()
while (($#)); do
  case "$1" in
    --quick) quick=1; if [[ ${2:-} && ${2:0:1} != - ]]; then out=$(abs "$2"); shift; fi ;;
    --only) only=${2:?--only needs STEP[,STEP...]}; shift ;;
    --build) build=$(abs "${2:?--build needs DIR}"); shift ;;
    --no-build) do_build=0 ;;
    --list) printf '%s\n' "${STEPS[@]}"; echo "kept as committed: ${KEPT[*]}"; exit 0 ;;
    --) shift; extra=("$@"); break ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "run.sh: unknown argument '$1' (--help)" >&2; exit 2 ;;
  esac
  shift
done
if [[ -n $only ]]; then
  for s in ${only//,/ }; do
    [[ " ${STEPS[*]} " == *" $s "* ]] || { echo "run.sh: no step '$s' (known: ${STEPS[*]})" >&2; exit 2; }
  done
fi

if ((quick)); then
  out=${out:-$(mktemp -d -t lockstep-rerun-XXXXXX)}
  R=$out/results C=$out/charts PAGE=$out/BENCHMARKS.md
  [[ -z $only ]] && rm -rf "$R" "$C"  # a whole quick run starts afresh; --only adds to it
  mkdir -p "$R" "$C"
  for f in "${KEPT[@]}"; do cp bench/results/"$f" "$R"/; done
  gb=(--benchmark_out_format=json --benchmark_min_time=0.001 --benchmark_repetitions=1)
else
  R=$ROOT/bench/results C=$ROOT/bench/charts PAGE=$ROOT/BENCHMARKS.md
  mkdir -p "$R" "$C"
  gb=(--benchmark_out_format=json --benchmark_min_time=0.3 --benchmark_repetitions=3
      --benchmark_report_aggregates_only=true)
fi
B=$build/bench
L=$build/lockstep
SPD=${LOCKSTEP_SPD_DIR:-$ROOT/../shared/spd}
VOLS=${LOCKSTEP_VOLUMES_DIR:-$ROOT/../shared/volumes}
PY=python3
LOG=$(mktemp -d -t lockstep-rerun-log-XXXXXX)
trap 'rm -rf "$LOG"' EXIT

if ((do_build)); then
  echo "== build ($build)"
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  ninja -C "$build" lockstep lockstep_bench lockstep_props lockstep_raster_study lockstep_cones_study \
    lockstep_shadow_study lockstep_mc_study lockstep_radiosity_study lockstep_volume_study lockstep_ray_trace_study lockstep_ray_trace_depth \
    lockstep_embree_raw >/dev/null
fi

bench() {  # lockstep_bench FILTER OUT.json [ARGS...]
  local filter=$1 json=$2
  shift 2
  "$B"/lockstep_bench --benchmark_filter="$filter" --benchmark_out="$json" "${gb[@]}" "$@" "${extra[@]}" >/dev/null
}
made() { printf '%s\n' "$@" >> "$LOG"/made; }     # the step's outputs, checked after it
note() { echo "$*" >> "$LOG"/notes; }
skip() { echo "$*" > "$LOG"/skipped; return 100; }
need_spd() { for s in "$@"; do [[ -f $SPD/$s.nff ]] || skip "needs $SPD/$s.nff (../shared/spd)"; done; }

# ---------------------------------------------------------------- the steps
# Each writes into $R (results) and $C (charts) and names the files it made (made).

step_machine() {
  { lscpu | grep -E '^Model name' | sed 's/  */ /g'; echo "cores: $(nproc), $(free -g | awk '/Mem:/{print $2}') GiB"
    "$L" --version; } > "$R"/machine.txt
  made "$R"/machine.txt
}

step_ray_cast_composite() {  # ray casting and compositing: frames, kernels, throughput
  local f='^(frame/ray_cast/|frame/composite/|kernel/|throughput/)'
  ((quick)) && f='^(frame/ray_cast/balls-1/(simd|embree|auto)/threads:1/|frame/composite/2-layers/simd/threads:1/|kernel/ray_sphere/|throughput/spheres/)'
  bench "$f" "$R"/latest.json
  made "$R"/latest.json
}

step_accuracy() {  # accuracy against the oracle and where each method breaks (props)
  rm -f "$R"/accuracy.csv "$R"/stability.csv
  local deep=1 acc='*Accuracy*' stab='Stability*:Watertight*:Degenerate*'
  if ((quick)); then deep=0 acc='*Accuracy*ray_sphere*' stab='Stability*ray_sphere*'; fi
  # Exit 1 is a property that failed: the CSV still holds what was measured.
  LOCKSTEP_NO_SAVE=1 LOCKSTEP_ACCURACY_CSV="$R"/accuracy.csv "$build"/props/lockstep_props --gtest_filter="$acc" \
    >/dev/null || true
  LOCKSTEP_NO_SAVE=1 LOCKSTEP_DEEP=$deep LOCKSTEP_STABILITY_CSV="$R"/stability.csv \
    "$build"/props/lockstep_props --gtest_filter="$stab" >/dev/null || true
  made "$R"/accuracy.csv "$R"/stability.csv
}

step_charts() {  # scaling, accuracy and composite charts, the tables of tables.md
  LOCKSTEP_STABILITY_CSV="$R"/stability.csv $PY bench/scripts/charts.py "$R"/latest.json "$R"/accuracy.csv "$C" \
    > "$R"/tables.md
  made "$R"/tables.md "$C"/scaling.png "$C"/accuracy.png "$C"/composite.png
}

step_raster() {  # the raster families' 1024^2 frames; llvmpipe in a process per thread count
  local f='^frame/(zbuffer|scanline|painter)/.*/(reference|simd)/' scenes='.*'
  ((quick)) && f='^frame/(zbuffer|scanline|painter)/tetra-3/flat/(reference|simd)/threads:1/' scenes='tetra-3'
  bench "$f" "$R"/raster_own.json
  rm -f "$R"/raster_llvmpipe_*.json
  if "$L" --version | grep -q 'llvmpipe row: built'; then
    for t in 1 2; do
      ((quick)) && [[ $t == 2 ]] && continue
      bench "^frame/zbuffer/$scenes/flat/llvmpipe/threads:$t/" "$R"/raster_llvmpipe_$t.json
    done
  else
    note "no llvmpipe row built: raster.json without it"
  fi
  $PY - "$R" <<'EOF'
import glob, json, sys
r = sys.argv[1]
parts = [json.load(open(p)) for p in [f"{r}/raster_own.json"] + sorted(glob.glob(f"{r}/raster_llvmpipe_*.json"))]
out = parts[0]
for p in parts[1:]:
    out["benchmarks"] += p["benchmarks"]
json.dump(out, open(f"{r}/raster.json", "w"), indent=1)
EOF
  made "$R"/raster_own.json "$R"/raster.json
}

step_raster_study() {  # speed against accuracy and the failure maps of the raster families
  "$B"/lockstep_raster_study all $( ((quick)) && echo --quick) > "$R"/raster_study.csv
  $PY bench/scripts/raster_charts.py "$R"/raster_study.csv "$R"/raster.json "$C" > "$R"/raster_tables.md
  made "$R"/raster_study.csv "$R"/raster_tables.md "$C"/raster_tessellation.png "$C"/raster_painter.png
}

step_cones() {  # NFF cones tessellated against exact
  "$B"/lockstep_cones_study $( ((quick)) && echo --quick) > "$R"/cones_tess.csv
  $PY bench/scripts/cones_chart.py "$R"/cones_tess.csv "$C" "$R"/cones_tess.json > /dev/null
  made "$R"/cones_tess.csv "$R"/cones_tess.json "$C"/cones_tess.png
}

step_shadow_map() {  # shadow maps' failure map
  "$B"/lockstep_shadow_study $( ((quick)) && echo --quick) > "$R"/shadow_map.csv
  $PY bench/scripts/shadow_map_chart.py "$R"/shadow_map.csv "$C" "$R"/shadow_map.json > /dev/null
  made "$R"/shadow_map.csv "$R"/shadow_map.json "$C"/shadow_map.png
}

step_shadows() {  # the z-buffer's shadowed frames
  local f='^frame/zbuffer/.*-shadows-'
  ((quick)) && f='^frame/zbuffer/teapot-2/phong-shadows-map/(reference|simd)/threads:1/'
  bench "$f" "$R"/shadows_bench.json
  $PY bench/scripts/shadows_bench_table.py "$R"/shadows_bench.json "$R"/shadows.json
  made "$R"/shadows_bench.json "$R"/shadows.json
}

step_mc_study() {  # marching cubes' speed against accuracy
  "$B"/lockstep_mc_study $( ((quick)) && echo --quick) > "$R"/mc_study.csv
  $PY bench/scripts/mc_chart.py "$R"/mc_study.csv "$C" > /dev/null
  made "$R"/mc_study.csv "$C"/mc_accuracy.png
}

step_mc_topology() {  # marching cubes' topology against scikit-image (Debian's python3-skimage)
  # Its smallest run is the ctest's (about 100 s of CPU): the quick rerun leaves it to that test.
  ((quick)) && skip "quick: the ctest topology.skimage runs tests/topology_skimage.py --quick"
  local rc=0
  /usr/bin/python3 tests/topology_skimage.py "$L" $( ((quick)) && echo --quick) > "$R"/mc_topology.txt || rc=$?
  ((rc == 77)) && skip "no scikit-image for /usr/bin/python3 (scripts/setup.sh installs python3-skimage)"
  ((rc == 0)) || return $rc
  made "$R"/mc_topology.txt
}

step_volume() {  # volume ray casting and the isosurface's frames (the real volumes of ../shared)
  [[ -f $VOLS/cthead.nhdr ]] || skip "needs $VOLS/cthead.nhdr (../shared/volumes)"
  local f='^frame/volume(_iso)?/'
  ((quick)) && f='^frame/volume_iso/cthead/bone/simd/threads:2/'
  bench "$f" "$R"/volume_bench.json
  made "$R"/volume_bench.json
}

step_volume_study() {  # volume: step (speed against accuracy) and cross (mesh against isosurface)
  local q=$( ((quick)) && echo --quick)
  "$B"/lockstep_volume_study step $q > "$R"/volume_step.csv
  "$B"/lockstep_volume_study cross $q > "$R"/volume_cross.csv
  $PY bench/scripts/volume_charts.py "$R"/volume_step.csv "$C" > /dev/null
  $PY bench/scripts/volume_charts.py "$R"/volume_cross.csv "$C" > /dev/null
  made "$R"/volume_step.csv "$R"/volume_cross.csv "$C"/volume_step.png "$C"/volume_cross.png
}

step_ray_trace() {  # ray tracing's frames: rays per second
  local f='^frame/ray_trace/' gbr=(--benchmark_min_time=0.2)
  ((quick)) && f='^frame/ray_trace/balls-3/depth1/(reference|embree)/threads:1/' gbr=()
  bench "$f" "$R"/ray_trace.json "${gbr[@]}"
  $PY bench/scripts/ray_trace_bench_table.py "$R"/ray_trace.json "$R"/ray_trace_rates.json
  made "$R"/ray_trace.json "$R"/ray_trace_rates.json
}

step_radiosity() {  # radiosity's Cornell box frames, reference and simd
  local f='^frame/radiosity/' gbr=(--benchmark_min_time=0.2)
  ((quick)) && f='^frame/radiosity/cornell-305-rays/(reference|simd)/threads:1/' gbr=()
  bench "$f" "$R"/radiosity.json "${gbr[@]}"
  $PY bench/scripts/radiosity_table.py "$R"/radiosity.json "$R"/radiosity_frames.json
  # One call of the CLI per frame, fresh processes: the one-shot cost beside the warm frame.
  $PY bench/scripts/radiosity_oneshot.py "$L" "$R"/radiosity.json "$R"/radiosity_oneshot.json $( ((quick)) && echo 1) > /dev/null
  made "$R"/radiosity.json "$R"/radiosity_frames.json "$R"/radiosity_oneshot.json
}

step_radiosity_study() {  # radiosity's form-factor error and solver residual against time
  "$B"/lockstep_radiosity_study $( ((quick)) && echo --quick) > "$R"/radiosity_study.csv
  $PY bench/scripts/radiosity_chart.py "$R"/radiosity_study.csv "$C" > /dev/null
  made "$R"/radiosity_study.csv "$C"/radiosity_form_factors.png "$C"/radiosity_solvers.png
}

step_ray_trace_study() {  # ray tracing's failure map: acne and leaks
  "$B"/lockstep_ray_trace_study $( ((quick)) && echo --quick) > "$R"/ray_trace_acne.csv
  $PY bench/scripts/ray_trace_chart.py "$R"/ray_trace_acne.csv "$C" "$R"/ray_trace_acne.json > /dev/null
  made "$R"/ray_trace_acne.csv "$R"/ray_trace_acne.json "$C"/ray_trace_acne.png
}

step_ray_trace_depth() {  # time and image error against the ray tree's depth
  local scenes=(balls-3 balls-4 balls-5 shells-1 tetra-3 mount-3 gears-2) args=()
  if ((quick)); then
    args=(--size 32 --reps 1 --max-depth 3 corpus/scenes/balls-1.nff)
  else
    need_spd "${scenes[@]}"
    for s in "${scenes[@]}"; do args+=("$SPD/$s.nff"); done
  fi
  "$B"/lockstep_ray_trace_depth "${args[@]}" > "$R"/ray_trace_depth.csv
  $PY bench/scripts/ray_trace_depth_chart.py "$R"/ray_trace_depth.csv "$C" "$R"/ray_trace_depth.json
  made "$R"/ray_trace_depth.csv "$R"/ray_trace_depth.json "$C"/ray_trace_depth.png
}

step_embree_raw() {  # the embree row against raw Embree: each scene in 3 fresh processes
  local scenes=(balls-1 balls-3 balls-5) runs=3 args=(--reps 7 --clock cpu) paths=()
  if ((quick)); then
    runs=1 args=(--size 32 --reps 1 --clock cpu) paths=(corpus/scenes/balls-1.nff)
  else
    need_spd "${scenes[@]}"
    for s in "${scenes[@]}"; do paths+=("$SPD/$s.nff"); done
  fi
  for _ in $(seq "$runs"); do
    for p in "${paths[@]}"; do "$B"/lockstep_embree_raw "${args[@]}" "$p"; done
  done > "$R"/embree_raw.csv
  $PY bench/scripts/embree_raw_table.py "$R"/embree_raw.csv "$R"/embree_raw.json
  made "$R"/embree_raw.csv "$R"/embree_raw.json
}

step_oneshot() {  # what one call of each subcommand costs (bench/scripts/oneshot.sh)
  [[ -f $SPD/sombrero-2.nff && -f $VOLS/cthead.nhdr ]] || skip "needs $SPD/sombrero-2.nff and $VOLS/cthead.nhdr (../shared)"
  for t in /usr/bin/time strace idiff; do command -v $t >/dev/null || skip "needs $t"; done
  local runs=7 min_time=0.2
  ((quick)) && runs=1 min_time=0.001
  ONESHOT_BUILD=$build ONESHOT_MIN_TIME=$min_time ONESHOT_QUICK=$quick bash bench/scripts/oneshot.sh $runs "$R"/oneshot.json
  made "$R"/oneshot.json
}

step_oneshot_pages() {  # one-shot against warm, huge pages against 4 KiB pages (bench/scripts/oneshot_pages.py)
  /usr/bin/python3 -c 'import numpy' 2>/dev/null || skip "needs numpy for /usr/bin/python3 (python3-numpy)"
  command -v /usr/bin/time >/dev/null || skip "needs /usr/bin/time"
  /usr/bin/python3 bench/scripts/oneshot_pages.py --build "$build" --out "$R"/oneshot_pages.json $( ((quick)) && echo --quick)
  made "$R"/oneshot_pages.json
}

step_page() {  # BENCHMARKS.md from the results (bench/scripts/benchmarks_md.py)
  $PY bench/scripts/benchmarks_md.py --results "$R" --out "$PAGE" $( ((quick)) && echo --partial)
  made "$PAGE"
}

# ---------------------------------------------------------------- run them
failed=() skipped=() n=0
total=${#STEPS[@]}
[[ -n $only ]] && total=$(wc -w <<<"${only//,/ }")
echo "== lockstep bench rerun ($( ((quick)) && echo "quick, into $out" || echo "full, into bench/results, bench/charts and BENCHMARKS.md"))"
for step in "${STEPS[@]}"; do
  [[ -n $only && ",$only," != *",$step,"* ]] && continue
  n=$((n + 1))
  echo "[$n/$total] $step"
  t0=$SECONDS
  rm -f "$LOG"/made "$LOG"/notes "$LOG"/skipped
  set +e
  ( set -euo pipefail; "step_$step" ) > "$LOG"/out 2>&1
  rc=$?
  set -e
  [[ -f $LOG/notes ]] && sed 's/^/   /' "$LOG"/notes
  if ((rc == 100)) && [[ -f $LOG/skipped ]]; then
    echo "   skipped: $(cat "$LOG"/skipped)"
    skipped+=("$step: $(cat "$LOG"/skipped)")
    continue
  fi
  missing=()
  if ((rc == 0)); then
    while read -r f; do [[ -s $f ]] || missing+=("${f#"$ROOT"/}"); done < <(cat "$LOG"/made 2>/dev/null)
    [[ -f $LOG/made ]] || missing+=("(the step named no output)")
  fi
  if ((rc != 0 || ${#missing[@]})); then
    ((rc != 0)) && echo "   FAILED (exit $rc):" || echo "   FAILED: did not write ${missing[*]}"
    tail -20 "$LOG"/out | sed 's/^/     /'
    failed+=("$step")
  else
    echo "   ok ($((SECONDS - t0)) s): $(sed "s|^$ROOT/||" "$LOG"/made | tr '\n' ' ')"
  fi
done
echo "== $n steps: $((n - ${#failed[@]} - ${#skipped[@]})) ran, ${#skipped[@]} skipped, ${#failed[@]} failed${failed:+ (${failed[*]})}"
for s in "${skipped[@]}"; do echo "   skipped $s"; done
((${#failed[@]} == 0))
