#!/usr/bin/env bash
# Regenerates the example tube meshes committed in meshes/ (listed in meshes/README.md).
# Usage: tools/sweep-tube/regenerate-meshes.sh [path/to/sweep-tube] [output-dir]
#   defaults: build/dev/tools/sweep-tube/sweep-tube and meshes/ of this checkout.
# The test TubeMeshes.RegeneratedFilesMatchCommittedBytes runs this into a temporary folder and
# compares byte for byte, so edit a command here and in meshes/README.md together.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
tube=${1:-$here/build/dev/tools/sweep-tube/sweep-tube}
out=${2:-$here/meshes}
mkdir -p "$out"
export LC_ALL=C

"$tube" -q -o "$out/tube_straight.obj" --length 1 --radius 0.1 --rings 33 --segments 24
"$tube" -q -o "$out/tube_bent.obj" --length 2 --radius 0.12 --bend 1.8 --rings 49 --segments 24
"$tube" -q -o "$out/tube_tapered.off" --length 1.5 --radius 0.15 --taper 0.4 --rings 33 --segments 24
"$tube" -q -o "$out/tube_ellipse.ply" --length 1 --radius 0.12 --shape ellipse --ellipse-ratio 0.6 --rings 33 --segments 32
"$tube" -q -o "$out/tube_lobed.obj" --length 1.2 --radius 0.1 --shape lobed --lobes 5 --lobe-amplitude 0.2 --rings 41 --segments 40
