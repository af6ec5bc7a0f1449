#!/usr/bin/env bash
# The layers of lib/ (README, "Layout"), checked on the sources: a module includes only modules
# below it, and the runtime modules (core, bind, sim, io) include no authoring library. Prints every
# offending line and exits 1, or prints one line and exits 0. The link side (the installed runtime
# links no authoring library) is tools/check-runtime.sh.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

# module: the modules it may include (itself included).
declare -A allowed=(
  [core]="core"
  [bind]="core bind"
  [sim]="core bind sim"
  [io]="core bind sim io"
  [capi]="core bind sim io capi"
  [assets]="core bind sim io fit assets"
  [fit]="core fit"
  [preview]="core preview"
)
runtime="core bind sim io capi"
# Headers of the authoring libraries a runtime module must never see.
authoring='^#include <(assimp/|tiny_gltf|tiny_obj_loader|CGAL/|boost/|png\.h|gmp|mpfr)'

bad=0
for module in "${!allowed[@]}"; do
  [[ -d lib/$module ]] || { echo "check-layers: lib/$module is missing" >&2; bad=1; continue; }
  while IFS= read -r hit; do
    file=${hit%%:*}; rest=${hit#*:}; line=${rest%%:*}; text=${rest#*:}
    target=$(sed -E 's/^#include "sweep\/([a-z_]+)\/.*/\1/' <<<"$text")
    [[ $target == "$text" ]] && continue  # an include without a module folder
    [[ -d lib/$target ]] || continue      # not one of ours (e.g. "tube.h" beside a tool)
    if [[ " ${allowed[$module]} " != *" $target "* ]]; then
      echo "$file:$line: lib/$module includes lib/$target, which it may not depend on: $text"
      bad=1
    fi
  done < <(grep -Hn '^#include "' lib/"$module"/*.{h,cpp} 2>/dev/null || true)
  if [[ " $runtime " == *" $module "* ]]; then
    while IFS= read -r hit; do
      echo "$hit: a runtime module includes an authoring library"
      bad=1
    done < <(grep -HnE "$authoring" lib/"$module"/*.{h,cpp} 2>/dev/null || true)
    cml=lib/$module/CMakeLists.txt
    if grep -nE 'assimp|TinyGLTF|tinyobjloader|CGAL|PNG::|sweep_(assets|fit|preview)' "$cml" | grep -vE '^[0-9]+:\s*#'; then
      echo "$cml: a runtime module links an authoring library (lines above)"
      bad=1
    fi
  fi
done
if ((bad)); then
  echo "check-layers: FAILED (README, \"Layout\": the layers and why)" >&2
  exit 1
fi
echo "check-layers: ok (core < bind < sim < io make the runtime; assets, fit, preview above)"
