#!/usr/bin/env bash
# .glb size and peak memory against frames: the bent example tube baked at 60 fps for 600, 3,600
# and 25,000 frames (a push at the tip). Writes tools/bench/results/glb_frames.md, which
# run-benchmarks.sh puts into BENCHMARKS.md.   tools/bench/glb-frames.sh [build/release/tools]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bin=${1:-$here/build/release/tools}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp "$here/rigs/tube-bent.rig.json" "$here/meshes/tube_bent.obj" "$work/"
sed -i 's#"mesh": *"[^"]*"#"mesh": "tube_bent.obj"#' "$work/tube-bent.rig.json"
"$bin/sweep-bind/sweep-bind" "$work/tube-bent.rig.json" >/dev/null
{
  echo "| frames | .glb bytes | bytes a frame | peak memory | bake time |"
  echo "|---|---|---|---|---|"
  for frames in 600 3600 25000; do
    cat >"$work/scene.json" <<JSON
{"format": "sweep-scene", "version": 1, "duration": $(awk "BEGIN { print ($frames - 1) / 60 }"), "fps": 60,
 "forces": [{"sweep": "tube", "t": 1.0, "theta": 0.0, "vector": [0, 2.0, 0], "start": 0.0, "end": 0.75,
             "sections": "chain"}]}
JSON
    /usr/bin/time -f "%M %e" -o "$work/time" "$bin/sweep-sim/sweep-sim" "$work/tube-bent.rig.json" \
      --scene "$work/scene.json" -o "$work/out.glb" --no-sleep >/dev/null
    read -r kb seconds <"$work/time"
    bytes=$(stat -c %s "$work/out.glb")
    echo "| $frames | $bytes | $((bytes / frames)) | $((kb / 1024)) MiB | $seconds s |"
    rm -f "$work/out.glb"
  done
} >"$here/tools/bench/results/glb_frames.md"
cat "$here/tools/bench/results/glb_frames.md"
