#!/usr/bin/env bash
# Installs the Debian packages sweep needs to build, test and run its demo. Idempotent: packages
# already present are not touched, and apt is not called at all when nothing is missing.
#   tools/setup-deps.sh            # build + demo
#   tools/setup-deps.sh --tests    # also what only the tests use: Blender (~170 MB download), which
#                                  # plays the baked files in tests/blender, and clang with its
#                                  # sanitizer, libFuzzer and OpenMP runtimes (the asan preset)
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libassimp-dev nlohmann-json3-dev libcli11-dev libgtest-dev libgmock-dev
  libtinygltf-dev libtinyobjloader-dev
  libpng-dev     # sweep-fit --preview pictures
  python3 python3-jsonschema python3-matplotlib python3-numpy  # schema checks, preview pictures
  libcgal-demo   # CGAL's sample meshes (diplodocus.off, ...) for the demo and real-mesh tests
  gnuplot-nox    # the plots of tools/bench/run-benchmarks.sh
  clang-format   # the sources' format, checked by the tests (tools/check-format.sh)
)
case "${1:-}" in
  --tests) packages+=(blender clang libclang-rt-dev libomp-dev) ;;
  "") ;;
  *) echo "error: unknown option $1 (expected --tests or nothing)" >&2; exit 1 ;;
esac
# Node.js runs the Khronos glTF validator in the .glb tests. Machines of this kind may already have a
# Node.js that bundles npm (Debian's own npm package then conflicts with it): ask apt only for what
# is missing as a command.
command -v node >/dev/null 2>&1 || packages+=(nodejs)
command -v npm >/dev/null 2>&1 || packages+=(npm)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}" >&2
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# CGAL's sample meshes ship compressed inside libcgal-dev's docs; unpack the meshes folder once
# into meshes/cgal/ (git-ignored: these files are never committed).
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
if [ ! -f "$here/meshes/cgal/diplodocus.off" ]; then
  mkdir -p "$here/meshes/cgal"
  tar -xzf /usr/share/doc/libcgal-dev/data.tar.gz -C "$here/meshes/cgal" --strip-components=2 \
      --wildcards 'data/meshes/*'
fi

# The Khronos glTF validator (npm package `gltf-validator`, version pinned in
# tests/gltf-validator/package.json; one package, no dependencies) for the .glb tests. Installed once
# into tests/gltf-validator/node_modules (git-ignored); tests never download anything.
if [ ! -d "$here/tests/gltf-validator/node_modules/gltf-validator" ]; then
  echo "setup: installing the glTF validator into tests/gltf-validator" >&2
  npm install --no-audit --no-fund --prefix "$here/tests/gltf-validator"
fi
