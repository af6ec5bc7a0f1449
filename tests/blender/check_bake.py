"""Opens a bake in Blender and checks that it plays what sweep-sim baked.

Run by Blender (Debian's `blender` package, 3.4), not by Python:
    blender -b --factory-startup --python-exit-code 1 --python check_bake.py -- MESH BAKE.glb BAKE.pc2 [FPS]
        [--skinned TOLERANCE]
MESH is the baked mesh as .obj or .off (the .pc2 check puts the cache on it); FPS the bake's frame
rate (default 24). With --skinned, BAKE.glb is a skinned bake (sweep-sim --joints): Blender plays it
through the armature its importer builds, and each sampled frame must match the .pc2 within
TOLERANCE (mesh units: the error sweep-sim reported, skin_error_max_relative times the part's
length) instead of exactly.

The .pc2 is the reference: sweep-sim's own tests prove it equals the simulator's frames bit for bit.
  1. The .glb, imported with Blender's glTF importer: at time k / FPS (Blender frame 24·k / FPS, the
     importer's time base) the evaluated mesh (morph targets as shape keys, driven by the weights
     animation) must equal pc2 frame k, in glTF axes.
  2. The .pc2 on the input mesh through Blender's Mesh Cache modifier: at frame k the evaluated mesh
     must equal pc2 frame k.
Each check also asserts that it can tell frame k from frame k + 1 (a wrong time base would pass a
check that cannot). Prints one line per check; exits 1 on any failure.
"""
import struct
import sys

import numpy

numpy.bool = bool  # Debian's Blender 3.4 glTF importer still uses numpy.bool (removed in NumPy 1.24)

import bpy  # noqa: E402  (after the NumPy fix, which the importer needs when it loads)

args = sys.argv[sys.argv.index("--") + 1:]
skinned_tolerance = None
if "--skinned" in args:
    at = args.index("--skinned")
    skinned_tolerance = float(args[at + 1])
    del args[at:at + 2]
mesh_path, glb_path, pc2_path = args[:3]
fps = float(args[3]) if len(args) > 3 else 24.0


def read_pc2(path):
    data = open(path, "rb").read()
    if data[:12] != b"POINTCACHE2\0":
        raise SystemExit(f"{path}: not a PC2 file")
    _, points, _, _, samples = struct.unpack("<iiffi", data[12:32])
    return numpy.frombuffer(data, dtype="<f4", offset=32).reshape(samples, points, 3).astype(numpy.float64)


def evaluated_positions(obj, frame):
    """World-space positions of `obj`'s evaluated mesh at (fractional) `frame`, in mesh order."""
    whole = int(frame)
    bpy.context.scene.frame_set(whole, subframe=frame - whole)
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    co = numpy.empty(3 * len(mesh.vertices), dtype=numpy.float32)
    mesh.vertices.foreach_get("co", co)
    evaluated.to_mesh_clear()
    co = co.reshape(-1, 3).astype(numpy.float64)
    m = numpy.array(obj.matrix_world)
    return co @ m[:3, :3].T + m[:3, 3]


def off_object(path):
    """An OFF mesh (which Blender 3.4 does not import) as an object, vertices in file order."""
    tokens = [t for line in open(path) for t in line.split("#")[0].split()]
    if tokens[0] != "OFF":
        raise SystemExit(f"{path}: not an OFF file")
    nv, nf = int(tokens[1]), int(tokens[2])
    values = tokens[4:]
    verts = [tuple(map(float, values[3 * i:3 * i + 3])) for i in range(nv)]
    faces, at = [], 3 * nv
    for _ in range(nf):
        n = int(values[at])
        faces.append([int(x) for x in values[at + 1:at + 1 + n]])
        at += 1 + n
    mesh = bpy.data.meshes.new("mesh")
    mesh.from_pydata(verts, [], faces)
    obj = bpy.data.objects.new("mesh", mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def only_mesh_object():
    meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    if len(meshes) != 1:
        raise SystemExit(f"expected one mesh object, found {len(meshes)}")
    return meshes[0]


def check(name, obj, reference, to_reference_axes, frames, blender_frame, size, tolerance=None):
    """Largest distance between Blender at blender_frame(k) and reference frame k, over `frames`.

    Exact files (tolerance None) must match to float precision, and be farther than that from
    frame k + 1. A skinned file matches only within `tolerance` (mesh units), which may exceed the
    motion of one frame: its time base is checked instead by RMS distance, Blender's frame k being
    nearer to reference frame k than to frame k + 3."""
    skinned = tolerance is not None
    step = 3 if skinned else 1
    worst, nearest_other = 0.0, float("inf")
    for k in frames:
        got = to_reference_axes(evaluated_positions(obj, blender_frame(k)))
        if got.shape != reference[k].shape:
            print(f"FAIL {name}: frame {k}: {got.shape[0]} vertices, the bake has {reference[k].shape[0]}")
            return False
        worst = max(worst, numpy.abs(got - reference[k]).max())
        if skinned:
            if k + step < len(reference) and numpy.abs(reference[k + step] - reference[k]).max() > 0:
                here = numpy.sqrt(((got - reference[k]) ** 2).sum(axis=1).mean())
                there = numpy.sqrt(((got - reference[k + step]) ** 2).sum(axis=1).mean())
                nearest_other = min(nearest_other, there / max(here, 1e-30))
        elif k + 1 < len(reference) and numpy.abs(reference[k + 1] - reference[k]).max() > 0:
            nearest_other = min(nearest_other, numpy.abs(got - reference[k + 1]).max())
    if skinned:
        limit = tolerance + 1e-6 * size
        # nearest_other: over the sampled moving frames, the least ratio of the RMS distance to
        # frame k + 3 over the RMS distance to frame k; above 1 when the time base is right.
        ok = worst <= limit and 1.0 < nearest_other < float("inf")
        print(f"{'ok  ' if ok else 'FAIL'} {name}: {len(frames)} frames, largest difference {worst:.3g} "
              f"(tolerance {limit:.3g}: the error sweep-sim reported); frame k + 3 is at least "
              f"{nearest_other:.3g}x farther in RMS than frame k")
        return ok
    tolerance = 1e-6 * size
    # nearest_other stays infinite when no sampled frame differs from the next: then the check
    # could not tell a wrong time base from a right one, and fails.
    ok = worst <= tolerance < nearest_other < float("inf")
    print(f"{'ok  ' if ok else 'FAIL'} {name}: {len(frames)} frames, largest difference {worst:.3g} "
          f"(tolerance {tolerance:.3g}; the next frame is {nearest_other:.3g} away)")
    return ok


reference = read_pc2(pc2_path)
samples = len(reference)
frames = sorted({0, 1, 2, samples // 4, samples // 3, samples // 2, samples - 2})
size = float(numpy.linalg.norm(reference[0].max(axis=0) - reference[0].min(axis=0)))
passed = True

# 1. The .glb through Blender's glTF importer: Blender (x, y, z) = glTF (x, -z, y).
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=glb_path)
glb_object = only_mesh_object()
bpy.context.scene.frame_start, bpy.context.scene.frame_end = 0, samples - 1
if skinned_tolerance is not None:
    armatures = [m for m in glb_object.modifiers if m.type == "ARMATURE"]
    if not armatures or glb_object.data.shape_keys is not None:
        print(f"FAIL skinned glb: expected an armature and no shape keys, got modifiers "
              f"{[m.type for m in glb_object.modifiers]}, shape keys {glb_object.data.shape_keys}")
        passed = False
    else:
        print(f"ok   skinned glb: armature with {len(armatures[0].object.data.bones)} bones, no shape keys")
passed &= check("glb via the glTF importer" + (" (skinned)" if skinned_tolerance is not None else ""),
                glb_object, reference,
                lambda p: numpy.stack([p[:, 0], p[:, 2], -p[:, 1]], axis=1), frames,
                lambda k: 24.0 * k / fps, size, skinned_tolerance)

# 2. The .pc2 on the input mesh through the Mesh Cache modifier (axes as in the file).
bpy.ops.wm.read_factory_settings(use_empty=True)
if mesh_path.lower().endswith(".off"):
    mesh_object = off_object(mesh_path)
else:
    bpy.ops.wm.obj_import(filepath=mesh_path, forward_axis="Y", up_axis="Z")
    mesh_object = only_mesh_object()
cache = mesh_object.modifiers.new("bake", "MESH_CACHE")
cache.cache_format = "PC2"
cache.filepath = pc2_path
cache.frame_start = 0
cache.frame_scale = 1
passed &= check("pc2 via the Mesh Cache modifier", mesh_object, reference, lambda p: p, frames,
                lambda k: k, size)

print("blender check: " + ("passed" if passed else "FAILED"))
sys.exit(0 if passed else 1)
