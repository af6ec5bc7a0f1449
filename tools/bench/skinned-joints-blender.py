"""Blender plays a skinned character's joints .glb (sweep-sim's default for a skinned clip): imports it,
plays its "sweep bake" action at the bake's fps and compares every frame's evaluated vertices with the
bake's .pc2, over the vertices that move off their rest most (the parts) and over all.
    blender -b --python tools/bench/skinned-joints-blender.py -- bake.glb bake.pc2 FPS [PART_LENGTH]"""
import struct
import sys

import numpy

numpy.bool = bool  # Debian's Blender 3.4 glTF importer still uses numpy.bool (removed in NumPy 1.24)
import bpy  # noqa: E402

args = sys.argv[sys.argv.index("--") + 1:]
glb, pc2_path, fps = args[0], args[1], float(args[2])
length = float(args[3]) if len(args) > 3 else 1.0


def read_pc2(path):
    data = open(path, "rb").read()
    _, points, _, _, samples = struct.unpack("<iiffi", data[12:32])
    return numpy.frombuffer(data[32:], "<f4").reshape(samples, points, 3).astype(float)


def to_blender(a):  # glTF's y up to Blender's z up, as the importer turns the mesh
    return numpy.stack([a[..., 0], -a[..., 2], a[..., 1]], axis=-1)


bake = read_pc2(pc2_path)
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.fps, scene.render.fps_base = int(round(fps)), 1.0  # before importing: the importer keys at it
bpy.ops.import_scene.gltf(filepath=glb)
obj = [o for o in scene.objects if o.type == "MESH"][0]
armature = [o for o in scene.objects if o.type == "ARMATURE"][0]
actions = [a.name for a in bpy.data.actions]
action = next(a for a in bpy.data.actions if a.name.startswith("sweep bake"))
armature.animation_data.action = action
print(f"{obj.name}: {len(obj.data.vertices)} vertices, {len(armature.data.bones)} bones, actions {actions}; playing {action.name}")


def evaluated(frame):
    whole = int(frame)
    scene.frame_set(whole, subframe=frame - whole)
    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = ev.to_mesh()
    co = numpy.empty(3 * len(mesh.vertices), numpy.float32)
    mesh.vertices.foreach_get("co", co)
    ev.to_mesh_clear()
    world = numpy.array(ev.matrix_world)
    return co.reshape(-1, 3).astype(float) @ world[:3, :3].T + world[:3, 3]


start = action.frame_range[0]  # the importer's frame of time 0
want = to_blender(bake)
moved = numpy.linalg.norm(want - want[:1], axis=-1).max(axis=0)
worst = 0.0
for k in range(len(bake)):
    got = evaluated(start + k * scene.render.fps / fps)
    if got.shape[0] > want.shape[1]:  # a .glb made from FBX, Collada, ...: the mesh's vertices first, then copies
        got = got[:want.shape[1]]      # split at UV seams and hard edges (obj_gltf.h)
    if got.shape != want[k].shape:
        sys.exit(f"{got.shape[0]} vertices evaluated, the .pc2 has {want.shape[1]}")
    worst = max(worst, numpy.linalg.norm(got - want[k], axis=-1).max())
print(f"frames 0..{len(bake) - 1}: largest distance of Blender's evaluated vertices from the .pc2 "
      f"{worst:.4g} = {worst / length:.4g} of the part's length {length:g} (vertices move up to {moved.max():.4g})")
