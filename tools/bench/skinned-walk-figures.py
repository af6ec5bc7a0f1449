#!/usr/bin/python3
"""The looping bake of a skinned clip against the pose the clip keys: per part, the seam (how far its
last frame is from its first, in part lengths), how far it lags the keyed pose (its farthest vertex
and its tip, in part lengths; the tip's swing angle about the root), and the phase lag of the tip's
sideways sway at the loop's period.

    tools/bench/skinned-walk-figures.py BAKE.pc2 KEYED.pc2 RIG.json FPS PERIOD [SIDEWAYS_AXIS]

KEYED.pc2: the clip's own pose at the same frames (make_skinned_diplodocus.py --keyed). A part's
vertices are those off the keyed pose by more than 1e-5 at some frame, each given to the sweep whose
key sections pass nearest; its tip is the vertex nearest its last section's centre."""
import json
import struct
import sys

import numpy as np


def read_pc2(path):
    data = open(path, "rb").read()
    _, points, _, _, samples = struct.unpack("<iiffi", data[12:32])
    return np.frombuffer(data[32:], "<f4").reshape(samples, points, 3).astype(np.float64)


def main(bake, keyed, rig, fps, period, axis=2):
    baked, ref = read_pc2(bake), read_pc2(keyed)
    off = np.linalg.norm(baked - ref, axis=2)
    moving = np.nonzero(off.max(axis=0) > 1e-5)[0]
    sweeps = json.load(open(rig))["sweeps"]
    centres = [np.array([s["center"] for s in sweep["sections"]]) for sweep in sweeps]
    rest = ref[0]
    owner = np.argmin([np.linalg.norm(rest[moving][:, None] - c[None], axis=2).min(axis=1) for c in centres], axis=0)
    per = int(round(period * fps))
    for i, sweep in enumerate(sweeps):
        c = centres[i]
        length = np.linalg.norm(np.diff(c, axis=0), axis=1).sum()
        part = moving[owner == i]
        tip = int(np.argmin(np.linalg.norm(rest - c[-1], axis=1)))
        root = int(np.argmin(np.linalg.norm(rest - c[0], axis=1)))
        seam = np.linalg.norm(baked[-1, part] - baked[0, part], axis=1).max() / length
        a, b = baked[:, tip] - baked[:, root], ref[:, tip] - ref[:, root]
        cos = np.sum(a * b, axis=1) / np.linalg.norm(a, axis=1) / np.linalg.norm(b, axis=1)
        swing = np.degrees(np.arccos(np.clip(cos, -1, 1))).max()
        frames = np.arange(len(baked) - 1)[-per:]  # the last whole period

        def fundamental(x):
            return np.sum(x[frames] * np.exp(-2j * np.pi * frames / per)) * 2 / per

        fb, fk = fundamental(baked[:, tip, axis]), fundamental(ref[:, tip, axis])
        lag = (np.angle(fk) - np.angle(fb)) % (2 * np.pi)
        lag = lag - 2 * np.pi if lag > np.pi else lag
        print(f"{sweep['name']}: {len(part)} vertices, length {length:.4f}; seam {seam:.2e} of the length; "
              f"off the keyed pose: farthest vertex {off[:, part].max() / length * 100:.2f} %, tip "
              f"{off[:, tip].max() / length * 100:.2f} % of the length, tip swing {swing:.2f} deg; sideways sway of the "
              f"tip: keyed {abs(fk):.4f}, baked {abs(fb):.4f} mesh units, baked lags by {lag / (2 * np.pi) * period:+.3f} s "
              f"({np.degrees(lag):+.0f} deg of the cycle)")


if __name__ == "__main__":
    if len(sys.argv) not in (6, 7):
        raise SystemExit(__doc__.split("\n\n")[1])
    main(sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4]), float(sys.argv[5]),
         int(sys.argv[6]) if len(sys.argv) == 7 else 2)
