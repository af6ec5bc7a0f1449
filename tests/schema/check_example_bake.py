"""The bent-tube rig's own scene, baked by the real tools, is that scene played on that mesh:
as many .pc2 frames as the scene has (duration x fps + 1), frame 0 the mesh's own positions (its
`v` lines, in order, as float32), and the part moving (the last frame is not the rest pose), with
the vertices beyond the part untouched.

usage: check_example_bake.py RIG.json MESH.obj BAKE.pc2"""
import json
import math
import struct
import sys

rig_path, mesh_path, pc2_path = sys.argv[1:4]
scene = json.load(open(rig_path))["scene"]
frames = math.floor(scene["duration"] * scene["fps"] + 1e-9) + 1
mesh = [tuple(float(x) for x in line.split()[1:4]) for line in open(mesh_path) if line.startswith("v ")]
pc2 = open(pc2_path, "rb").read()
assert pc2[:12] == b"POINTCACHE2\0", "not a .pc2"
points, = struct.unpack_from("<i", pc2, 16)
samples, = struct.unpack_from("<i", pc2, 28)
assert points == len(mesh), f"{points} points, the mesh has {len(mesh)} vertices"
assert samples == frames, f"{samples} frames, the scene has {frames}"
assert len(pc2) == 32 + 12 * points * samples, "the file's size does not match its header"
def frame(k):
    return [struct.unpack_from("<3f", pc2, 32 + 12 * (points * k + v)) for v in range(points)]
f32 = lambda p: struct.unpack("<3f", struct.pack("<3f", *p))
first, last = frame(0), frame(samples - 1)
assert first == [f32(p) for p in mesh], "frame 0 is not the mesh's rest positions"
moved = sum(1 for a, b in zip(first, last) if a != b)
assert moved > 0, "nothing moved over the scene"
assert moved < points, "every vertex moved: the part's root side should stay put"
print(f"{samples} frames of {points} vertices; {moved} vertices moved by the last frame")
