#!/usr/bin/env bash
# The cost of playing a skinned clip, in one run: a 600-frame (20 s at 30 fps) bake of the rigged
# diplodocus walking its clip (every one of its 23,982 vertices skinned each frame; the rig
# tools/run-demo.sh fits on out/diplodocus-skinned.glb) against the same bake with the skin removed:
# the same parts and materials fitted on the OFF, on a body path (five cubic keys: a walk forward and
# a turn). CPU time (user + sys), not wall time: the machine is shared. Twice, alternating.
#   tools/run-demo.sh && tools/bench/skinned-walk-cost.sh [BIN_DIR (default build/release/tools)]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
bin=${1:-build/release/tools}
o=out/skinned-walk-cost
mkdir -p "$o"
rm -f "$o/plain.rig.json"
"$bin/sweep-fit/sweep-fit" meshes/cgal/diplodocus.off -o "$o/plain.rig.json" -q --name tail --root=-0.29,-0.16,-0.015 \
  --tip=-0.5,-0.345,-0.012 --material rigs/diplodocus-tail.material.json
"$bin/sweep-fit/sweep-fit" meshes/cgal/diplodocus.off -o "$o/plain.rig.json" -q --name neck --root 0.26,0.08,0.062 \
  --tip 0.36,0.45,0.11 --material rigs/diplodocus-neck.material.json
"$bin/sweep-bind/sweep-bind" "$o/plain.rig.json" --blend 0.02 -q
cat > "$o/skinned.scene.json" <<J
{"format": "sweep-scene", "version": 1, "forces": [], "duration": 20, "fps": 30, "gravity": [0, -9.81, 0],
 "body": {"node": "Hip", "animation": "Walk", "loop": true}}
J
cat > "$o/path.scene.json" <<J
{"format": "sweep-scene", "version": 1, "forces": [], "duration": 20, "fps": 30, "gravity": [0, -9.81, 0],
 "body": {"interpolation": "cubic", "keys": [{"time": 0, "translation": [0, 0, 0]}, {"time": 5, "translation": [0.2, 0, 0]},
   {"time": 10, "translation": [0.5, 0, 0.05], "turn_degrees": 20}, {"time": 15, "translation": [0.8, 0, 0.1], "turn_degrees": 30},
   {"time": 20, "translation": [1.0, 0, 0.1], "turn_degrees": 30}]}}
J
for run in 1 2; do
  /usr/bin/time -f "skinned clip: %U s user, %S s sys, %e s wall, max RSS %M kB" "$bin/sweep-sim/sweep-sim" -q \
    out/diplodocus-walk.rig.json --scene "$o/skinned.scene.json" -o "$o/skinned.pc2" 2>&1 | grep -v '^warning'
  /usr/bin/time -f "body path:    %U s user, %S s sys, %e s wall, max RSS %M kB" "$bin/sweep-sim/sweep-sim" -q \
    "$o/plain.rig.json" --scene "$o/path.scene.json" -o "$o/path.pc2" 2>&1 | grep -v '^warning'
done
