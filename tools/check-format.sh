#!/usr/bin/env bash
# The C++ sources are formatted as .clang-format says (clang-format 14, Debian 12's): prints each
# file that differs and exits 1, or prints one line and exits 0. Apply with
#   git ls-files '*.cpp' '*.h' | xargs clang-format -i
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
command -v clang-format >/dev/null || { echo "check-format: clang-format is not installed (tools/setup-deps.sh installs it)" >&2; exit 1; }
report=$(git ls-files -z '*.cpp' '*.h' | xargs -0 clang-format --style=file --dry-run 2>&1 || true)
if [ -n "$report" ]; then
  grep -oE '^[^:]+:[0-9]+' <<<"$report" | sort -u -t: -k1,1 | sed 's/$/: not formatted as .clang-format says (first line that differs)/'
  echo "check-format: apply with: git ls-files '*.cpp' '*.h' | xargs clang-format -i"
  exit 1
fi
echo "check-format: ok ($(git ls-files '*.cpp' '*.h' | wc -l) files, $(clang-format --version | grep -o 'version [0-9.]*'))"
