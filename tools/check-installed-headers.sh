#!/usr/bin/env bash
# The headers `cmake --install` gives a game stand on their own as a set: every header of the
# runtime's modules (cmake/SweepInstall.cmake: SWEEP_RUNTIME_MODULES, less the internal *_detail.h)
# and libsweep's sweep/sweep.h includes only installed headers of the project, the standard
# library, Eigen and nlohmann-json — never an internal header, an authoring module (assets, fit,
# preview), a tool's code or an authoring library. Prints every offending line and exits 1, or
# prints one line and exits 0.
# Usage: tools/check-installed-headers.sh [SOURCE_DIR]   (default: this checkout)
set -euo pipefail
cd "${1:-$(dirname "${BASH_SOURCE[0]}")/..}"

rules=cmake/SweepInstall.cmake
modules=$(sed -nE 's/^set\(SWEEP_RUNTIME_MODULES (.*)\)$/\1/p' "$rules")
[[ -n $modules ]] || { echo "check-installed-headers: no SWEEP_RUNTIME_MODULES in $rules" >&2; exit 1; }
grep -q 'PATTERN "\*_detail.h" EXCLUDE' "$rules" ||
  { echo "check-installed-headers: $rules no longer leaves out *_detail.h: update this check" >&2; exit 1; }

# The installed headers, as a game includes them ("sweep/core/rig.h").
declare -A installed=([sweep/sweep.h]=lib/capi/include/sweep/sweep.h)
for module in $modules; do
  for file in lib/"$module"/*.h; do
    [[ $file == *_detail.h ]] && continue
    installed[sweep/$module/$(basename "$file")]=$file
  done
done

# Each installed file's name as a game includes it.
declare -A name_of=()
for name in "${!installed[@]}"; do name_of[${installed[$name]}]=$name; done

quoted='^[[:space:]]*#[[:space:]]*include[[:space:]]*"([^"]+)"'
angled='^[[:space:]]*#[[:space:]]*include[[:space:]]*<([^>]+)>'
bad=0
while IFS= read -r hit; do
  file=${hit%%:*}; rest=${hit#*:}; line=${rest%%:*}; text=${rest#*:}
  if [[ $text =~ $quoted ]]; then
    target=${BASH_REMATCH[1]}
    [[ -n ${installed[$target]+x} ]] && continue
    echo "$file:$line: includes \"$target\", which is not installed: $text"
    bad=1
  elif [[ $text =~ $angled ]]; then
    target=${BASH_REMATCH[1]}
    # The C++ standard library (no folder, no extension), the C headers sweep.h needs, Eigen,
    # nlohmann-json: what the runtime links. Not an authoring library (<tiny_gltf.h>, <png.h>).
    [[ ($target != */* && $target != *.*) || $target =~ ^std(def|int|bool)\.h$ ]] && continue
    [[ $target == Eigen/* || $target == nlohmann/* ]] && continue
    echo "$file:$line: includes <$target>, not the standard library, Eigen or nlohmann-json: $text"
    bad=1
  fi
done < <(grep -Hn '^[[:space:]]*#[[:space:]]*include' "${!name_of[@]}")
if ((bad)); then
  echo "check-installed-headers: FAILED (an installed header must build from the installed ones alone)" >&2
  exit 1
fi
echo "check-installed-headers: ok (${#installed[@]} installed headers include only installed ones, std, Eigen, nlohmann-json)"
