#!/usr/bin/env bash
# The whole test suite from a fresh clone (CI runs exactly this):
#   1. installs what is missing (Debian packages with Blender, CGAL's sample meshes, the glTF
#      validator);
#   2. builds the dev preset (warnings as errors) and runs every CTest test;
#   3. builds the asan preset and runs every test again under AddressSanitizer + UBSan;
#   4. runs each libFuzzer target a fixed number of times (SWEEP_FUZZ_RUNS, default 300000; fixed
#      seed, so the same on every machine) on its committed corpus.
# SWEEP_TESTS_QUICK=1 stops after step 2 (for a quick local check).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
tools/setup-deps.sh --tests
jobs=$(nproc)
start=$SECONDS
stage() { echo; echo "== $1 ($((SECONDS - start)) s so far)"; }

stage "dev build and test suite"
cmake --preset dev >/dev/null
cmake --build --preset dev -j "$jobs"
ctest --preset dev -j "$jobs"
if [ "${SWEEP_TESTS_QUICK:-0}" = 1 ]; then
  echo "1 passed, 0 failed (quick: dev suite only)"
  exit 0
fi

stage "the same suite under AddressSanitizer + UndefinedBehaviorSanitizer"
tools/run-sanitizers.sh

stage "fuzzing every parser, ${SWEEP_FUZZ_RUNS:-300000} runs each"
tools/run-fuzz.sh --runs "${SWEEP_FUZZ_RUNS:-300000}"

stage "done"
echo "stages (dev suite, sanitizer suite, fuzzing): 3 passed, 0 failed"
