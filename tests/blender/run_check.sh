#!/bin/sh
# CTest driver for check_bake.py: bakes the bent-tube example (rigs/tube-bent.rig.json, its own scene
# at 24 fps, the same scene at 30 fps, and at 30 fps on a body that walks and turns) to .glb and
# .pc2 and has Blender play both (the moving body: world positions in the .pc2, the node's animation
# in the .glb).
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
python3 -c 'import json, sys; s = json.load(open(sys.argv[1])); s["body"] = {"interpolation": "cubic", "keys": [
  {"time": 0, "translation": [0, 0, 0]}, {"time": 0.8, "translation": [0.15, 0.05, 0], "turn_degrees": 10},
  {"time": 1.6, "translation": [0.25, 0.05, 0.1], "turn_degrees": 20, "turn_axis": [0, 0.3, 1]}]}; json.dump(s, open(sys.argv[2], "w"))' \
  "$work/scene-30fps.json" "$work/scene-moving.json"
status=0
for run in 24 30 moving; do
  fps=$run
  case $run in
    24) "$sim" -q "$rig" -b "$work/tube.bind" -o "$work/tube-$run.glb" -o "$work/tube-$run.pc2" ;;
    30) "$sim" -q "$rig" -b "$work/tube.bind" --scene "$work/scene-30fps.json" \
          -o "$work/tube-$run.glb" -o "$work/tube-$run.pc2" ;;
    moving) fps=30
      "$sim" -q "$rig" -b "$work/tube.bind" --scene "$work/scene-moving.json" \
        -o "$work/tube-$run.glb" -o "$work/tube-$run.pc2" ;;
  esac
  echo "== $run ($fps fps)"
  if blender -b --factory-startup --python-exit-code 1 --python "$src/tests/blender/check_bake.py" -- \
    "$src/meshes/tube_bent.obj" "$work/tube-$run.glb" "$work/tube-$run.pc2" "$fps" >"$work/blender-$run.log" 2>&1; then
    grep -E '^(ok|FAIL|blender check)' "$work/blender-$run.log" || cat "$work/blender-$run.log"
  else
    cat "$work/blender-$run.log"
    status=1
  fi
done
# The skinned bake (--joints): Blender's importer builds an armature, and its evaluated mesh must
# match the .pc2 within the error sweep-sim reported (skin_error_max_relative × the part's length).
# Layouts: N×1 (station joints alone, scaled in-plane), N×M with ring joints (children of their
# station joint, keyed by scale; "fit": --ring-fit, every ring joint keyed) and --joints alone (the
# defaults).
for layout in 4x1 12x1 6x8fit default; do
  case $layout in
    default) args="--joints" ;;
    *fit) m=${layout#*x}; args="--joints ${layout%x*} --ring-joints ${m%fit} --ring-fit" ;;
    *) args="--joints ${layout%x*} --ring-joints ${layout#*x}" ;;
  esac
  # (sh, not bash: the options as one word list, split on purpose)
  # shellcheck disable=SC2086
  "$sim" -q "$rig" -b "$work/tube.bind" --scene "$work/scene-moving.json" $args \
    -o "$work/tube-skin-$layout.glb" -o "$work/tube-skin-$layout.pc2" --report "$work/tube-skin-$layout.json"
  tolerance=$(python3 -c 'import json, sys
r = json.load(open(sys.argv[1])); rig = json.load(open(sys.argv[2]))
length = max(s["sections"][-1]["t"] for s in rig["sweeps"])
print(r["skin_error_max_relative"] * length * 1.0001)' "$work/tube-skin-$layout.json" "$rig")
  echo "== skinned, joints $layout (30 fps, moving body; tolerance $tolerance)"
  if blender -b --factory-startup --python-exit-code 1 --python "$src/tests/blender/check_bake.py" -- \
    "$src/meshes/tube_bent.obj" "$work/tube-skin-$layout.glb" "$work/tube-skin-$layout.pc2" 30 \
    --skinned "$tolerance" >"$work/blender-skin-$layout.log" 2>&1; then
    grep -E '^(ok|FAIL|blender check)' "$work/blender-skin-$layout.log" || cat "$work/blender-skin-$layout.log"
  else
    cat "$work/blender-skin-$layout.log"
    status=1
  fi
done
exit $status
