"""Blender plays the rigged diplodocus and its bake: imports the rigged .glb, compares the armature's
pose to the pose the clip keys (make_skinned_diplodocus.py --keyed), then replaces the Armature
modifier by a Mesh Cache modifier reading the bake's .pc2 and compares it to the bake.
    blender -b --python tools/bench/skinned-walk-blender.py -- out/diplodocus-skinned.glb \\
        out/diplodocus-walk.pc2 out/diplodocus-walk.keyed.pc2"""
import struct
import sys

import numpy

numpy.bool = bool  # Debian's Blender 3.4 glTF importer still uses numpy.bool (removed in NumPy 1.24)
import bpy  # noqa: E402

glb, bake_path, keyed_path = sys.argv[sys.argv.index("--") + 1:]


def read_pc2(path):
    data = open(path, "rb").read()
    _, points, _, _, samples = struct.unpack("<iiffi", data[12:32])
    return numpy.frombuffer(data[32:], "<f4").reshape(samples, points, 3).astype(float)


def to_blender(a):  # glTF's y up to Blender's z up, as the importer turns the mesh
    return numpy.stack([a[..., 0], -a[..., 2], a[..., 1]], axis=-1)


def evaluated(obj, frame):
    whole = int(frame)
    bpy.context.scene.frame_set(whole, subframe=frame - whole)
    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = ev.to_mesh()
    co = numpy.empty(3 * len(mesh.vertices), numpy.float32)
    mesh.vertices.foreach_get("co", co)
    ev.to_mesh_clear()
    world = numpy.array(ev.matrix_world)
    return co.reshape(-1, 3).astype(float) @ world[:3, :3].T + world[:3, 3]


bake, keyed = read_pc2(bake_path), read_pc2(keyed_path)
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=glb)
obj = [o for o in bpy.context.scene.objects if o.type == "MESH"][0]
fps = bpy.context.scene.render.fps
print(f"{obj.name}: {len(obj.data.vertices)} vertices, modifiers {[m.type for m in obj.modifiers]}, "
      f"actions {[a.name for a in bpy.data.actions]}")
# The imported action plays once (1.2 s, 36 frames at 30 fps); the keyed pose loops it.
frames = range(0, len(keyed), 9)
once = [k for k in frames if k <= 36]
worst = max(numpy.abs(evaluated(obj, fps * k / 30) - to_blender(keyed[k])).max() for k in once)
print(f"the armature plays the clip once: largest difference from the keyed pose {worst:.3g} (frames {once})")
for m in list(obj.modifiers):
    if m.type == "ARMATURE":
        obj.modifiers.remove(m)
cache = obj.modifiers.new("bake", "MESH_CACHE")
cache.cache_format, cache.filepath, cache.frame_start, cache.frame_scale = "PC2", bake_path, 0, 1
cache.forward_axis, cache.up_axis = "POS_Z", "NEG_Y"
worst = max(numpy.abs(evaluated(obj, k) - to_blender(bake[k])).max() for k in frames)
print(f"the .pc2 through a Mesh Cache modifier in place of the armature: largest difference from the bake {worst:.3g}")
