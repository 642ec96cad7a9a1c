#!/usr/bin/env bash
# Runs each libFuzzer harness in turn (one at a time, niced) for SECONDS, with its dictionary and
# seeds, and prints its execution count. Usage: tests/fuzz/run.sh BUILD_DIR SECONDS [HARNESS...]
# (BUILD_DIR configured with -DCMAKE_CXX_COMPILER=clang++ -DSIMREEL_FUZZ=ON; default: all six).
# Findings land in BUILD_DIR/tests/fuzz/artifacts/; the run stops at the first.
set -uo pipefail
src="$(cd "$(dirname "$0")/../.." && pwd)"
build="$(cd "$1" && pwd)"
secs="$2"
shift 2
harnesses=("$@")
[ ${#harnesses[@]} -eq 0 ] && harnesses=(scene obj ply off stl mass)
out="$build/tests/fuzz"
for h in "${harnesses[@]}"; do
  case "$h" in
    scene) dict=yaml.dict; seeds=("$src/scenes") ;;
    obj | off | stl) dict=$h.dict; seeds=("$src/assets" "$src/tests/data/hostile") ;;
    ply) dict=ply.dict; seeds=("$src/tests/fuzz/seeds/ply" "$src/tests/data/hostile") ;;
    mass) dict=""; seeds=("$src/tests/fuzz/seeds/mass") ;;
    *) echo "unknown harness $h" >&2; exit 2 ;;
  esac
  mkdir -p "$out/corpus/$h" "$out/artifacts" "$out/logs"
  log="$out/logs/$h-$(date +%Y%m%d-%H%M%S).log"
  (cd "$out" && nice "$out/fuzz_$h" -max_total_time="$secs" -rss_limit_mb=2048 -timeout=10 -max_len=8192 -print_final_stats=1 \
     -artifact_prefix="$out/artifacts/$h-" ${dict:+-dict="$src/tests/fuzz/$dict"} \
     "$out/corpus/$h" "${seeds[@]}" >"$log" 2>&1)
  rc=$?
  n=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$')
  echo "$h: exit $rc, ${n:-?} executions in $secs s ($log)"
  [ $rc -eq 0 ] || exit $rc
done
