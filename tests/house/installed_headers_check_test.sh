#!/usr/bin/env bash
# tools/check-installed-headers.sh fails where it must: on a copy of the installed modules'
# headers, each of these lines added to an installed header in turn must make it fail, and the
# copy unchanged must pass. Usage: installed_headers_check_test.sh SOURCE_DIR
set -euo pipefail
src=$(cd "$1" && pwd)
work=$(mktemp -d "${TMPDIR:-/tmp}/sweep-headers-check.XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/cmake" "$work/lib/capi/include/sweep" "$work/tools"
cp "$src/cmake/SweepInstall.cmake" "$work/cmake/"
cp "$src/tools/check-installed-headers.sh" "$work/tools/"
cp "$src/lib/capi/include/sweep/sweep.h" "$work/lib/capi/include/sweep/"
for m in core bind sim io; do mkdir -p "$work/lib/$m" && cp "$src/lib/$m/"*.h "$work/lib/$m/"; done
check() { bash "$work/tools/check-installed-headers.sh" "$work" > "$work/out.txt" 2>&1; }
check || { cat "$work/out.txt"; echo "FAILED: the unchanged headers are refused"; exit 1; }
# An internal header, a tool's (as an authoring module's: not installed), an authoring library.
for bad in '#include "sweep/core/contact_rows_detail.h"' '#include "tools/common/tool_main.h"' '#include <tiny_gltf.h>'; do
  cp "$src/lib/sim/scene.h" "$work/lib/sim/scene.h"
  printf '%s\n' "$bad" >> "$work/lib/sim/scene.h"
  if check; then echo "FAILED: sim/scene.h with $bad passes"; exit 1; fi
  grep -qF "lib/sim/scene.h" "$work/out.txt" || { cat "$work/out.txt"; echo "FAILED: no line names the header"; exit 1; }
done
echo "ok: the check refuses an internal, authoring or tool include in an installed header"
