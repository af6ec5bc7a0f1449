#!/usr/bin/python3
"""Preview a bake as a PNG contact sheet: a few frames of a .pc2 point cache, seen from the side and
from above, coloured by how far each point has moved from where the body's own rigid motion would
have carried it from frame 0 (on a still body: from frame 0). With --mesh (the mesh the bake
deforms, its vertices in the cache's order: an .off, .obj, .gltf or .glb file, any other format the
tools read (FBX, Collada, ...: through sweep-fit --export-obj, the tools' own importer), or the rig
the bake was made from, which names its mesh file and which meshes of it) the frames are shaded
surfaces: each
triangle lit from the viewer and a key light, the still body grey, the moving part in the colour of
its displacement, drawn back to front; without it, points. With --report (sweep-sim's JSON report)
a last panel plots the largest displacement over time; with --scene, the scene's colliders are
drawn in grey where they are in the world (those carried by a moving body, at its rest place). With
--reference (a cache of the same points and frames: the pose a skinned character's clip keys, without
the parts' motion) the colour is each point's distance from its place in the reference's frame, so a
walking character's legs stay grey and its tail and neck show how far they lag the keyed pose.
--frames gives how many frames (evenly spread), which ones ("0,12,40"), or "peak": frame 0 and the
frames at which the largest displacement peaks (the five highest of its local maxima, in time order).

    tools/sweep-preview.py out/diplodocus.pc2 -o out/diplodocus.png --mesh diplodocus.off \
        --report out/report.json

Uses Debian's python3-matplotlib and python3-numpy (tools/setup-deps.sh installs them).
Exit codes: 0 done, 2 bad input, 4 cannot write the picture.
"""
import argparse
import json
import os
import struct
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_pc2(path):
    """The PC2 layout: 'POINTCACHE2\\0', int32 version, int32 points, float32 start, float32 rate,
    int32 samples, then float32 xyz per point per sample, little-endian."""
    with open(path, "rb") as f:
        header = f.read(32)
        if len(header) < 32 or header[:12] != b"POINTCACHE2\0":
            raise ValueError("not a PC2 point cache (bad header)")
        _version, points, _start, _rate, samples = struct.unpack("<iiffi", header[12:32])
        data = np.frombuffer(f.read(), dtype="<f4")
    if points <= 0 or samples <= 0 or data.size != points * samples * 3:
        raise ValueError(f"truncated: header says {samples} samples of {points} points")
    return data.reshape(samples, points, 3)


def obj_off_faces(path):
    """The triangles of an .off or .obj mesh (polygons fanned), as vertex index triples."""
    ext = os.path.splitext(path)[1].lower()
    faces = []
    with open(path) as f:
        if ext == ".off":
            words = []
            for line in f:
                line = line.split("#")[0].split()
                if line:
                    words.append(line)
            head = words[0]
            counts = head[1:] if head[0].endswith("OFF") and len(head) > 1 else words[1]
            first = 1 if len(head) > 1 else 2
            nv, nf = int(counts[0]), int(counts[1])
            for row in words[first + nv:first + nv + nf]:
                k = int(row[0])
                idx = [int(x) for x in row[1:1 + k]]
                faces += [(idx[0], idx[i], idx[i + 1]) for i in range(1, k - 1)]
        else:
            for line in f:
                if line.startswith("f "):
                    idx = [int(w.split("/")[0]) - 1 for w in line.split()[1:]]
                    faces += [(idx[0], idx[i], idx[i + 1]) for i in range(1, len(idx) - 1)]
    return faces, None


def gltf_document(path):
    """A .gltf's or .glb's JSON and its buffers' bytes (a .glb's BIN chunk, data URIs, files beside)."""
    data = open(path, "rb").read()
    binary = None
    if data[:4] == b"glTF":
        length, = struct.unpack("<I", data[12:16])
        doc = json.loads(data[20:20 + length])
        at = 20 + length
        if at + 8 <= len(data):
            size, = struct.unpack("<I", data[at:at + 4])
            binary = data[at + 8:at + 8 + size]
    else:
        doc = json.loads(data)
    buffers = []
    for k, b in enumerate(doc.get("buffers", [])):
        uri = b.get("uri")
        if uri is None:
            buffers.append(binary if k == 0 and binary is not None else b"")
        elif uri.startswith("data:"):
            import base64
            buffers.append(base64.b64decode(uri.split(",", 1)[1]))
        else:
            from urllib.parse import unquote
            buffers.append(open(os.path.join(os.path.dirname(path), unquote(uri)), "rb").read())
    return doc, buffers


def gltf_faces(path, names=None):
    """The triangles of a glTF scene's meshes, numbered as the tools read them: the nodes `names`
    names (by the node's or its mesh's name), in that order, or every mesh of the default scene
    (each once, where its first node shows it, depth first); each node's primitives in order, their
    vertices one after another. Also the vertex count, which must be the cache's."""
    doc, buffers = gltf_document(path)
    nodes, meshes = doc.get("nodes", []), doc.get("meshes", [])
    order = []  # depth first through the default scene

    def visit(n):
        order.append(n)
        for c in nodes[n].get("children", []):
            visit(c)
    for n in doc.get("scenes", [{}])[doc.get("scene", 0)].get("nodes", []):
        visit(n)
    showing = [n for n in order if "mesh" in nodes[n]]
    if names:
        chosen = []
        for name in names:
            hits = [n for n in showing if nodes[n].get("name") == name] or \
                   [n for n in showing if meshes[nodes[n]["mesh"]].get("name") == name]
            if len(hits) != 1:
                raise ValueError(f"{'no' if not hits else 'more than one'} node or mesh is named '{name}'")
            chosen.append(hits[0])
        taken = [nodes[n]["mesh"] for n in chosen]
    else:
        taken = list(dict.fromkeys(nodes[n]["mesh"] for n in showing))

    def indices(index):  # an index accessor (tightly packed: glTF gives index views no stride)
        a = doc["accessors"][index]
        view = doc["bufferViews"][a["bufferView"]]
        dtype = {5121: "<u1", 5123: "<u2", 5125: "<u4"}[a["componentType"]]
        start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        return np.frombuffer(buffers[view["buffer"]], dtype=dtype, count=a["count"], offset=start).astype(np.int64)
    faces, base = [], 0
    for m in taken:
        for prim in meshes[m]["primitives"]:
            count = doc["accessors"][prim["attributes"]["POSITION"]]["count"]
            if prim.get("mode", 4) == 4:  # triangles; points and lines are no surface
                idx = indices(prim["indices"]) if "indices" in prim else np.arange(count)
                faces += (base + idx[:len(idx) // 3 * 3].reshape(-1, 3)).tolist()
            base += count
    return faces, base


def sweep_fit_binary(given=None):
    """sweep-fit: as given, on the PATH, or built beside this script (build/*/tools/sweep-fit)."""
    import glob
    import shutil
    if given:
        return given
    found = shutil.which("sweep-fit")
    if found:
        return found
    here = os.path.dirname(os.path.abspath(__file__))
    built = sorted(glob.glob(os.path.join(here, "..", "build", "*", "tools", "sweep-fit", "sweep-fit")))
    return built[0] if built else None


def imported_faces(path, names, sweep_fit):
    """Any other format (FBX, Collada, ...) read by the tools' own importer: sweep-fit --export-obj
    writes the mesh as the tools read it (the meshes `names` names, as one), whose faces and
    vertex count are then the cache's."""
    import subprocess
    binary = sweep_fit_binary(sweep_fit)
    if binary is None:
        raise ValueError("reading this format takes the tools' importer: put sweep-fit on the PATH or give --sweep-fit")
    with tempfile.TemporaryDirectory() as tmp:
        obj = os.path.join(tmp, "mesh.obj")
        args = [binary, path, "-q", "--export-obj", obj] + [a for n in (names or []) for a in ("--mesh", n)]
        run = subprocess.run(args, capture_output=True, text=True)
        if run.returncode != 0:
            raise ValueError(run.stderr.strip().removeprefix("error: ") or f"sweep-fit exit {run.returncode}")
        faces, _ = obj_off_faces(obj)
        with open(obj) as f:
            count = sum(1 for line in f if line.startswith("v "))
    return faces, count


def read_faces(path, sweep_fit=None):
    """The triangles of the mesh a bake deforms, numbered as the cache's points: from an .off, .obj,
    .gltf or .glb file, any other format the tools read (through sweep-fit --export-obj), or a rig
    (its mesh, and of a scene file the meshes its mesh_name names, in order). Also the vertex count
    where the format gives the cache's (all but .off and .obj), else None."""
    ext = os.path.splitext(path)[1].lower()
    names = None
    if ext == ".json":
        rig = json.load(open(path))
        if not isinstance(rig, dict) or rig.get("format") != "sweep-rig":
            raise ValueError("a .json --mesh must be a rig (format sweep-rig)")
        names = rig.get("mesh_name")
        names = [names] if isinstance(names, str) else names
        path = os.path.join(os.path.dirname(path), rig["mesh"])
        ext = os.path.splitext(path)[1].lower()
    if ext in (".off", ".obj") and not names:
        faces, count = obj_off_faces(path)
    elif ext in (".gltf", ".glb"):
        faces, count = gltf_faces(path, names)
    else:
        faces, count = imported_faces(path, names, sweep_fit)
    if not faces:
        raise ValueError("no faces")
    return np.array(faces, dtype=np.int64), count


def chosen_frames(spec, moved):
    """The frames --frames asks for: a count (evenly spread), a list "0,12,40", or "peak" (frame 0
    and the frames at which the largest displacement peaks: the five highest local maxima, in time
    order). ValueError naming a frame the cache does not have."""
    n = len(moved)
    if spec == "peak":
        largest = moved.max(axis=1)
        peaks = [k for k in range(1, n) if largest[k] > largest[k - 1] and (k == n - 1 or largest[k] >= largest[k + 1])]
        peaks = sorted(peaks, key=lambda k: -largest[k])[:5]
        return np.array(sorted({0, *peaks}))
    if "," in spec or not spec.strip().isdigit():
        picks = []
        for word in filter(None, spec.split(",")):  # "12," is frame 12 alone
            if not word.strip().lstrip("-").isdigit():
                raise ValueError(f"--frames: expected a count, a list of frames or 'peak', got '{spec}'")
            k = int(word)
            if not 0 <= k < n:
                raise ValueError(f"--frames: frame {k} is not in the cache (frames 0 to {n - 1})")
            picks.append(k)
        if not picks:
            raise ValueError(f"--frames: no frame in '{spec}'")
        return np.array(picks)
    count = int(spec)
    if count < 1:
        raise ValueError(f"--frames: expected at least 1 frame, got {count}")
    return np.unique(np.linspace(0, n - 1, count).round().astype(int))


def draw_shaded(ax, points, faces, a, b, colours):
    """Triangles projected on axes a, b, back to front (the viewer looks along the third axis from
    its positive side), each coloured and lit by |n·view| and a key light from above."""
    other = 3 - a - b
    tri = points[faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(normal, axis=1)
    normal = normal / np.maximum(length, 1e-300)[:, None]
    view = np.zeros(3)
    view[other] = 1
    key = np.array([0.3, 0.8, 0.5])
    key /= np.linalg.norm(key)
    light = 0.25 + 0.55 * np.abs(normal @ view) + 0.2 * np.abs(normal @ key)
    order = np.argsort(tri[:, :, other].mean(axis=1))  # farthest first
    shaded = np.clip(colours[order, :3] * light[order, None], 0, 1)
    polys = tri[order][:, :, [a, b]]
    from matplotlib.collections import PolyCollection
    ax.add_collection(PolyCollection(polys, facecolors=shaded, edgecolors="none", antialiaseds=False))


def rigid_fit(a, b):
    """The rotation R and shift t that carry points a closest to points b (Kabsch)."""
    ca, cb = a.mean(axis=0), b.mean(axis=0)
    u, _, vt = np.linalg.svd((a - ca).T @ (b - cb))
    d = np.sign(np.linalg.det(vt.T @ u.T))
    r = vt.T @ np.diag([1, 1, d]) @ u.T
    return r, cb - r @ ca


def displacements(frames):
    """Each point's distance, frame by frame, from where the body's rigid motion carries it from
    frame 0: the body (most of the points) is fitted again and again to the half of the points
    that fits it best, so a walking body is still and its swinging tail moves; a still body gives
    plain distances from frame 0."""
    rest = frames[0].astype(np.float64)
    out = np.zeros(frames.shape[:2])
    for k in range(1, len(frames)):
        now = frames[k].astype(np.float64)
        if not np.any(now != rest):
            continue
        # Trimmed refits from two starts, the body still and the fit to every point; the one whose
        # better half fits closer wins.
        fits = []
        for r, t in ((np.eye(3), np.zeros(3)), rigid_fit(rest, now)):
            for _ in range(12):  # the better half each time, until it settles
                residual = np.linalg.norm(now - (rest @ r.T + t), axis=1)
                best = residual <= np.median(residual)
                r_new, t_new = rigid_fit(rest[best], now[best])
                settled = np.allclose(r_new, r, atol=1e-12) and np.allclose(t_new, t, atol=1e-12)
                r, t = r_new, t_new
                if settled:
                    break
            residual = np.linalg.norm(now - (rest @ r.T + t), axis=1)
            fits.append((np.sort(residual)[: len(residual) // 2].sum(), r, t))
        _, r, t = min(fits, key=lambda f: f[0])
        carried = rest @ r.T + t
        out[k] = np.linalg.norm(now - carried, axis=1)
        # A body that does not move at all: distances from frame 0 exactly (no fitting noise).
        if np.allclose(r, np.eye(3), atol=1e-9) and np.allclose(t, 0, atol=1e-9 * np.abs(rest).max()):
            out[k] = np.linalg.norm(now - rest, axis=1)
    return out


def collider_outlines(scene):
    """The colliders of a scene file (or of a rig's scene), as the JSON gives them."""
    doc = json.load(open(scene))
    if doc.get("format") == "sweep-rig":
        doc = doc.get("scene", {})
    return [c for c in doc.get("colliders", []) if isinstance(c, dict)]


def quat_matrix(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def convex_hull(points):
    """Andrew's monotone chain: the hull of 2-D points, counter-clockwise."""
    pts = sorted(map(tuple, points))

    def half(seq):
        out = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1]) -
                                     (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(p)
        return out
    lower, upper = half(pts), half(reversed(pts))
    return np.array(lower[:-1] + upper[:-1])


def draw_collider(ax, c, a, b, lo, hi):
    """The collider's shadow on the view plane of axes a, b, in light grey."""
    style = dict(color="0.55", alpha=0.35, linewidth=0)
    shape = c.get("shape")
    if shape == "sphere":
        ax.add_patch(plt.Circle((c["center"][a], c["center"][b]), c["radius"], **style))
    elif shape == "capsule":
        p, q, r = np.array(c["from"], float), np.array(c["to"], float), c["radius"]
        for s in np.linspace(0, 1, 24):
            x = p + s * (q - p)
            ax.add_patch(plt.Circle((x[a], x[b]), r, **style))
    elif shape == "box":
        e = np.array(c["half_size"], float)
        m = quat_matrix(c.get("rotation", [0, 0, 0, 1]))
        corners = np.array([np.array(c["center"]) + m @ (e * np.array(s)) for s in
                            [(i, j, k) for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)]])
        ax.add_patch(plt.Polygon(convex_hull(corners[:, [a, b]]), **style))
    elif shape == "plane":
        n, p = np.array(c["normal"], float), np.array(c["point"], float)
        other = 3 - a - b
        if abs(n[other]) > 1e-9 * np.linalg.norm(n):
            return  # not seen edge-on in this view
        # The solid side: n·(x − p) ≤ 0, shaded across the view.
        xs = np.linspace(lo[a], hi[a], 2)
        if abs(n[b]) > 1e-12:
            ys = p[b] - n[a] * (xs - p[a]) / n[b]
            edge = hi[b] + (hi[b] - lo[b]) if n[b] < 0 else lo[b] - (hi[b] - lo[b])
            ax.fill_between(xs, ys, edge, **style)
        else:
            x0 = p[a]
            edge = lo[a] - (hi[a] - lo[a]) if n[a] > 0 else hi[a] + (hi[a] - lo[a])
            ax.axvspan(min(x0, edge), max(x0, edge), **style)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("pc2", help="baked point cache (.pc2) from sweep-sim")
    ap.add_argument("-o", "--output", required=True, help="PNG to write")
    ap.add_argument("--report", help="sweep-sim --report JSON, for the displacement plot")
    ap.add_argument("--frames", default="6", help="how many frames to show (default 6), which ones (0,12,40), "
                                                  "or 'peak' (frame 0 and where the motion peaks)")
    ap.add_argument("--fps", type=float, default=None, help="label frames with times at this rate")
    ap.add_argument("--views", default="xy,xz", help="axis pairs to project on (default xy,xz)")
    ap.add_argument("--dpi", type=int, default=110, help="resolution of the picture (default 110)")
    ap.add_argument("--scene", help="scene (or rig with a scene) whose colliders to draw")
    ap.add_argument("--mesh", help="the deformed mesh (.off, .obj, .gltf, .glb, or the bake's rig): shaded "
                                   "surfaces, not points")
    ap.add_argument("--sweep-fit", help="the sweep-fit program, which reads --mesh formats other than .off, .obj "
                                        "and glTF (default: on the PATH, or built beside this script)")
    ap.add_argument("--reference", help="a .pc2 of the same points and frames (e.g. the pose a clip keys): "
                                        "colour by the distance from it")
    args = ap.parse_args()
    try:
        frames = read_pc2(args.pc2)
        report = json.load(open(args.report)) if args.report else None
    except (OSError, ValueError) as e:
        print(f"error: {args.pc2 if not isinstance(e, json.JSONDecodeError) else args.report}: {e}", file=sys.stderr)
        return 2
    try:
        reference = read_pc2(args.reference) if args.reference else None
        if reference is not None and reference.shape != frames.shape:
            raise ValueError(f"{reference.shape[0]} frames of {reference.shape[1]} points, the cache has "
                             f"{frames.shape[0]} of {frames.shape[1]}: not a reference for this bake")
    except (OSError, ValueError) as e:
        print(f"error: {args.reference}: {e}", file=sys.stderr)
        return 2
    try:
        colliders = collider_outlines(args.scene) if args.scene else []
    except (OSError, ValueError, AttributeError) as e:
        print(f"error: {args.scene}: {e}", file=sys.stderr)
        return 2
    try:
        faces, count = read_faces(args.mesh, args.sweep_fit) if args.mesh else (None, None)
        if faces is not None and (faces.min() < 0 or faces.max() >= frames.shape[1]):
            raise ValueError(f"its faces name vertices up to {faces.max()}, the cache has "
                             f"{frames.shape[1]} points: not the mesh of this bake")
        if count is not None and count != frames.shape[1]:
            raise ValueError(f"it has {count} vertices, the cache has {frames.shape[1]} points: not the mesh of this bake")
    except (OSError, ValueError, IndexError, KeyError, TypeError, struct.error) as e:
        print(f"error: {args.mesh}: {e}", file=sys.stderr)
        return 2
    fps = args.fps or (report["fps"] if report else None)
    rest = frames[0]
    if reference is not None:
        moved = np.linalg.norm(frames.astype(np.float64) - reference, axis=2)
    else:
        moved = displacements(frames)
    extent = max(float(np.ptp(frames.reshape(-1, 3), axis=0).max()), 1e-30)
    moving = moved.max(axis=0) > 1e-5 * extent
    try:
        picks = chosen_frames(args.frames, moved)
    except ValueError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    views = [("xyz".index(v[0]), "xyz".index(v[1])) for v in args.views.split(",")]
    rows = len(views) + (1 if report else 0)
    fig, axes = plt.subplots(rows, len(picks), figsize=(3.2 * len(picks), 3.0 * rows), squeeze=False)
    vmax = max(moved[:, moving].max(), 1e-12) if moving.any() else 1.0
    lo, hi = frames.reshape(-1, 3).min(axis=0), frames.reshape(-1, 3).max(axis=0)
    if colliders:  # room for what the part runs into
        lo, hi = lo - 0.15 * (hi - lo).max(), hi + 0.15 * (hi - lo).max()
    for c, k in enumerate(picks):
        d = moved[k]
        for r, (a, b) in enumerate(views):
            ax = axes[r][c]
            if faces is not None:
                # A face moves with its vertices: the body's still faces grey, the part's by colour.
                face_d = d[faces].mean(axis=1)
                face_moving = moving[faces].any(axis=1)
                colours = np.where(face_moving[:, None], plt.get_cmap("viridis")(face_d / vmax),
                                   np.array([0.78, 0.78, 0.76, 1.0]))
                draw_shaded(ax, frames[k], faces, a, b, colours)
            else:
                ax.scatter(frames[k][~moving, a], frames[k][~moving, b], s=0.2, c="0.75", linewidths=0)
                ax.scatter(frames[k][moving, a], frames[k][moving, b], s=0.4, c=d[moving], cmap="viridis",
                           vmin=0, vmax=vmax, linewidths=0)
            for col in colliders:
                try:
                    draw_collider(ax, col, a, b, lo, hi)
                except (KeyError, TypeError, ValueError, IndexError):
                    pass  # sweep-sim reads the scene and says what is wrong with it; here: not drawn
            ax.set_xlim(lo[a], hi[a])
            ax.set_ylim(lo[b], hi[b])
            ax.set_aspect("equal")
            ax.set_xticks([])
            ax.set_yticks([])
            if r == 0:
                ax.set_title(f"frame {k}" + (f"  t = {k / fps:.2f} s" if fps else ""), fontsize=9)
            if c == 0:
                ax.set_ylabel(f"{'xyz'[a]}{'xyz'[b]} view", fontsize=9)
    if report:
        gs = axes[-1][0].get_gridspec()
        for ax in axes[-1]:
            ax.remove()
        ax = fig.add_subplot(gs[-1, :])
        t = [f["time"] for f in report["per_frame"]]
        ax.plot(t, [f["max_displacement"] for f in report["per_frame"]], lw=1.5)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("largest vertex displacement\n(mesh units)")
        ax.grid(alpha=0.3)
    fig.suptitle(f"{os.path.basename(args.pc2)}: {frames.shape[1]} vertices, {len(frames)} frames; "
                 + (f"colour = distance from {os.path.basename(args.reference)} (max {vmax:.3g})" if reference is not None
                    else f"colour = displacement from where the body carries frame 0 (max {vmax:.3g})"), fontsize=10)
    fig.tight_layout()
    # Written beside the target and renamed into place: never a half-written picture.
    out_dir = os.path.dirname(os.path.abspath(args.output))
    try:
        fd, tmp = tempfile.mkstemp(dir=out_dir, prefix=".preview-", suffix=".png")
        with os.fdopen(fd, "wb") as f:
            fig.savefig(f, format="png", dpi=args.dpi)
        mask = os.umask(0)  # mkstemp makes the file private; give it the usual permissions
        os.umask(mask)
        os.chmod(tmp, 0o666 & ~mask)
        os.replace(tmp, args.output)
    except OSError as e:
        print(f"error: {args.output}: cannot write: {e}", file=sys.stderr)
        return 4
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
