"""tools/sweep-preview.py --scene draws the scene's colliders where they are: a still ring of points
rendered without a scene and with a ball at (+.5, +.5) and at (−.5, −.5); each ball turns pixels
grey, the first right of and above the second; a scene that cannot be read is exit 2 with its
name and no picture. Usage: preview_colliders.py REPO_ROOT WORK_DIR"""
import json
import os
import struct
import subprocess
import sys

import matplotlib.image as mpimg
import numpy as np

root, work = sys.argv[1], sys.argv[2]
os.makedirs(work, exist_ok=True)
script = os.path.join(root, "tools", "sweep-preview.py")

# A ring of points in the xy plane, radius 1 about the origin, two frames, no motion.
angles = np.linspace(0, 2 * np.pi, 400, endpoint=False)
points = np.stack([np.cos(angles), np.sin(angles), np.zeros_like(angles)], axis=1).astype("<f4")
pc2 = os.path.join(work, "ring.pc2")
with open(pc2, "wb") as f:
    f.write(b"POINTCACHE2\0" + struct.pack("<iiffi", 1, len(points), 0.0, 1.0, 2))
    f.write(points.tobytes() * 2)


def scene_with_ball(name, centre):
    path = os.path.join(work, name)
    json.dump({"format": "sweep-scene", "version": 1, "duration": 1, "fps": 1, "forces": [],
               "colliders": [{"shape": "sphere", "center": centre, "radius": 0.2}]}, open(path, "w"))
    return path


def render(name, *extra):
    out = os.path.join(work, name)
    subprocess.run([sys.executable, script, pc2, "-o", out, "--views", "xy", "--frames", "1", *extra],
                   check=True, capture_output=True)
    return mpimg.imread(out)[..., :3]


def shadow(plain, drawn):
    """Where the drawing turned pixels grey: their count and mean (x, y) in image coordinates."""
    assert plain.shape == drawn.shape, "the scene must not change the picture's size"
    changed = np.abs(plain - drawn).max(axis=2) > 0.05
    grey = changed & (np.abs(drawn[..., 0] - drawn[..., 1]) < 0.02) & (drawn[..., 0] < 0.95) & (drawn[..., 0] > 0.3)
    ys, xs = np.nonzero(grey)
    return grey.sum(), (xs.mean() if len(xs) else 0), (ys.mean() if len(ys) else 0)


plain = render("plain.png")
n_a, xa, ya = shadow(plain, render("a.png", "--scene", scene_with_ball("a.json", [0.5, 0.5, 0])))
n_b, xb, yb = shadow(plain, render("b.png", "--scene", scene_with_ball("b.json", [-0.5, -0.5, 0])))
assert n_a > 50 and n_b > 50, f"no grey shadow where the ball is ({n_a}, {n_b} pixels)"
# The ball at (+.5, +.5) casts its shadow right of and above (smaller image y) the one at (−.5, −.5).
assert xa > xb + 20 and ya < yb - 20, f"shadows at ({xa:.0f}, {ya:.0f}) and ({xb:.0f}, {yb:.0f})"

bad = subprocess.run([sys.executable, script, pc2, "-o", os.path.join(work, "bad.png"), "--scene",
                      os.path.join(work, "absent.json")], capture_output=True, text=True)
assert bad.returncode == 2 and "absent.json" in bad.stderr, (bad.returncode, bad.stderr)
assert not os.path.exists(os.path.join(work, "bad.png")), "a picture was written for a bad scene"
print(f"preview draws colliders: shadows of {n_a} and {n_b} pixels, where the balls are")
