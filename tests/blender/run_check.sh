#!/bin/sh
# CTest driver for check_bake.py: bakes the bent-tube example (rigs/tube-bent.rig.json, its own scene
# at 24 fps and the same scene at 30 fps) to .glb and .pc2 and has Blender play both.
#   run_check.sh SOURCE_DIR WORK_DIR SWEEP_BIND SWEEP_SIM
# Exits 77 (CTest: skipped) when Blender is not installed; tools/setup-deps.sh installs it.
set -eu
src=$1 work=$2 bind=$3 sim=$4
if ! command -v blender >/dev/null 2>&1; then
  echo "blender is not installed (Debian package blender; tools/setup-deps.sh --tests installs it): skipped"
  exit 77
fi
command -v python3 >/dev/null 2>&1 || { echo "python3 is missing (tools/setup-deps.sh)"; exit 1; }
rig=$src/rigs/tube-bent.rig.json
rm -rf "$work" && mkdir -p "$work"
"$bind" -q "$rig" -o "$work/tube.bind"
python3 -c 'import json, sys; s = {"format": "sweep-scene", "version": 1, **json.load(open(sys.argv[1]))["scene"], "fps": 30}; json.dump(s, open(sys.argv[2], "w"))' \
  "$rig" "$work/scene-30fps.json"
status=0
for fps in 24 30; do
  if [ "$fps" = 24 ]; then
    "$sim" -q "$rig" -b "$work/tube.bind" -o "$work/tube-$fps.glb" -o "$work/tube-$fps.pc2"
  else
    "$sim" -q "$rig" -b "$work/tube.bind" --scene "$work/scene-30fps.json" \
      -o "$work/tube-$fps.glb" -o "$work/tube-$fps.pc2"
  fi
  echo "== $fps fps"
  if blender -b --factory-startup --python-exit-code 1 --python "$src/tests/blender/check_bake.py" -- \
    "$src/meshes/tube_bent.obj" "$work/tube-$fps.glb" "$work/tube-$fps.pc2" "$fps" >"$work/blender-$fps.log" 2>&1; then
    grep -E '^(ok|FAIL|blender check)' "$work/blender-$fps.log" || cat "$work/blender-$fps.log"
  else
    cat "$work/blender-$fps.log"
    status=1
  fi
done
exit $status
