#!/usr/bin/env bash
# The whole test suite from a fresh clone: installs what is missing (Debian packages, CGAL's sample
# meshes, the glTF validator), builds the developer preset with warnings as errors, runs CTest.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
tools/setup-deps.sh
jobs=$(nproc)
cmake --preset dev >/dev/null
cmake --build --preset dev -j "$jobs"
ctest --preset dev -j "$jobs"
