"""tools/sweep-preview.py reads what the tools read, and --frames picks frames by number or by motion.
A .glb written here holds two meshes in a scene whose nodes show them in another order than the
file lists them (mesh 1 "BodyMesh" under node Body first, then mesh 0 "StickMesh" of two primitives
under node Stick): --mesh FILE.glb numbers its triangles as the tools read the whole file (the
scene's meshes where its nodes first show them, each's primitives in order, vertices one after
another), and --mesh RIG takes the meshes the rig's mesh_name names, in its order. The triangles are
checked against the numbering computed here, independently. --frames "0,3,9" is those frames,
"peak" frame 0 and where the largest displacement peaks; a frame the cache has not is exit 2,
named, no picture; so are a glTF whose vertex count is not the cache's and a format it cannot read.
Other formats go through the tools' own importer (sweep-fit --export-obj): on this .glb it must
give the same triangles as the script's glTF reader. Runs the script in this process (one
interpreter, matplotlib imported once).
Usage: preview_inputs.py REPO_ROOT WORK_DIR SWEEP_FIT"""
import contextlib
import importlib.util
import io
import json
import os
import struct
import sys

import numpy as np

root, work, sweep_fit = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
spec = importlib.util.spec_from_file_location("sweep_preview", os.path.join(root, "tools", "sweep-preview.py"))
preview = importlib.util.module_from_spec(spec)
spec.loader.exec_module(preview)

# Two meshes: a stick (two primitives: a strip of 4 quads and a cap fan) and a body (a box's 12
# triangles), their vertices at known places.
bin_ = b""
accessors, views = [], []


def add(array, component, kind, target):
    global bin_
    data = array.tobytes()
    views.append({"buffer": 0, "byteOffset": len(bin_), "byteLength": len(data), "target": target})
    accessors.append({"bufferView": len(views) - 1, "componentType": component, "count": len(array) // (3 if kind == "VEC3" else 1),
                      "type": kind})
    if kind == "VEC3":
        accessors[-1]["min"] = array.reshape(-1, 3).min(axis=0).tolist()
        accessors[-1]["max"] = array.reshape(-1, 3).max(axis=0).tolist()
    bin_ += data + b"\0" * ((4 - len(data) % 4) % 4)
    return len(accessors) - 1


def primitive(points, triangles, index_type):
    dtype = {5123: "<u2", 5125: "<u4"}[index_type]
    return {"attributes": {"POSITION": add(np.array(points, "<f4").ravel(), 5126, "VEC3", 34962)},
            "indices": add(np.array(triangles, dtype).ravel(), index_type, "SCALAR", 34963)}


strip = [(x, y, 0.0) for x in range(5) for y in (0, 1)]
strip_tris = [t for i in range(4) for t in ((2 * i, 2 * i + 2, 2 * i + 3), (2 * i, 2 * i + 3, 2 * i + 1))]
cap = [(4, 0.5, 0.5), (4, 0, 0), (4, 1, 0), (4, 1, 1)]
cap_tris = [(0, 1, 2), (0, 2, 3)]
box = [(x, y, z) for x in (-1, -2) for y in (0, 1) for z in (0, 1)]
box_tris = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1), (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4),
            (1, 5, 7), (1, 7, 3)]
doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
       "nodes": [{"name": "Root", "children": [1, 2]}, {"name": "Body", "mesh": 1}, {"name": "Stick", "mesh": 0}],
       "meshes": [{"name": "StickMesh", "primitives": [primitive(strip, strip_tris, 5125), primitive(cap, cap_tris, 5123)]},
                  {"name": "BodyMesh", "primitives": [primitive(box, box_tris, 5125)]}]}
doc.update(accessors=accessors, bufferViews=views, buffers=[{"byteLength": len(bin_)}])
text = json.dumps(doc).encode()
text += b" " * ((4 - len(text) % 4) % 4)
glb = os.path.join(work, "two.glb")
with open(glb, "wb") as f:
    f.write(b"glTF" + struct.pack("<II", 2, 12 + 8 + len(text) + 8 + len(bin_)))
    f.write(struct.pack("<I", len(text)) + b"JSON" + text + struct.pack("<I", len(bin_)) + b"BIN\0" + bin_)

# The numbering, computed here: pieces one after another, each's triangles shifted by what came before.
def numbered(pieces):
    out, base = [], 0
    for points, tris in pieces:
        out += [tuple(base + v for v in t) for t in tris]
        base += len(points)
    return np.array(out), base


body, stick_side, stick_cap = (box, box_tris), (strip, strip_tris), (cap, cap_tris)
whole, whole_count = numbered([body, stick_side, stick_cap])  # the scene shows Body first
faces, count = preview.read_faces(glb)
assert count == whole_count == 22 and np.array_equal(faces, whole), (count, faces[:3], whole[:3])


def rig(name, mesh_name):
    path = os.path.join(work, name)
    with open(path, "w") as f:
        json.dump({"format": "sweep-rig", "version": 4, "mesh": "two.glb", "mesh_name": mesh_name, "sweeps": []}, f)
    return path


listed, listed_count = numbered([stick_side, stick_cap, body])  # the rig's order: Stick, then Body
faces, count = preview.read_faces(rig("both.rig.json", ["Stick", "Body"]))
assert count == listed_count and np.array_equal(faces, listed), faces[:3]
faces, count = preview.read_faces(rig("mesh.rig.json", "StickMesh"))  # by its mesh's name
stick, stick_count = numbered([stick_side, stick_cap])
assert count == stick_count == 14 and np.array_equal(faces, stick)

# The tools' importer (what an FBX goes through) numbers them as the glTF reader does.
faces, count = preview.imported_faces(glb, ["Body", "Stick"], sweep_fit)
assert count == whole_count and np.array_equal(np.array(faces), whole), faces[:3]

# --frames: a count, a list, or the peaks of the largest displacement (local maxima, highest five).
largest = np.array([0, 1, 3, 2, 5, 4, 4, 6, 1, 0, 0.5, 0.2])
moved = np.stack([largest, largest / 2], axis=1)
assert preview.chosen_frames("peak", moved).tolist() == [0, 2, 4, 7, 10]
assert preview.chosen_frames("0,3,9", moved).tolist() == [0, 3, 9]
assert preview.chosen_frames("3", moved).tolist() == [0, 6, 11]
assert preview.chosen_frames("5,", moved).tolist() == [5]


def run(*args):
    """The script's main() on these arguments: its exit code and what it printed on stderr."""
    err = io.StringIO()
    sys.argv = ["sweep-preview.py", "--sweep-fit", sweep_fit, *args]
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = preview.main()
    return code, err.getvalue()


def cache(path, count, frames):
    with open(path, "wb") as f:
        f.write(b"POINTCACHE2\0" + struct.pack("<iiffi", 1, count, 0.0, 1.0, len(frames)))
        for frame in frames:
            f.write(np.asarray(frame, "<f4").tobytes())


rest = np.array(box + strip + cap, dtype=np.float64)
lifted = rest.copy()
lifted[8:, 2] += 0.5  # the stick rises, the body stays
pc2 = os.path.join(work, "two.pc2")
cache(pc2, len(rest), [rest, lifted, rest])
out = os.path.join(work, "two.png")
code, err = run(pc2, "-o", out, "--mesh", glb, "--frames", "peak", "--views", "xy", "--dpi", "40")
assert code == 0 and os.path.exists(out), (code, err)
for args, words in ((("--frames", "0,3"), "frame 3 is not in the cache (frames 0 to 2)"),
                    (("--frames", "many"), "expected a count, a list of frames or 'peak'"),
                    (("--mesh", rig("stick.rig.json", "Stick")), "it has 14 vertices, the cache has 22 points"),
                    (("--mesh", os.path.join(work, "two.fbx")), "two.fbx: no such file")):
    bad = os.path.join(work, "bad.png")
    code, err = run(pc2, "-o", bad, *args)
    assert code == 2 and words in err, (args, code, err)
    assert not os.path.exists(bad), f"a picture was written for {args}"
