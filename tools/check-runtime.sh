#!/usr/bin/env bash
# The installed runtime, as a game programmer meets it:
#   1. `cmake --install` the build into a temporary prefix;
#   2. configure and build examples/runtime against that prefix only (find_package(sweep));
#   3. its link line and `ldd` name no authoring library (CGAL and its GMP/MPFR, assimp,
#      tinygltf, tinyobjloader, libpng, Boost);
#   4. the installed tools bind and bake the bent-tube rig, and the example, stepping and deforming
#      frame by frame through the runtime API, ends on the bake's last frame bit for bit;
#   5. libsweep: examples/capi (C) builds against the prefix alone, links no authoring library and
#      runs its live loop on the bent tube; so does examples/capi/sweep_ctypes.py (Python's ctypes)
#      on the installed libsweep.so.
# Usage: tools/check-runtime.sh [BUILD_DIR]   (default: build/dev). Exit 0 on success.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=$(cd "${1:-$root/build/dev}" && pwd)
work=$(mktemp -d "${TMPDIR:-/tmp}/sweep-runtime-check.XXXXXX")
trap 'rm -rf "$work"' EXIT
say() { echo "check-runtime: $*"; }
die() { echo "check-runtime: FAILED: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$work/prefix" > "$work/install.log" || die "cmake --install (log: $work/install.log)"
for tool in sweep-fit sweep-bind sweep-sim; do
  [[ -x $work/prefix/bin/$tool ]] || die "$tool was not installed"
done
[[ -f $work/prefix/include/sweep/sweep.h ]] || die "sweep/sweep.h was not installed"
libsweep=$(find "$work/prefix" -name 'libsweep.so' | head -n 1)
[[ -n $libsweep ]] || die "libsweep.so was not installed"
[[ -f $work/prefix/lib/cmake/sweep/sweepConfig.cmake ]] || die "no CMake package installed"
say "installed into a temporary prefix: $(cd "$work/prefix" && find . -type f | wc -l) files"

# Only the prefix: CMAKE_FIND_USE_PACKAGE_REGISTRY off, so the build tree cannot be found instead.
cmake -S "$root/examples/runtime" -B "$work/example" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_BUILD_TYPE=Release > "$work/configure.log" \
  || { cat "$work/configure.log"; die "configuring examples/runtime against the installed package"; }
cmake --build "$work/example" --verbose > "$work/build.log" 2>&1 \
  || { cat "$work/build.log"; die "building examples/runtime against the installed package"; }
exe=$work/example/sweep-runtime-example
authoring='assimp|CGAL|gmp|mpfr|tinygltf|tiny_gltf|tinyobj|png|boost'
if grep -E -- "-o [^ ]*sweep-runtime-example " "$work/build.log" | grep -Eiq "$authoring"; then
  grep -E -- "-o [^ ]*sweep-runtime-example " "$work/build.log"
  die "the example's link line names an authoring library"
fi
if ldd "$exe" | grep -Eiq "$authoring"; then
  ldd "$exe"
  die "the example loads an authoring library"
fi
say "link line: $(grep -E -- "-o [^ ]*sweep-runtime-example " "$work/build.log" | tr ' ' '\n' | grep -E '\.a$|\.so|^-l|^-fopenmp' | xargs -n1 basename | sort -u | tr '\n' ' ')"
say "ldd: $(ldd "$exe" | awk '{print $1}' | tr '\n' ' ')"

rig=$root/rigs/tube-bent.rig.json
mesh=$root/meshes/tube_bent.obj
"$work/prefix/bin/sweep-bind" -q "$rig" -o "$work/tube.bind"
"$work/prefix/bin/sweep-sim" -q "$rig" -b "$work/tube.bind" -o "$work/tube.pc2"
"$exe" "$rig" "$work/tube.bind" "$mesh" -o "$work/last.f32" > "$work/example.log"
tail -n 1 "$work/example.log"
python3 - "$work/tube.pc2" "$work/last.f32" <<'EOF'
import struct, sys
pc2 = open(sys.argv[1], "rb").read()
points, samples = struct.unpack_from("<i", pc2, 16)[0], struct.unpack_from("<i", pc2, 28)[0]
frame = points * 12
last = pc2[32 + (samples - 1) * frame: 32 + samples * frame]
first = pc2[32: 32 + frame]
mine = open(sys.argv[2], "rb").read()
if len(mine) != frame:
    sys.exit(f"the example wrote {len(mine)} bytes, a frame of {points} points is {frame}")
if last == first:
    sys.exit("the bake's last frame is its rest pose: nothing moved, the comparison proves nothing")
if mine != last:
    diffs = sum(1 for k in range(0, frame, 4) if mine[k:k + 4] != last[k:k + 4])
    sys.exit(f"the example's last frame differs from sweep-sim's in {diffs} of {frame // 4} floats")
print(f"check-runtime: the example's last frame equals the bake's ({points} vertices, frame {samples - 1}), bit for bit")
EOF
# libsweep's C example: built against the prefix alone, as a C program.
cmake -S "$root/examples/capi" -B "$work/capi" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_BUILD_TYPE=Release > "$work/capi-configure.log" \
  || { cat "$work/capi-configure.log"; die "configuring examples/capi against the installed package"; }
cmake --build "$work/capi" > "$work/capi-build.log" 2>&1 \
  || { cat "$work/capi-build.log"; die "building examples/capi against the installed package"; }
capi=$work/capi/sweep-capi-example
if ldd "$capi" | grep -Eiq "$authoring"; then
  ldd "$capi"
  die "the C example loads an authoring library"
fi
"$capi" "$rig" "$work/tube.bind" "$mesh" > "$work/capi.log" || { cat "$work/capi.log"; die "the C example failed"; }
say "C example: $(tail -n 1 "$work/capi.log")"
python3 "$root/examples/capi/sweep_ctypes.py" "$libsweep" "$rig" "$work/tube.bind" "$mesh" > "$work/ctypes.log" \
  || { cat "$work/ctypes.log"; die "the ctypes example failed"; }
say "ctypes example: $(tail -n 1 "$work/ctypes.log")"
say "ok"
