#!/usr/bin/env python3
"""Gives CGAL's diplodocus (meshes/cgal/diplodocus.off) a skeleton, skin weights and a looping walk,
and writes it as a binary glTF (.glb): the walking demo's creature (tools/run-demo.sh).

The mesh is kept as read: the OFF's vertices in their order (so a bake of it lines up with the OFF,
as the preview's --mesh needs) and its faces fanned into triangles. It is not committed (CGAL's
sample meshes never are); this script makes it from the unpacked sample, byte for byte the same on
every run (the .glb needs the standard library only; numbers written as float32).

Skeleton (joint positions read off the mesh: centroids of its body's, tail's, neck's and legs'
cross sections; y up, head at +x):
  Hip -> Chest -> Neck1 -> Neck2 -> Neck3 -> Head;  Hip -> Tail1 -> Tail2 -> Tail3 -> Tail4;
  Hip -> HindL -> HindL_knee, Hip -> HindR -> HindR_knee, Chest -> FrontL -> FrontL_knee,
  Chest -> FrontR -> FrontR_knee  (L: -z side, R: +z side).
Every joint rests unrotated at its position; its inverse bind matrix is the inverse translation.

Weights: each joint moves a bone, a segment (a joint to its child; the last of a chain to the end
of the limb). A vertex belongs to the limb (tail, neck, a leg) of its nearest bone outside the trunk
(Hip, Chest); it is weighted by the bones of that limb and the trunk as 1 / (d^2 + 0.01^2)^2, d its
distance to the bone, keeping the 4 largest, normalised to sum 1. So no vertex moves with both a leg
and the tail or neck, and weights blend smoothly over each joint.

Clip "Walk" (1.2 s, loops; LINEAR keys every 1/30 s, the last key the first's values, so the clip
wraps without a seam): a brisk lateral-sequence walk in place, phase p = 2 pi t / 1.2 s.
  Hip:   bobs 0.006 twice a cycle, sways 0.004 sideways, turns 3 deg about y and rolls 1.5 deg.
  Chest: turns -2 deg about y against the hip.
  Legs:  each upper joint swings 16 deg about z (fore and aft), the knee bends up to 20 deg while
         the leg swings forward; hind left, front left, hind right, front right a quarter apart.
  Tail:  Tail1..Tail4 sway about y, 3, 4, 5, 6 deg, each 0.5 rad behind the one before.
  Neck:  Neck1..Neck3 sway about y, 2 deg each, 0.4 rad apart; Head nods 3 deg about z.

Run: python3 meshes/make_skinned_diplodocus.py meshes/cgal/diplodocus.off out/diplodocus-skinned.glb
  [--keyed FPS FRAMES keyed.pc2]   also the pose the clip keys at frames k / FPS (needs numpy)"""
import json
import math
import struct
import sys

PERIOD = 1.2
KEYS_PER_SECOND = 30

# name, parent, rest position (mesh units), the bone's end (its child's position or the limb's end)
JOINTS = [
    ("Hip", None, (-0.20, -0.09, 0.010), (0.00, -0.07, 0.035)),
    ("Chest", "Hip", (0.00, -0.07, 0.035), (0.25, 0.03, 0.055)),
    ("Neck1", "Chest", (0.25, 0.03, 0.055), (0.276, 0.155, 0.069)),
    ("Neck2", "Neck1", (0.276, 0.155, 0.069), (0.300, 0.270, 0.087)),
    ("Neck3", "Neck2", (0.300, 0.270, 0.087), (0.330, 0.380, 0.100)),
    ("Head", "Neck3", (0.330, 0.380, 0.100), (0.470, 0.430, 0.115)),
    ("Tail1", "Hip", (-0.300, -0.150, -0.003), (-0.335, -0.240, -0.010)),
    ("Tail2", "Tail1", (-0.335, -0.240, -0.010), (-0.378, -0.314, -0.021)),
    ("Tail3", "Tail2", (-0.378, -0.314, -0.021), (-0.429, -0.341, -0.021)),
    ("Tail4", "Tail3", (-0.429, -0.341, -0.021), (-0.500, -0.348, -0.016)),
    ("HindL", "Hip", (-0.190, -0.140, -0.085), (-0.262, -0.280, -0.101)),
    ("HindL_knee", "HindL", (-0.262, -0.280, -0.101), (-0.275, -0.365, -0.108)),
    ("HindR", "Hip", (-0.110, -0.150, 0.100), (-0.135, -0.300, 0.090)),
    ("HindR_knee", "HindR", (-0.135, -0.300, 0.090), (-0.115, -0.425, 0.080)),
    ("FrontL", "Chest", (0.150, -0.130, -0.040), (0.134, -0.300, -0.062)),
    ("FrontL_knee", "FrontL", (0.134, -0.300, -0.062), (0.160, -0.425, -0.080)),
    ("FrontR", "Chest", (0.150, -0.130, 0.120), (0.160, -0.330, 0.115)),
    ("FrontR_knee", "FrontR", (0.160, -0.330, 0.115), (0.220, -0.467, 0.120)),
]
LIMBS = {"trunk": ["Hip", "Chest"], "neck": ["Neck1", "Neck2", "Neck3", "Head"],
         "tail": ["Tail1", "Tail2", "Tail3", "Tail4"]}
for _leg in ("HindL", "HindR", "FrontL", "FrontR"):
    LIMBS[_leg] = [_leg, _leg + "_knee"]
# Each leg's phase in the cycle (lateral sequence: hind, front of one side, then the other's).
LEG_PHASE = {"HindL": 0.0, "FrontL": 0.5 * math.pi, "HindR": math.pi, "FrontR": 1.5 * math.pi}


def read_off(path):
    words = []
    with open(path) as f:
        for line in f:
            words += line.split("#")[0].split()
    if not words or not words[0].endswith("OFF"):
        raise SystemExit(f"{path}: not an OFF file")
    nv, nf = int(words[1]), int(words[2])
    at = 4
    positions = [tuple(float(x) for x in words[at + 3 * i:at + 3 * i + 3]) for i in range(nv)]
    at += 3 * nv
    triangles = []
    for _ in range(nf):
        k = int(words[at])
        idx = [int(x) for x in words[at + 1:at + 1 + k]]
        at += 1 + k
        triangles += [(idx[0], idx[i], idx[i + 1]) for i in range(1, k - 1)]
    return positions, triangles


def segment_distance(p, a, b):
    d = (b[0] - a[0], b[1] - a[1], b[2] - a[2])
    q = (p[0] - a[0], p[1] - a[1], p[2] - a[2])
    t = max(0.0, min(1.0, (q[0] * d[0] + q[1] * d[1] + q[2] * d[2]) / (d[0] ** 2 + d[1] ** 2 + d[2] ** 2)))
    return math.dist(p, (a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]))


def skin_weights(positions):
    index = {name: j for j, (name, _, _, _) in enumerate(JOINTS)}
    limb_of = {name: limb for limb, names in LIMBS.items() for name in names}
    joints, weights = [], []
    for p in positions:
        d = [segment_distance(p, head, end) for (_, _, head, end) in JOINTS]
        limbs = [j for j in range(len(JOINTS)) if limb_of[JOINTS[j][0]] != "trunk"]
        limb = limb_of[JOINTS[min(limbs, key=d.__getitem__)][0]]
        allowed = [index[n] for n in LIMBS[limb] + LIMBS["trunk"]]
        raw = sorted(((1.0 / (d[j] ** 2 + 1e-4) ** 2, j) for j in allowed), reverse=True)[:4]
        total = sum(w for w, _ in raw)
        # float32 weights whose float32 sum is 1: the largest takes what the others leave.
        w32 = [struct.unpack("<f", struct.pack("<f", w / total))[0] for w, _ in raw]
        w32[0] = 1.0 - sum(w32[1:])
        joints.append([j for _, j in raw])
        weights.append(w32)
    return joints, weights


def quat(axis, degrees):
    h = math.radians(degrees) / 2
    return [axis[0] * math.sin(h), axis[1] * math.sin(h), axis[2] * math.sin(h), math.cos(h)]


def quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return [aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz]


def walk_keys():
    """Per joint name: (translation keys or None, rotation keys), one a key time."""
    X, Y, Z = (1, 0, 0), (0, 1, 0), (0, 0, 1)
    n = int(round(PERIOD * KEYS_PER_SECOND))
    phases = [2 * math.pi * (k % n) / n for k in range(n + 1)]  # the last key is the first's
    keys = {}
    hx, hy, hz = JOINTS[0][2]  # the hip, the skeleton's root: its translation is its place
    keys["Hip"] = ([[hx, hy + 0.006 * math.cos(2 * p), hz + 0.004 * math.sin(p)] for p in phases],
                   [quat_mul(quat(Y, 3 * math.sin(p)), quat(X, 1.5 * math.sin(p))) for p in phases])
    keys["Chest"] = (None, [quat(Y, -2 * math.sin(p)) for p in phases])
    for leg, phase in LEG_PHASE.items():
        keys[leg] = (None, [quat(Z, 16 * math.sin(p + phase)) for p in phases])
        # The knee bends while the leg swings forward (its swing's velocity positive).
        keys[leg + "_knee"] = (None, [quat(Z, -20 * max(0.0, math.cos(p + phase)) ** 2) for p in phases])
    for k, name in enumerate(LIMBS["tail"]):
        keys[name] = (None, [quat(Y, (3 + k) * math.sin(p - 0.5 * k)) for p in phases])
    for k, name in enumerate(LIMBS["neck"][:3]):
        keys[name] = (None, [quat(Y, 2 * math.sin(p - 0.4 * (k + 1))) for p in phases])
    keys["Head"] = (None, [quat(Z, 3 * math.sin(2 * p)) for p in phases])
    times = [PERIOD * k / n for k in range(n + 1)]
    return times, keys


def keyed_pose_cache(positions, joints, weights, fps, frames, out):
    """The clip's own pose (linear blend skinning of the keys, looped; no part's motion) at frames
    k / fps, as a .pc2: the reference a bake's parts lag behind (sweep-preview.py --reference).
    Uses numpy (Debian's python3-numpy, as the preview does)."""
    import numpy as np
    times, keys = walk_keys()
    times = np.array(times)
    bind = np.array(positions)
    lbs_joints, lbs_weights = np.array(joints), np.array(weights)
    index = {name: j for j, (name, _, _, _) in enumerate(JOINTS)}

    def rotation(q):
        x, y, z, w = q
        return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])

    def sample(values, k, u, spherical):  # glTF's LINEAR: lerp, or slerp for rotations
        a, b = np.array(values[k], float), np.array(values[k + 1], float)
        if not spherical:
            return a + u * (b - a)
        if a @ b < 0:
            b = -b
        angle = math.acos(min(1.0, a @ b))
        if angle < 1e-12:
            return a
        return (math.sin((1 - u) * angle) * a + math.sin(u * angle) * b) / math.sin(angle)

    with open(out, "wb") as f:
        f.write(b"POINTCACHE2\0" + struct.pack("<iiffi", 1, len(positions), 0.0, 1.0, frames))
        for frame in range(frames):
            t = math.fmod(frame / fps, PERIOD)
            k = min(int(np.searchsorted(times, t, side="right")) - 1, len(times) - 2)
            u = (t - times[k]) / (times[k + 1] - times[k])
            world, skinning = [], []
            for name, parent, head, _ in JOINTS:
                local = np.eye(4)
                translation, turn = keys.get(name, (None, None))
                origin = (0.0, 0.0, 0.0) if parent is None else JOINTS[index[parent]][2]
                local[:3, 3] = sample(translation, k, u, False) if translation else np.subtract(head, origin)
                if turn:
                    local[:3, :3] = rotation(sample(turn, k, u, True))
                world.append(local if parent is None else world[index[parent]] @ local)
                inverse_bind = np.eye(4)
                inverse_bind[:3, 3] = np.negative(head)
                skinning.append(world[-1] @ inverse_bind)
            blend = np.einsum("vi,vijk->vjk", lbs_weights, np.array(skinning)[lbs_joints])
            pose = np.einsum("vjk,vk->vj", blend[:, :3, :3], bind) + blend[:, :3, 3]
            f.write(pose.astype("<f4").tobytes())


def main(off_path, out, keyed=None):
    positions, triangles = read_off(off_path)
    joints, weights = skin_weights(positions)
    if keyed is not None:
        keyed_pose_cache(positions, joints, weights, *keyed)
    times, keys = walk_keys()

    buf = bytearray()
    views, accessors = [], []

    def add(data, component, type_, count, extra=None):
        while len(buf) % 4:
            buf.append(0)
        views.append({"buffer": 0, "byteOffset": len(buf), "byteLength": len(data)})
        buf.extend(data)
        acc = {"bufferView": len(views) - 1, "componentType": component, "count": count, "type": type_}
        acc.update(extra or {})
        accessors.append(acc)
        return len(accessors) - 1

    def f32(values):
        return struct.pack("<%df" % len(values), *values)

    flat = [x for p in positions for x in p]
    lo = [min(flat[i::3]) for i in range(3)]
    hi = [max(flat[i::3]) for i in range(3)]
    # min/max as the float32 values stored, so a validator's recomputation agrees exactly.
    lo, hi = list(struct.unpack("<3f", f32(lo))), list(struct.unpack("<3f", f32(hi)))
    pos = add(f32(flat), 5126, "VEC3", len(positions), {"min": lo, "max": hi})
    jnt = add(struct.pack("<%dB" % (4 * len(joints)), *[j for js in joints for j in js]), 5121, "VEC4", len(joints))
    wgt = add(f32([w for ws in weights for w in ws]), 5126, "VEC4", len(weights))
    idx = add(struct.pack("<%dI" % (3 * len(triangles)), *[i for t in triangles for i in t]), 5125, "SCALAR",
              3 * len(triangles))
    ibm = add(f32([x for (_, _, h, _) in JOINTS for x in (1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -h[0], -h[1], -h[2], 1)]),
              5126, "MAT4", len(JOINTS))
    t32 = list(struct.unpack("<%df" % len(times), f32(times)))
    time_acc = add(f32(times), 5126, "SCALAR", len(times), {"min": [t32[0]], "max": [t32[-1]]})

    index = {name: j for j, (name, _, _, _) in enumerate(JOINTS)}
    samplers, channels = [], []
    for name, _, _, _ in JOINTS:
        if name not in keys:
            continue
        translation, rotation = keys[name]
        for path, values, type_ in (("translation", translation, "VEC3"), ("rotation", rotation, "VEC4")):
            if values is None:
                continue
            out_acc = add(f32([x for v in values for x in v]), 5126, type_, len(values))
            samplers.append({"input": time_acc, "output": out_acc, "interpolation": "LINEAR"})
            channels.append({"sampler": len(samplers) - 1, "target": {"node": index[name] + 1, "path": path}})

    nodes = [{"name": "Diplodocus", "mesh": 0, "skin": 0}]
    for name, parent, head, _ in JOINTS:
        origin = (0.0, 0.0, 0.0) if parent is None else JOINTS[index[parent]][2]
        node = {"name": name, "translation": [head[i] - origin[i] for i in range(3)]}
        children = [index[c] + 1 for c, p, _, _ in JOINTS if p == name]
        if children:
            node["children"] = children
        nodes.append(node)
    doc = {
        "asset": {"version": "2.0", "generator": "meshes/make_skinned_diplodocus.py"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": nodes,
        "meshes": [{"name": "Diplodocus", "primitives": [
            {"attributes": {"POSITION": pos, "JOINTS_0": jnt, "WEIGHTS_0": wgt}, "indices": idx}]}],
        "skins": [{"name": "Skeleton", "joints": list(range(1, len(JOINTS) + 1)), "inverseBindMatrices": ibm,
                   "skeleton": 1}],
        "animations": [{"name": "Walk", "samplers": samplers, "channels": channels}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(buf)}],
    }
    while len(buf) % 4:
        buf.append(0)
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    glb = struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(text) + 8 + len(buf))
    glb += struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(buf), b"BIN\0") + bytes(buf)
    with open(out, "wb") as f:
        f.write(glb)


if __name__ == "__main__":
    args = sys.argv[1:]
    if len(args) == 6 and args[2] == "--keyed":
        main(args[0], args[1], (float(args[3]), int(args[4]), args[5]))
    elif len(args) == 2:
        main(args[0], args[1])
    else:
        raise SystemExit(__doc__.split("\n\n")[-1])
