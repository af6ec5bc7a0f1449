#!/usr/bin/env python3
"""Writes meshes/skinned_tail.gltf: a skinned creature for the skinned-clip tests.

A box body (z from -0.6 to -0.05) and a tail: the straight tube of the binding tests (length 1 along
+z from the origin, radius 0.1, 41 rings of 24 vertices every 0.025, then the root and tip cap
centres), skinned to a skeleton Hip -> Tail1 -> Tail2 -> Tail3 (joints at z = -0.3, 0, 0.33, 0.66).
Weights: the body on Hip (its front face shared with Tail1, 0.6 / 0.4); the tail on Tail1 alone up
to z = 0.1, then blended two by two (hat functions peaking at 0.1, 0.4 and 0.75). A node "Eye" is
no joint. Clips:
  Walk (1 s, loops): Hip bobs and sways (translation, LINEAR) and turns about y (0, 15, 0, -15, 0
       degrees, LINEAR); Tail1 sways about x (-10, 10, -10 degrees, CUBICSPLINE with tangents);
       Tail2 about x (-15 then 15 degrees, STEP); Tail3 about y (0, 20, 0 degrees, LINEAR).
  Blink: moves only Eye.
Run: python3 meshes/make_skinned_tail.py meshes/skinned_tail.gltf  (deterministic bytes)."""
import base64
import json
import math
import struct
import sys


def quat_axis(axis, degrees):
    h = math.radians(degrees) / 2
    s = math.sin(h)
    return [axis[0] * s, axis[1] * s, axis[2] * s, math.cos(h)]


def f32(values):
    return struct.pack("<%df" % len(values), *values)


def main(out):
    positions, joints, weights = [], [], []

    def tail_weights(z):
        w1 = 1.0 if z <= 0.1 else max(0.0, (0.4 - z) / 0.3)
        w2 = 0.0 if z <= 0.1 else ((z - 0.1) / 0.3 if z <= 0.4 else max(0.0, (0.75 - z) / 0.35))
        w3 = 0.0 if z <= 0.4 else min(1.0, (z - 0.4) / 0.35)
        return [1, 2, 3, 0], [w1, w2, w3, 0.0]

    rings, segments, radius = 41, 24, 0.1
    for r in range(rings):
        z = r / (rings - 1)
        for s in range(segments):
            a = 2 * math.pi * s / segments
            positions += [radius * math.cos(a), radius * math.sin(a), z]
            j, w = tail_weights(z)
            joints += j
            weights += w
    for z in (0.0, 1.0):  # cap centres
        positions += [0.0, 0.0, z]
        j, w = tail_weights(z)
        joints += j
        weights += w
    tail_count = len(positions) // 3
    body = tail_count
    for z in (-0.6, -0.05):
        for y in (-0.25, 0.25):
            for x in (-0.25, 0.25):
                positions += [x, y, z]
                joints += [0, 1, 0, 0]
                weights += [1.0, 0.0, 0.0, 0.0] if z < -0.3 else [0.6, 0.4, 0.0, 0.0]
    count = len(positions) // 3
    indices = []
    for r in range(rings - 1):
        for s in range(segments):
            a, b = r * segments + s, r * segments + (s + 1) % segments
            indices += [a, b, b + segments, a, b + segments, a + segments]
    root, tip = rings * segments, rings * segments + 1
    for s in range(segments):
        indices += [root, (s + 1) % segments, s]
        last = (rings - 1) * segments
        indices += [tip, last + s, last + (s + 1) % segments]
    box = [(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4),
           (2, 6, 7), (2, 7, 3), (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)]
    for t in box:
        indices += [body + t[0], body + t[1], body + t[2]]

    joint_z = [-0.3, 0.0, 0.33, 0.66]
    ibms = []
    for z in joint_z:  # inverse of a translation by (0, 0, z), column-major
        ibms += [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -z, 1]

    buf = bytearray()
    views, accessors = [], []

    def add(data, component, type_, count_, extra=None):
        while len(buf) % 4:
            buf.append(0)
        views.append({"buffer": 0, "byteOffset": len(buf), "byteLength": len(data)})
        buf.extend(data)
        acc = {"bufferView": len(views) - 1, "componentType": component, "count": count_, "type": type_}
        if extra:
            acc.update(extra)
        accessors.append(acc)
        return len(accessors) - 1

    xs, ys, zs = positions[0::3], positions[1::3], positions[2::3]
    pos = add(f32(positions), 5126, "VEC3", count,
              {"min": [min(xs), min(ys), min(zs)], "max": [max(xs), max(ys), max(zs)]})
    jnt = add(struct.pack("<%dB" % len(joints), *joints), 5121, "VEC4", count)
    wgt = add(f32(weights), 5126, "VEC4", count)
    idx = add(struct.pack("<%dI" % len(indices), *indices), 5125, "SCALAR", len(indices))
    ibm = add(f32(ibms), 5126, "MAT4", len(joint_z))

    samplers, channels = [], []

    def channel(node, path, times, values, interpolation, width):
        t = add(f32(times), 5126, "SCALAR", len(times), {"min": [times[0]], "max": [times[-1]]})
        flat = [x for v in values for x in v]
        v = add(f32(flat), 5126, "VEC4" if width == 4 else "VEC3", len(values))
        samplers.append({"input": t, "output": v, "interpolation": interpolation})
        channels.append({"sampler": len(samplers) - 1, "target": {"node": node, "path": path}})

    X, Y = (1, 0, 0), (0, 1, 0)
    channel(1, "translation", [0, 0.25, 0.5, 0.75, 1],
            [[0, 0, -0.3], [0.03, 0.04, -0.3], [0, 0, -0.3], [-0.03, 0.04, -0.3], [0, 0, -0.3]], "LINEAR", 3)
    channel(1, "rotation", [0, 0.25, 0.5, 0.75, 1], [quat_axis(Y, d) for d in (0, 15, 0, -15, 0)], "LINEAR", 4)
    q = [quat_axis(X, d) for d in (-10, 10, -10)]
    tangents = [([0, 0, 0, 0], [0.4, 0, 0, 0]), ([-0.2, 0, 0, 0], [-0.2, 0, 0, 0]), ([0.4, 0, 0, 0], [0, 0, 0, 0])]
    cubic = []
    for k in range(3):
        cubic += [tangents[k][0], q[k], tangents[k][1]]
    channel(2, "rotation", [0, 0.5, 1], cubic, "CUBICSPLINE", 4)
    channel(3, "rotation", [0, 0.5], [quat_axis(X, -15), quat_axis(X, 15)], "STEP", 4)
    channel(4, "rotation", [0, 0.5, 1], [quat_axis(Y, d) for d in (0, 20, 0)], "LINEAR", 4)
    walk = {"name": "Walk", "samplers": samplers, "channels": channels}
    samplers, channels = [], []
    channel(5, "translation", [0, 1], [[0, 0.5, 0], [0, 0.6, 0]], "LINEAR", 3)
    blink = {"name": "Blink", "samplers": samplers, "channels": channels}

    doc = {
        "asset": {"version": "2.0", "generator": "meshes/make_skinned_tail.py"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 5]}],
        "nodes": [
            {"name": "Creature", "mesh": 0, "skin": 0},
            {"name": "Hip", "translation": [0, 0, -0.3], "children": [2]},
            {"name": "Tail1", "translation": [0, 0, 0.3], "children": [3]},
            {"name": "Tail2", "translation": [0, 0, 0.33], "children": [4]},
            {"name": "Tail3", "translation": [0, 0, 0.33]},
            {"name": "Eye", "translation": [0, 0.5, 0]},
        ],
        "meshes": [{"name": "Creature", "primitives": [
            {"attributes": {"POSITION": pos, "JOINTS_0": jnt, "WEIGHTS_0": wgt}, "indices": idx}]}],
        "skins": [{"name": "Skeleton", "joints": [1, 2, 3, 4], "inverseBindMatrices": ibm, "skeleton": 1}],
        "animations": [walk, blink],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(buf),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buf)).decode()}],
    }
    with open(out, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "skinned_tail.gltf")
