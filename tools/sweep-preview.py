#!/usr/bin/python3
"""Preview a bake as a PNG contact sheet: a few frames of a .pc2 point cache, seen from the side and
from above, each vertex coloured by how far it has moved from frame 0. With --report (sweep-sim's
JSON report) a last panel plots the largest displacement over time.

    tools/sweep-preview.py out/diplodocus.pc2 -o out/diplodocus.png --report out/report.json

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


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("pc2", help="baked point cache (.pc2) from sweep-sim")
    ap.add_argument("-o", "--output", required=True, help="PNG to write")
    ap.add_argument("--report", help="sweep-sim --report JSON, for the displacement plot")
    ap.add_argument("--frames", type=int, default=6, help="frames to show (default 6)")
    ap.add_argument("--fps", type=float, default=None, help="label frames with times at this rate")
    ap.add_argument("--views", default="xy,xz", help="axis pairs to project on (default xy,xz)")
    ap.add_argument("--dpi", type=int, default=110, help="resolution of the picture (default 110)")
    args = ap.parse_args()
    try:
        frames = read_pc2(args.pc2)
        report = json.load(open(args.report)) if args.report else None
    except (OSError, ValueError) as e:
        print(f"error: {args.pc2 if not isinstance(e, json.JSONDecodeError) else args.report}: {e}", file=sys.stderr)
        return 2
    fps = args.fps or (report["fps"] if report else None)
    rest = frames[0]
    moving = np.linalg.norm(frames - rest, axis=2).max(axis=0) > 0
    picks = np.unique(np.linspace(0, len(frames) - 1, max(1, args.frames)).round().astype(int))
    views = [("xyz".index(v[0]), "xyz".index(v[1])) for v in args.views.split(",")]
    rows = len(views) + (1 if report else 0)
    fig, axes = plt.subplots(rows, len(picks), figsize=(3.2 * len(picks), 3.0 * rows), squeeze=False)
    vmax = max(np.linalg.norm(frames[:, moving] - rest[moving], axis=2).max(), 1e-12) if moving.any() else 1.0
    lo, hi = frames.reshape(-1, 3).min(axis=0), frames.reshape(-1, 3).max(axis=0)
    for c, k in enumerate(picks):
        d = np.linalg.norm(frames[k] - rest, axis=1)
        for r, (a, b) in enumerate(views):
            ax = axes[r][c]
            ax.scatter(frames[k][~moving, a], frames[k][~moving, b], s=0.2, c="0.75", linewidths=0)
            ax.scatter(frames[k][moving, a], frames[k][moving, b], s=0.4, c=d[moving], cmap="viridis",
                       vmin=0, vmax=vmax, linewidths=0)
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
                 f"colour = displacement from frame 0 (max {vmax:.3g})", fontsize=10)
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
