#!/usr/bin/env bash
# The whole test suite from a fresh clone (CI runs exactly this):
#   1. installs what is missing (Debian packages with Blender, CGAL's sample meshes, the glTF
#      validator);
#   2. builds the dev preset (warnings as errors) and runs every CTest test;
#   3. builds the asan preset and runs every test again under AddressSanitizer + UBSan;
#   4. runs each libFuzzer target for a bounded time on its committed corpus.
# SWEEP_TESTS_QUICK=1 stops after step 2 (for a quick local check); SWEEP_FUZZ_SECONDS sets step 4's
# time per target (default 60).
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

stage "fuzzing every parser for ${SWEEP_FUZZ_SECONDS:-60} s each"
tools/run-fuzz.sh "${SWEEP_FUZZ_SECONDS:-60}"

stage "done"
echo "stages (dev suite, sanitizer suite, fuzzing): 3 passed, 0 failed"
