#!/usr/bin/env bash
# The main job from a fresh clone: install what is missing, build the release preset, then fit the
# tail and the neck of a mesh into one rig, bind it, and bake the scene of the paper's Fig. 4
# (bending, twisting and cross-sectional change at once) to .glb and .pc2, with a JSON report and
# a preview picture; then, for the bundled example, a second demo in material mode with gravity and
# a third, the diplodocus rigged (a skeleton, skin weights and a looping walk clip) and walking.
#
#   tools/run-demo.sh                     # CGAL's diplodocus (23,982 vertices), the bundled example
#   MESH=my.off TAIL_ROOT=x,y,z TAIL_TIP=x,y,z NECK_ROOT=x,y,z NECK_TIP=x,y,z SCENE=my.scene.json \
#     OUT=out/mine tools/run-demo.sh      # another mesh: say where its parts leave the body and end
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
tools/setup-deps.sh

mesh=${MESH:-meshes/cgal/diplodocus.off}
scene=${SCENE:-rigs/diplodocus-fig4.scene.json}
out=${OUT:-out/diplodocus}
tail_root=${TAIL_ROOT:--0.29,-0.16,-0.015}
tail_tip=${TAIL_TIP:--0.5,-0.345,-0.012}
neck_root=${NECK_ROOT:-0.26,0.08,0.062}
neck_tip=${NECK_TIP:-0.36,0.45,0.11}

# The previews shade the mesh's surfaces where sweep-preview.py can read its faces (.off, .obj);
# PREVIEW=0 skips the pictures (about ten seconds each on the diplodocus).
case "$mesh" in
  *.off|*.OFF|*.obj|*.OBJ) shaded=(--mesh "$mesh") ;;
  *) shaded=() ;;
esac
preview() { if [ "${PREVIEW:-1}" != 0 ]; then tools/sweep-preview.py "$@" "${shaded[@]}" --views xz,xy; fi; }

cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)" --target sweep-fit sweep-bind sweep-sim
bin=build/release/tools
mkdir -p "$(dirname "$out")"
rm -f "$out.rig.json"  # fit adds sweeps to an existing rig: start a fresh one

# The paper's Fig. 4 scene pushes as the paper's springs need: --springs keeps them (a fit without
# it gives each part the material preset its name chooses, which these forces would fold).
"$bin/sweep-fit/sweep-fit" "$mesh" -o "$out.rig.json" --name tail --root "$tail_root" --tip "$tail_tip" \
  --springs --report "$out.fit-tail.json"
"$bin/sweep-fit/sweep-fit" "$mesh" -o "$out.rig.json" --name neck --root "$neck_root" --tip "$neck_tip" \
  --springs --report "$out.fit-neck.json"
"$bin/sweep-bind/sweep-bind" "$out.rig.json" --blend 0.02 --report "$out.bind.json"
"$bin/sweep-sim/sweep-sim" "$out.rig.json" --scene "$scene" -o "$out.glb" -o "$out.pc2" \
  --report "$out.sim.json"
preview "$out.pc2" -o "$out.png" --report "$out.sim.json"

# The second demo (the diplodocus only): the same parts in material mode — a 25 m animal of flesh
# over a stiff spine (rigs/diplodocus-*.material.json) — drooping under gravity from an unloaded
# rest, then a tail swing and a neck push in newtons (rigs/diplodocus-material.scene.json).
material_demo=""
if [ -z "${MESH:-}" ]; then
  material_demo="$out-material"
  rm -f "$material_demo.rig.json"
  "$bin/sweep-fit/sweep-fit" "$mesh" -o "$material_demo.rig.json" --name tail --root "$tail_root" --tip "$tail_tip" \
    --material rigs/diplodocus-tail.material.json
  "$bin/sweep-fit/sweep-fit" "$mesh" -o "$material_demo.rig.json" --name neck --root "$neck_root" --tip "$neck_tip" \
    --material rigs/diplodocus-neck.material.json
  "$bin/sweep-bind/sweep-bind" "$material_demo.rig.json" --blend 0.02 -q
  "$bin/sweep-sim/sweep-sim" "$material_demo.rig.json" --scene rigs/diplodocus-material.scene.json \
    -o "$material_demo.glb" -o "$material_demo.pc2" --report "$material_demo.sim.json"
  preview "$material_demo.pc2" -o "$material_demo.png" --report "$material_demo.sim.json"
  # The third: the diplodocus given a skeleton, skin weights and a looping 1.2 s walk
  # (meshes/make_skinned_diplodocus.py writes it as a skinned .glb); tail and neck fitted on its bind
  # pose with the same materials, and the clip walked in a loop after a 12 s preroll
  # (rigs/diplodocus-walk.scene.json): tail and neck lag and overshoot the pose the clip keys.
  walk_demo="$out-walk"
  # (and the pose the clip keys at the scene's 73 frames, which the picture colours the lag against)
  /usr/bin/python3 meshes/make_skinned_diplodocus.py "$mesh" "$out-skinned.glb" --keyed 30 73 "$walk_demo.keyed.pc2"
  rm -f "$walk_demo.rig.json"
  "$bin/sweep-fit/sweep-fit" "$out-skinned.glb" -o "$walk_demo.rig.json" --name tail --root "$tail_root" --tip "$tail_tip" \
    --material rigs/diplodocus-tail.material.json --report "$walk_demo.fit-tail.json"
  "$bin/sweep-fit/sweep-fit" "$out-skinned.glb" -o "$walk_demo.rig.json" --name neck --root "$neck_root" --tip "$neck_tip" \
    --material rigs/diplodocus-neck.material.json --report "$walk_demo.fit-neck.json"
  "$bin/sweep-bind/sweep-bind" "$walk_demo.rig.json" --blend 0.02 -q
  "$bin/sweep-sim/sweep-sim" "$walk_demo.rig.json" --scene rigs/diplodocus-walk.scene.json \
    -o "$walk_demo.pc2" -o "$walk_demo.glb" --report "$walk_demo.sim.json"
  preview "$walk_demo.pc2" -o "$walk_demo.png" --report "$walk_demo.sim.json" --reference "$walk_demo.keyed.pc2" --frames 9 --dpi 90
fi

cat <<MSG

Done. The baked files:
  $out.glb       glTF 2.0: mesh + one morph target a frame + the animation (Blender, three.js, engines)
  $out.pc2       point cache in the mesh's vertex order (Blender's Mesh Cache modifier, Houdini, 3ds Max)
  $out.png       preview: shaded frames from above and from the side, the moving part coloured by
                 its displacement, and the displacement over time
Reports (JSON): $out.fit-tail.json $out.fit-neck.json $out.bind.json $out.sim.json
The rig and its binding: $out.rig.json $out.rig.bind
MSG
if [ -n "$material_demo" ]; then
  cat <<MSG
Material mode with gravity (the second demo): $material_demo.glb $material_demo.pc2 $material_demo.png
The rigged diplodocus walking (the third): $out-skinned.glb (the rigged input: open it in Blender or an
  engine) and its bake $walk_demo.glb (the same character whole, its parts' motion as joints added to its
  skeleton: play its "sweep bake" animation), $walk_demo.pc2, $walk_demo.png
MSG
fi
