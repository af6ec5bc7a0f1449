"""tools/sweep-preview.py --mesh draws shaded surfaces, not points: a tube (24 around, 20 rings,
along x) whose far third moves up in the second frame, seen from the side. With --mesh the tube's
silhouette is filled (a surface), where points leave most of it white; the still part is grey and
the moving part coloured, also when the whole tube walks off and turns (the body's rigid
motion is not displacement); a mesh whose faces name vertices the cache has not is exit 2, named, and
no picture; with --reference (a keyed pose) the colours are distances from it, so what the
reference moves too stays grey. Usage: preview_shaded.py REPO_ROOT WORK_DIR"""
import os
import struct
import subprocess
import sys

import matplotlib.image as mpimg
import numpy as np

root, work = sys.argv[1], sys.argv[2]
os.makedirs(work, exist_ok=True)
script = os.path.join(root, "tools", "sweep-preview.py")

around, rings, radius, length = 24, 20, 0.1, 2.0
xs = np.linspace(-length / 2, length / 2, rings)
angles = np.linspace(0, 2 * np.pi, around, endpoint=False)
rest = np.array([(x, radius * np.cos(a), radius * np.sin(a)) for x in xs for a in angles])
faces = [(i * around + j, i * around + (j + 1) % around, (i + 1) * around + (j + 1) % around,
          (i + 1) * around + j) for i in range(rings - 1) for j in range(around)]
obj = os.path.join(work, "tube.obj")
with open(obj, "w") as f:
    f.writelines(f"v {p[0]:.6f} {p[1]:.6f} {p[2]:.6f}\n" for p in rest)
    f.writelines("f " + " ".join(str(v + 1) for v in face) + "\n" for face in faces)
moved = rest.copy()
moved[rest[:, 0] > 0.35, 1] += 0.3  # the far third lifts (the body, most of the points, stays)
pc2 = os.path.join(work, "tube.pc2")
with open(pc2, "wb") as f:
    f.write(b"POINTCACHE2\0" + struct.pack("<iiffi", 1, len(rest), 0.0, 1.0, 2))
    f.write(rest.astype("<f4").tobytes() + moved.astype("<f4").tobytes())


def render(name, *extra):
    out = os.path.join(work, name)
    subprocess.run([sys.executable, script, pc2, "-o", out, "--views", "xy", "--frames", "1", *extra],
                   check=True, capture_output=True)
    return mpimg.imread(out)[..., :3]


def paint(img):
    """Pixels of the drawing (not the white page, not the black axes and text): grey ones and
    coloured ones, as boolean masks."""
    lo, hi = img.min(axis=2), img.max(axis=2)
    drawn = (lo < 0.97) & (hi > 0.12)
    grey = drawn & (hi - lo < 0.03)
    coloured = drawn & (hi - lo > 0.08)
    return drawn, grey, coloured


points = render("points.png")
shaded = render("shaded.png", "--mesh", obj)
assert points.shape == shaded.shape
drawn_p, _, _ = paint(points)
drawn_s, grey, coloured = paint(shaded)
# Frame 0 alone: the tube from the side is a band 2r by L, filled by the surface; points cover a
# fraction of it.
assert drawn_s.sum() > 2 * drawn_p.sum(), f"shaded {drawn_s.sum()} pixels, points {drawn_p.sum()}"
# Its still part (the left) is grey, its moving third (right) coloured by displacement.
ys, xs = np.nonzero(grey)
yc, xc = np.nonzero(coloured)
assert grey.sum() > 0.4 * drawn_s.sum() and coloured.sum() > 0.15 * drawn_s.sum(), (grey.sum(), coloured.sum())
assert xs.mean() < xc.mean() - 0.2 * (xc.max() - xs.min()), (xs.mean(), xc.mean())

# The same motion on a body that walks off and turns (a rigid motion of every point, frame 1):
# the colours are displacements from where the body carries frame 0, so the still part stays grey.
turn = np.radians(30)
rotation = np.array([[np.cos(turn), 0, np.sin(turn)], [0, 1, 0], [-np.sin(turn), 0, np.cos(turn)]])
walked = moved @ rotation.T + np.array([0.7, 0.0, -0.4])
with open(pc2, "wb") as f:
    f.write(b"POINTCACHE2\0" + struct.pack("<iiffi", 1, len(rest), 0.0, 1.0, 2))
    f.write(rest.astype("<f4").tobytes() + walked.astype("<f4").tobytes())
drawn_w, grey_w, coloured_w = paint(render("walked.png", "--mesh", obj))
ys, xs = np.nonzero(grey_w)
yc, xc = np.nonzero(coloured_w)
assert grey_w.sum() > 0.4 * drawn_w.sum() and coloured_w.sum() > 0.15 * drawn_w.sum(), (grey_w.sum(), coloured_w.sum())
assert xs.mean() < xc.mean(), "on a walking body the still part must stay grey"

bad = os.path.join(work, "bad.obj")
with open(bad, "w") as f:
    f.write("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9999\n")
run = subprocess.run([sys.executable, script, pc2, "-o", os.path.join(work, "bad.png"), "--mesh", bad],
                     capture_output=True, text=True)
assert run.returncode == 2 and "bad.obj" in run.stderr and "not the mesh" in run.stderr, (run.returncode, run.stderr)
assert not os.path.exists(os.path.join(work, "bad.png")), "a picture was written for a wrong mesh"

# --reference: colours are distances from a reference cache's same frame (a clip's keyed pose). The
# reference bends the near third down (a keyed motion the bake shares, not rigid: without the
# reference it is coloured) and the bake lifts the far third on top of it: with the reference the
# near third is grey and the far third coloured.
keyed = rest.copy()
near = rest[:, 0] < -0.35
keyed[near, 1] -= 0.5 * (-0.35 - rest[near, 0])
baked = keyed.copy()
baked[rest[:, 0] > 0.35, 1] += 0.3
reference = os.path.join(work, "keyed.pc2")
for path, second in ((pc2, baked), (reference, keyed)):
    with open(path, "wb") as f:
        f.write(b"POINTCACHE2\0" + struct.pack("<iiffi", 1, len(rest), 0.0, 1.0, 2))
        f.write(rest.astype("<f4").tobytes() + second.astype("<f4").tobytes())
for extra, near_grey in (((), False), (("--reference", reference), True)):
    img = render("reference.png", "--mesh", obj, *extra)
    drawn_r, grey_r, coloured_r = paint(img)
    columns = np.nonzero(drawn_r.any(axis=0))[0]
    left = np.zeros_like(drawn_r)
    left[:, columns.min():columns.min() + (columns.max() - columns.min()) // 5] = True
    right = np.zeros_like(drawn_r)
    right[:, columns.max() - (columns.max() - columns.min()) // 5:] = True
    assert (coloured_r & right).sum() > 0.5 * (drawn_r & right).sum(), "the lifted far third must be coloured"
    if near_grey:
        assert (grey_r & left).sum() > 0.5 * (drawn_r & left).sum(), "what the reference moves too must be grey"
    else:
        assert (coloured_r & left).sum() > 0.5 * (drawn_r & left).sum(), "without a reference the bent end is coloured"
# A reference of other frames or points is exit 2, named, and no picture.
short = os.path.join(work, "short.pc2")
with open(short, "wb") as f:
    f.write(b"POINTCACHE2\0" + struct.pack("<iiffi", 1, len(rest), 0.0, 1.0, 1) + rest.astype("<f4").tobytes())
run = subprocess.run([sys.executable, script, pc2, "-o", os.path.join(work, "short.png"), "--reference", short],
                     capture_output=True, text=True)
assert run.returncode == 2 and "short.pc2" in run.stderr and "not a reference" in run.stderr, (run.returncode, run.stderr)
assert not os.path.exists(os.path.join(work, "short.png")), "a picture was written for a wrong reference"
