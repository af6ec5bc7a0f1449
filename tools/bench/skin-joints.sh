#!/usr/bin/env bash
# Skinned .glb (sweep-sim --joints N --ring-joints M) against the morph-target .glb: CGAL's diplodocus, tail and neck
# fitted and bound as tools/run-demo.sh does, the Fig. 4 scene at 150 fps (its 4 s in 601 frames,
# 600 intervals), baked with the exact deformation (--exact) so the error is the skin's alone.
# For each N×M (N joints along a sweep, M around each station but the root; M = 1: none): the skin's largest and RMS error over every bound vertex of every frame (% of the
# part's length, from sweep-sim's report), the file's size and the bake's write time (median of 3
# runs, from the report's seconds.write), beside the morph-target bake's size and write time.
# A layout NxMfit adds --ring-fit (the ring joints' keys by least squares).
# Writes tools/bench/results/skin_joints.md.   tools/bench/skin-joints.sh [build/release/tools] [NxM[fit] ...]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=${1:-$here/build/release/tools}
shift || true
layouts=${*:-4x1 8x1 16x1 24x1 4x4 8x4 16x4 4x8 8x8 16x8 24x8 8x12 16x12 24x12 8x24 16x24 24x24 8x8fit 24x24fit}
mesh=$here/meshes/cgal/diplodocus.off
[ -f "$mesh" ] || { echo "error: $mesh is missing (tools/setup-deps.sh)"; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin/sweep-fit/sweep-fit" "$mesh" -o "$work/d.rig.json" --name tail --root -0.29,-0.16,-0.015 \
  --tip -0.5,-0.345,-0.012 >/dev/null
"$bin/sweep-fit/sweep-fit" "$mesh" -o "$work/d.rig.json" --name neck --root 0.26,0.08,0.062 \
  --tip 0.36,0.45,0.11 >/dev/null
"$bin/sweep-bind/sweep-bind" "$work/d.rig.json" --blend 0.02 -q
python3 -c 'import json, sys; s = json.load(open(sys.argv[1])); s["fps"] = 150; json.dump(s, open(sys.argv[2], "w"))' \
  "$here/rigs/diplodocus-fig4.scene.json" "$work/scene.json"
median() { sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }
# bake OUT [ARGS]: three runs; prints "bytes write_ms max% rms%".
bake() {
  local out=$1; shift
  for run in 1 2 3; do
    "$bin/sweep-sim/sweep-sim" "$work/d.rig.json" --scene "$work/scene.json" --exact -q \
      -o "$work/$out" --report "$work/r.json" "$@"
    python3 -c 'import json, sys; r = json.load(open(sys.argv[1])); print(r["seconds"]["write"] * 1e3)' "$work/r.json"
  done | median >"$work/write"
  python3 -c 'import json, os, sys
r = json.load(open(sys.argv[1]))
print(os.path.getsize(sys.argv[2]), open(sys.argv[3]).read().strip(),
      "%.3f" % (100 * r.get("skin_error_max_relative", 0)), "%.4f" % (100 * r.get("skin_error_rms_relative", 0)), r["frames"])' \
    "$work/r.json" "$work/$out" "$work/write"
}
read -r morph_bytes morph_ms _ _ frames < <(bake morph.glb)
{
  echo "| N × M | joints | max error, % of length | RMS error, % of length | .glb bytes | size / morph | write time |"
  echo "|---|---|---|---|---|---|---|"
  for layout in $layouts; do
    n=${layout%x*}
    m=${layout#*x}
    fit=()
    if [ "${m%fit}" != "$m" ]; then m=${m%fit}; fit=(--ring-fit); fi
    read -r bytes ms max rms _ < <(bake "skin$layout.glb" --joints "$n" --ring-joints "$m" "${fit[@]}")
    joints=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["skin_joints"])' "$work/r.json")
    echo "| $n × $m${fit:+ (--ring-fit)} | $joints | $max | $rms | $bytes | 1/$(awk "BEGIN { printf \"%.1f\", $morph_bytes / $bytes }") | $(printf '%.1f' "$ms") ms |"
  done
  echo "| morph targets (no --joints) | | 0 | 0 | $morph_bytes | 1 | $(printf '%.1f' "$morph_ms") ms |"
  echo
  echo "$frames frames; $(uname -srm); $(date -u +%Y-%m-%d)"
} >"$here/tools/bench/results/skin_joints.md"
cat "$here/tools/bench/results/skin_joints.md"
