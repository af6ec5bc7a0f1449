"""Opens a glTF asset and its passthrough bake in Blender and checks that the bake is the asset whole
and plays what sweep-sim baked.

Run by Blender (Debian's `blender` package, 3.4), not by Python:
    blender -b --factory-startup --python-exit-code 1 --python check_passthrough.py -- \
        INPUT.gltf BAKE.glb BAKE.pc2 FPS OBJECT
OBJECT is the name of the node whose mesh the bake deforms: the rig's mesh (its vertices are the
.pc2's, in its own space). INPUT may be an .obj (+ .mtl): its UVs are then compared as the
set of (position, UV) corners, and each .glb vertex is found in the .pc2 by its rest position.
  1. Both files through Blender's glTF importer: the same objects; the deformed object's UV layers
     (every loop's UV), vertex colours and materials equal the input's, and each material's image
     has the input's size and pixels.
  2. The bake plays: at time k / FPS (Blender frame 24·k / FPS) the evaluated object, in its own
     space, equals pc2 frame k (glTF axes: Blender (x, y, z) = glTF (x, -z, y)), and is told apart
     from frame k + 1.
  3. (a glTF INPUT) The .pc2 on the input's object as Blender imports it, through a Mesh Cache
     modifier with forward axis +Z and up axis -Y (the importer turns glTF's Y-up data to Blender's
     Z-up, (x, y, z) -> (x, -z, y); of the modifier's 24 axis settings only this one gives that, as
     measured in Blender 3.4): at Blender frame k the evaluated object, in world space, equals the
     .glb's at time k / FPS (step 2), within 1e-5 of the object's size, and is told apart from frame
     k + 1; every other object of the .glb (the Ground) is where the input has it at that time.
Prints one line per check; exits 1 on any failure.
"""
import struct
import sys

import numpy

numpy.bool = bool  # Debian's Blender 3.4 glTF importer still uses numpy.bool (removed in NumPy 1.24)

import bpy  # noqa: E402

args = sys.argv[sys.argv.index("--") + 1:]
input_path, glb_path, pc2_path, fps, name = args[0], args[1], args[2], float(args[3]), args[4]


def read_pc2(path):
    data = open(path, "rb").read()
    _, points, _, _, samples = struct.unpack("<iiffi", data[12:32])
    return numpy.frombuffer(data, dtype="<f4", offset=32).reshape(samples, points, 3).astype(numpy.float64)


def load(path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    return bpy.context.scene.objects


def describe(obj):
    """What the asset must keep: UVs, colours, materials and their images."""
    mesh = obj.data
    out = {"vertices": len(mesh.vertices), "uv": {}, "colours": {}, "materials": []}
    for layer in mesh.uv_layers:
        uv = numpy.empty(2 * len(mesh.loops), dtype=numpy.float32)
        layer.data.foreach_get("uv", uv)
        out["uv"][layer.name] = uv
    for layer in getattr(mesh, "color_attributes", []):
        c = numpy.empty(4 * len(layer.data), dtype=numpy.float32)
        layer.data.foreach_get("color", c)
        out["colours"][layer.name] = c
    for slot in obj.material_slots:
        m = slot.material
        images = []
        if m is not None and m.use_nodes:
            for node in m.node_tree.nodes:
                if node.type == "TEX_IMAGE" and node.image is not None:
                    px = numpy.empty(len(node.image.pixels), dtype=numpy.float32)
                    node.image.pixels.foreach_get(px)
                    images.append((tuple(node.image.size), px))
        out["materials"].append((m.name if m else None, images))
    return out


def evaluated_positions(obj, frame, world=True):
    """The evaluated mesh at `frame`, in world space or (world False) the object's own."""
    whole = int(frame)
    bpy.context.scene.frame_set(whole, subframe=frame - whole)
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    co = numpy.empty(3 * len(mesh.vertices), dtype=numpy.float32)
    mesh.vertices.foreach_get("co", co)
    evaluated.to_mesh_clear()
    co = co.reshape(-1, 3).astype(numpy.float64)
    if not world:
        return co
    m = numpy.array(evaluated.matrix_world)
    return co @ m[:3, :3].T + m[:3, 3]


passed = True


def report(ok, what):
    global passed
    passed &= bool(ok)
    print(f"{'ok  ' if ok else 'FAIL'} {what}")


def corners(obj, to_file_axes):
    """Every face corner as (position, UV), rounded: an OBJ and its .glb order their loops apart."""
    mesh = obj.data
    co = numpy.array([v.co[:] for v in mesh.vertices])
    co = to_file_axes(co)
    uv = mesh.uv_layers[0].data
    return sorted({(tuple(numpy.round(co[loop.vertex_index], 5)), tuple(numpy.round(uv[loop.index].uv[:], 5)))
                   for loop in mesh.loops})


from_obj = input_path.lower().endswith(".obj")
if from_obj:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.obj_import(filepath=input_path, forward_axis="Y", up_axis="Z")
    source = [o for o in bpy.context.scene.objects if o.type == "MESH"][0]
    want = describe(source)
    want_corners = corners(source, lambda p: p)
    load(glb_path)
    obj = bpy.context.scene.objects[name]
    got = describe(obj)
    got_corners = corners(obj, lambda p: numpy.stack([p[:, 0], p[:, 2], -p[:, 1]], axis=1))
    report(got_corners == want_corners and len(want_corners) > 0,
           f"{name}: {len(got_corners)} (position, UV) corners equal the OBJ's as Blender imports it")
    want["materials"] = sorted(want["materials"], key=lambda m: m[0] or "")
    got["materials"] = sorted(got["materials"], key=lambda m: m[0] or "")
else:
    objects_in = sorted(o.name for o in load(input_path))
    want = describe(bpy.context.scene.objects[name])
    objects_out = sorted(o.name for o in load(glb_path))
    report(objects_in == objects_out, f"objects {objects_out} (input: {objects_in})")
    obj = bpy.context.scene.objects[name]
    got = describe(obj)
    report(got["vertices"] == want["vertices"], f"{name}: {got['vertices']} vertices (input {want['vertices']})")
    report(got["uv"].keys() == want["uv"].keys() and len(want["uv"]) > 0 and
           all(numpy.array_equal(got["uv"][k], want["uv"][k]) for k in want["uv"]),
           f"{name}: UV layers {list(got['uv'])} equal the input's, every loop")
    report(got["colours"].keys() == want["colours"].keys() and
           all(numpy.array_equal(got["colours"][k], want["colours"][k]) for k in want["colours"]),
           f"{name}: colour attributes {list(got['colours'])} equal the input's")
same_materials = [g[0] for g in got["materials"]] == [w[0] for w in want["materials"]]
same_images = all(len(g[1]) == len(w[1]) and all(a[0] == b[0] and numpy.array_equal(a[1], b[1]) for a, b in zip(g[1], w[1]))
                  for g, w in zip(got["materials"], want["materials"]))
images = sum(len(w[1]) for w in want["materials"])
report(same_materials and same_images and images > 0,
       f"{name}: materials {[g[0] for g in got['materials']]} and their {images} image(s) (size, pixels) equal the input's")

# 2. The animation that plays the bake: the importer makes the morph targets shape keys and the
# weights channel an action on them.
keys = obj.data.shape_keys
if keys is not None and (keys.animation_data is None or keys.animation_data.action is None):
    actions = [a for a in bpy.data.actions if "sweep bake" in a.name and any("key_blocks" in f.data_path for f in a.fcurves)]
    if actions:
        keys.animation_data_create().action = actions[0]
reference = read_pc2(pc2_path)
count = len(obj.data.vertices)
samples = len(reference)
# Which .pc2 vertex each Blender vertex is: the same one, or (an OBJ, split at seams) the one at its
# rest position. Both in the object's own space.
rest = numpy.stack([v.co[:] for v in obj.data.vertices])
rest = numpy.stack([rest[:, 0], rest[:, 2], -rest[:, 1]], axis=1)
if from_obj:
    at = {tuple(numpy.round(p, 5)): i for i, p in enumerate(reference[0])}
    index = numpy.array([at.get(tuple(numpy.round(p, 5)), 0) for p in rest])
else:
    index = numpy.arange(count)
size = float(numpy.linalg.norm(reference[0][index].max(axis=0) - reference[0][index].min(axis=0)))
worst, nearest_other = 0.0, float("inf")
glb_world = []  # the .glb's object in world space, Blender axes, at each frame: step 3's reference
glb_others = []  # the .glb's other mesh objects, likewise
for k in range(samples):
    glb_world.append(evaluated_positions(obj, 24.0 * k / fps))
    glb_others.append({o.name: evaluated_positions(o, 24.0 * k / fps)
                       for o in bpy.context.scene.objects if o.type == "MESH" and o.name != name})
    p = evaluated_positions(obj, 24.0 * k / fps, world=False)
    p = numpy.stack([p[:, 0], p[:, 2], -p[:, 1]], axis=1)  # Blender → glTF axes
    worst = max(worst, numpy.abs(p - reference[k][index]).max())
    if k + 1 < samples and numpy.abs(reference[k + 1][index] - reference[k][index]).max() > 0:
        nearest_other = min(nearest_other, numpy.abs(p - reference[k + 1][index]).max())
tolerance = 1e-5 * size
report(worst <= tolerance < nearest_other < float("inf"),
       f"{name}: {samples} frames play the bake, largest difference {worst:.3g} (tolerance {tolerance:.3g}; "
       f"the next frame is {nearest_other:.3g} away)")

# 3. The .pc2 on the object Blender imports from the input (a glTF: it is in the object's own space,
# glTF axes), through the Mesh Cache modifier; the other objects untouched.
if not from_obj:
    load(input_path)
    target = bpy.context.scene.objects[name]
    others = [o for o in bpy.context.scene.objects if o.type == "MESH" and o.name != name]
    cache = target.modifiers.new("bake", "MESH_CACHE")
    cache.cache_format = "PC2"
    cache.filepath = pc2_path
    cache.frame_start = 0
    cache.frame_scale = 1
    cache.forward_axis = "POS_Z"
    cache.up_axis = "NEG_Y"
    worst, nearest_other, others_moved = 0.0, float("inf"), 0.0
    for k in range(samples):
        p = evaluated_positions(target, k)
        if p.shape != glb_world[k].shape:
            report(False, f"{name}: frame {k}: {p.shape[0]} vertices with the Mesh Cache, the .glb's object has {glb_world[k].shape[0]}")
            break
        worst = max(worst, numpy.abs(p - glb_world[k]).max())
        if k + 1 < samples and numpy.abs(glb_world[k + 1] - glb_world[k]).max() > 0:
            nearest_other = min(nearest_other, numpy.abs(p - glb_world[k + 1]).max())
        for other in others:
            input_other = evaluated_positions(other, 24.0 * k / fps)
            others_moved = max(others_moved, numpy.abs(input_other - glb_others[k][other.name]).max())
    report(worst <= tolerance < nearest_other < float("inf"),
           f"{name}: the .pc2 through a Mesh Cache modifier on the input's object, {samples} frames, equals the "
           f".glb in world space: largest difference {worst:.3g} (tolerance {tolerance:.3g}; the next frame is "
           f"{nearest_other:.3g} away)")
    report(others_moved == 0.0 and len(others) > 0,
           f"the .glb's other objects {sorted(o.name for o in others)} are where the input has them, every "
           f"frame (largest difference {others_moved:.3g})")
print("blender check: " + ("passed" if passed else "FAILED"))
sys.exit(0 if passed else 1)
