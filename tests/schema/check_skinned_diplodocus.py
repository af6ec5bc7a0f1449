#!/usr/bin/python3
"""meshes/make_skinned_diplodocus.py: the walking demo's rigged diplodocus is the same bytes on every
run, holds the OFF's mesh as read, a skin glTF accepts (at most 4 influences a vertex, weights >= 0
summing to 1, inverse bind matrices that undo the skeleton's rest pose), weights that keep each limb
to itself (no tail or neck vertex moved by a leg), and a clip that loops (every channel's last key
is its first). The Khronos validator (where installed) finds no error in it.

    check_skinned_diplodocus.py PROJECT_DIR SCRATCH_DIR      exit 0 pass, 1 fail, 77 skipped
"""
import json
import pathlib
import shutil
import struct
import subprocess
import sys

import numpy as np

project, scratch = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
off = project / "meshes/cgal/diplodocus.off"
if not off.exists():
    print(f"skipped: {off} is not unpacked (tools/setup-deps.sh)")
    sys.exit(77)
scratch.mkdir(parents=True, exist_ok=True)
generator = project / "meshes/make_skinned_diplodocus.py"
outs = [scratch / "diplodocus-skinned-1.glb", scratch / "diplodocus-skinned-2.glb"]
for out in outs:
    subprocess.run([sys.executable, str(generator), str(off), str(out)], check=True)
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


data = outs[0].read_bytes()
check(data == outs[1].read_bytes(), "two runs of the generator wrote different bytes")

# The .glb: header, JSON chunk, BIN chunk.
magic, version, length = struct.unpack("<4sII", data[:12])
check(magic == b"glTF" and version == 2 and length == len(data), "not a glTF 2.0 binary of its stated length")
json_length = struct.unpack("<I", data[12:16])[0]
doc = json.loads(data[20:20 + json_length])
binary = data[20 + json_length + 8:]


def accessor(i):
    a = doc["accessors"][i]
    view = doc["bufferViews"][a["bufferView"]]
    width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4, "MAT4": 16}[a["type"]]
    dtype = {5126: "<f4", 5121: "u1", 5125: "<u4"}[a["componentType"]]
    return np.frombuffer(binary, dtype, a["count"] * width, view["byteOffset"]).reshape(a["count"], width)


# The mesh as read: the OFF's vertices in order (as float32) and its faces fanned into triangles.
words = off.read_text().split()
nv, nf = int(words[1]), int(words[2])
off_positions = np.array(words[4:4 + 3 * nv], float).reshape(nv, 3).astype("<f4")
triangles, at = [], 4 + 3 * nv
for _ in range(nf):
    k = int(words[at])
    idx = [int(x) for x in words[at + 1:at + 1 + k]]
    triangles += [(idx[0], idx[i], idx[i + 1]) for i in range(1, k - 1)]
    at += 1 + k
primitive = doc["meshes"][0]["primitives"][0]
attributes = primitive["attributes"]
positions = accessor(attributes["POSITION"])
check(np.array_equal(positions, off_positions), "POSITION is not the OFF's vertices in order")
check(np.array_equal(accessor(primitive["indices"]).reshape(-1, 3), np.array(triangles)),
      "the triangles are not the OFF's faces")

# The skin.
skin = doc["skins"][0]
nodes = doc["nodes"]
names = [nodes[j]["name"] for j in skin["joints"]]
joints = accessor(attributes["JOINTS_0"]).astype(int)
weights = accessor(attributes["WEIGHTS_0"]).astype(float)
check(joints.shape == (nv, 4) and weights.shape == (nv, 4), "JOINTS_0/WEIGHTS_0 are not 4 a vertex")
check(joints.max() < len(names), "a joint index past the skin's joints")
check(weights.min() >= 0, "a negative weight")
sums = weights.sum(axis=1)
check(np.abs(sums - 1).max() <= 2e-7, f"weights sum to 1 only within {np.abs(sums - 1).max():.2e}")
# Each joint's world rest transform (node translations composed down the hierarchy) times its
# inverse bind matrix is the identity: the mesh as read is the bind pose.
parent = {c: i for i, n in enumerate(nodes) for c in n.get("children", [])}


def rest_world(n):
    m = np.eye(4)
    m[:3, 3] = nodes[n].get("translation", [0, 0, 0])
    check("rotation" not in nodes[n] and "scale" not in nodes[n], f"joint {nodes[n]['name']} rests rotated or scaled")
    return rest_world(parent[n]) @ m if n in parent else m


ibm = accessor(skin["inverseBindMatrices"]).astype(float).reshape(-1, 4, 4).transpose(0, 2, 1)  # column-major
for k, j in enumerate(skin["joints"]):
    check(np.abs(rest_world(j) @ ibm[k] - np.eye(4)).max() < 1e-6, f"joint {names[k]}: IBM does not undo its rest pose")
# No vertex moved by the tail or the neck is moved by a leg.
legs = [i for i, n in enumerate(names) if n.startswith(("Hind", "Front"))]
limb = [i for i, n in enumerate(names) if n.startswith(("Tail", "Neck", "Head"))]
on_limb = (np.isin(joints, limb) & (weights > 0)).any(axis=1)
on_leg = (np.isin(joints, legs) & (weights > 0)).any(axis=1)
check(not (on_limb & on_leg).any(), f"vertices moved by both a leg and the tail or neck: {np.nonzero(on_limb & on_leg)[0][:10]}")
check(on_limb.sum() > 3000 and on_leg.sum() > 3000, "fewer than 3000 vertices on the tail and neck, or on the legs")

# The clip loops: each channel's last key is its first; every joint but the knees' parents moves.
walk = [a for a in doc["animations"] if a["name"] == "Walk"]
check(len(walk) == 1, "no clip 'Walk'")
moved = set()
for channel in walk[0]["channels"]:
    sampler = walk[0]["samplers"][channel["sampler"]]
    times, values = accessor(sampler["input"])[:, 0], accessor(sampler["output"])
    name = nodes[channel["target"]["node"]]["name"]
    moved.add(name)
    check(sampler["interpolation"] == "LINEAR", f"{name}: not LINEAR")
    check(times[0] == 0 and abs(times[-1] - 1.2) < 1e-6 and np.all(np.diff(times) > 0), f"{name}: keys not over 0..1.2 s")
    check(np.array_equal(values[0], values[-1]), f"{name} {channel['target']['path']}: last key is not the first")
check(moved == set(names), f"the clip leaves joints still: {sorted(set(names) - moved)}")

# The Khronos validator: no errors.
validator = project / "tests/gltf-validator/validate.js"
if shutil.which("node") and (project / "tests/gltf-validator/node_modules/gltf-validator").exists():
    run = subprocess.run(["node", str(validator), str(outs[0])], capture_output=True, text=True)
    check(run.returncode == 0, f"the validator finds errors: {run.stdout[:2000]}")
else:
    print("note: the glTF validator is not installed; not run")

for f in failures:
    print("FAIL:", f)
print(f"{'failed' if failures else 'passed'}: {outs[0]} ({nv} vertices, {len(names)} joints)")
sys.exit(1 if failures else 0)
