#!/usr/bin/env bash
# Runs every libFuzzer target (tests/fuzz/) for a bounded time: tools/run-fuzz.sh [seconds-per-target]
# (default 60). The mutation seed is SWEEP_FUZZ_SEED (default 1, so that a run is repeatable and a
# red CI reproduces here; SWEEP_FUZZ_SEED=0 lets libFuzzer pick one, for exploring). Configures its own clang build (build/fuzz: SWEEP_FUZZ=ON, which instruments the
# library for coverage under ASan+UBSan), builds only the fuzz targets, and runs each on a scratch
# copy of its committed seed corpus (tests/fuzz/corpus/<target>/; new inputs it finds stay in the
# scratch copy). Any crash, leak, sanitizer report or timeout fails the script; the input that did
# it is copied to tests/fuzz/regressions/<target>/ so that it can be fixed and kept (those files
# are replayed by test_fuzz_regressions in the regular suite). Prints each target's executions.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
seconds=${1:-60}
seed=${SWEEP_FUZZ_SEED:-1}
build=${SWEEP_FUZZ_BUILD_DIR:-build/fuzz}
jobs=${SWEEP_JOBS:-2}
targets=(rig_json scene binding off_mesh obj_mesh ply_mesh fit_off)

CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSWEEP_FUZZ=ON -DSWEEP_WERROR=ON -DSWEEP_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target "${targets[@]/#/fuzz_}"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failed=()
for t in "${targets[@]}"; do
  mkdir -p "$work/$t/corpus" "$work/$t/artifacts"
  cp tests/fuzz/corpus/"$t"/* "$work/$t/corpus/"
  echo "== fuzz_$t: $seconds s"
  dict=()
  if [ -f tests/fuzz/"$t".dict ]; then dict=(-dict=tests/fuzz/"$t".dict); fi
  set +e
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    "$build/tests/fuzz/fuzz_$t" "$work/$t/corpus" -max_total_time="$seconds" -timeout=10 -seed="$seed" \
    -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 "${dict[@]}" \
    -artifact_prefix="$work/$t/artifacts/" >"$work/$t/log" 2>&1
  status=$?
  set -e
  grep -E '^stat::number_of_executed_units|^Done [0-9]+ runs' "$work/$t/log" | tail -1 || true
  if [ $status -ne 0 ]; then
    failed+=("$t")
    mkdir -p tests/fuzz/regressions/"$t"
    cp "$work/$t/artifacts/"* tests/fuzz/regressions/"$t"/ 2>/dev/null || true
    grep -E 'ERROR|SUMMARY|==[0-9]+==|terminate|what\(\)' "$work/$t/log" | head -20
    echo "fuzz_$t FAILED (exit $status); input kept in tests/fuzz/regressions/$t/"
  fi
done
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzzing found crashes in: ${failed[*]}"
  exit 1
fi
echo "fuzzing: no crashes in ${#targets[@]} targets x $seconds s"
