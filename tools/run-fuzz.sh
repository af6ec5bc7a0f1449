#!/usr/bin/env bash
# Runs every libFuzzer target (tests/fuzz/) on its committed corpus, in one of two ways:
#   tools/run-fuzz.sh --runs N     N executions per parser target (a fit target gets N/40: one fit
#                                  costs about as much as 40 parses; gltf N/6 and material N/4, by
#                                  CPU time a run: 1.48 ms and 0.22 ms, scene's 0.22 ms),
#                                  seed SWEEP_FUZZ_SEED (default 1). The same binary then does the
#                                  same work on any machine, so a red CI reproduces here and a
#                                  green run here stays green in CI.
#                                  This is what the test suite runs.
#   tools/run-fuzz.sh [SECONDS]    SECONDS per target (default 60), for exploring; bounded by time,
#                                  so two runs differ. SWEEP_FUZZ_SEED=0 also lets libFuzzer pick a seed.
# SWEEP_FUZZ_TARGETS="gltf material" runs only those targets.
# Builds the fuzz targets in the asan preset's build (build/asan: clang, ASan+UBSan, the libraries
# at -O1 with libFuzzer's coverage instrumentation; the sanitized test suite runs in the same build,
# so the libraries are compiled once for both), and runs each on a scratch copy of its committed seed corpus
# (tests/fuzz/corpus/<target>/; new inputs it finds stay in the scratch copy). Any crash, leak, sanitizer report or timeout fails the script; the input that did it is
# copied to tests/fuzz/regressions/<target>/ so that it can be fixed and kept (those files are
# replayed by the Fuzz/Replay tests of the regular suite). Prints each target's executions.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
runs=""
seconds=60
if [ "${1:-}" = --runs ]; then
  runs=${2:?--runs needs a count}
elif [ -n "${1:-}" ]; then
  seconds=$1
fi
seed=${SWEEP_FUZZ_SEED:-1}
build=build/asan
jobs=${SWEEP_JOBS:-2}
# Longest first, so that two at a time finish together (gltf ~52 s, scene 23, fit_off 20, rig_json 17 at -O1).
targets=(gltf scene fit_off rig_json material binding off_mesh obj_mesh ply_mesh)
if [ -n "${SWEEP_FUZZ_TARGETS:-}" ]; then read -r -a targets <<<"$SWEEP_FUZZ_TARGETS"; fi

cmake --preset asan >/dev/null
built_at=$SECONDS
cmake --build --preset asan -j "$jobs" --target "${targets[@]/#/fuzz_}"
echo "fuzz targets built in $((SECONDS - built_at)) s"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# One target's run, its report kept in $work/$t/ (log, result, artifacts) for the summary below.
run_target() {
  local t=$1 budget label dict=() target_start=$SECONDS status
  mkdir -p "$work/$t/corpus" "$work/$t/artifacts"
  cp tests/fuzz/corpus/"$t"/* "$work/$t/corpus/"
  if [ -n "$runs" ]; then
    case "$t" in
      fit_off) budget=(-runs=$((runs / 40))) ;;
      gltf) budget=(-runs=$((runs / 6))) ;;
      material) budget=(-runs=$((runs / 4))) ;;
      *) budget=(-runs="$runs") ;;
    esac
    label="${budget[0]#-runs=} runs"
  else
    budget=(-max_total_time="$seconds")
    label="$seconds s"
  fi
  if [ -f tests/fuzz/"$t".dict ]; then dict=(-dict=tests/fuzz/"$t".dict); fi
  set +e
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    "$build/tests/fuzz/fuzz_$t" "$work/$t/corpus" "${budget[@]}" -timeout=10 -seed="$seed" \
    -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 "${dict[@]}" \
    -artifact_prefix="$work/$t/artifacts/" >"$work/$t/log" 2>&1
  status=$?
  set -e
  {
    echo "== fuzz_$t: $label"
    grep -E '^stat::number_of_executed_units|^Done [0-9]+ runs' "$work/$t/log" | tail -1 || true
    echo "fuzz_$t: $((SECONDS - target_start)) s"
  } >"$work/$t/result"
  echo "$status" >"$work/$t/status"
}

# The targets run $jobs at a time (each is one process on one core; the runs are fixed, so running
# them side by side changes no result, only the wall time: 146 s one after another on 2 cores).
running=0
for t in "${targets[@]}"; do
  if [ "$running" -ge "$jobs" ]; then
    wait -n
    running=$((running - 1))
  fi
  run_target "$t" &
  running=$((running + 1))
done
wait

failed=()
for t in "${targets[@]}"; do
  cat "$work/$t/result"
  status=$(cat "$work/$t/status")
  if [ "$status" -ne 0 ]; then
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
if [ -n "$runs" ]; then budget_text="$runs runs"; else budget_text="$seconds s"; fi
echo "fuzzing: no crashes in ${#targets[@]} targets ($budget_text each, seed $seed)"
