#!/usr/bin/env python3
"""The internal step against accuracy, scene by scene: each scene baked by sweep-sim at steps of
1/480, 1/240, 1/120 and 1/60 s and at a reference step 64 times finer than the finest (1/30720 s),
every vertex of every frame compared. Error: the largest distance of a vertex from where the
reference puts it, over the length of the rig's shortest part (a bound vertex moves only with its
part, so this bounds every part's own error from above). The bar for the default step is 1e-4 of
the length.

Scenes (the demo assets as tools/run-demo.sh and the tests make them):
  - fig4: the diplodocus in springs mode, rigs/diplodocus-fig4.scene.json (follower loads);
  - path: the same rig on rigs/diplodocus-path.scene.json (a body path with a turn; legs and
    ground as colliders, where the step is cut to contact_step);
  - material: the parts in material mode, rigs/diplodocus-material.scene.json (gravity, unloaded
    start, two pushes);
  - wind: the material parts on the body path scene, which also blows a gusting, turbulent wind;
  - walk: the skinned diplodocus (meshes/make_skinned_diplodocus.py) playing its walk clip,
    rigs/diplodocus-walk.scene.json, compared in bind space (--under-skin: the parts' motion alone);
  - swing: a material tube (2 m, 5 cm radius, ρ = 1100 kg/m³, E = 1e8 Pa: its first sway ~1 Hz)
    held level on a body that turns 90° about the vertical in 0.6 s (θ = 90° (3u² − 2u³), keyed in
    linear pieces) and stops, under gravity (as modelled): "dynamics" modal, then exact. The swing
    column: the largest distance of a vertex from the rest turned with the body, over the length.

    tools/bench/step-accuracy.py [BIN_DIR (default build/dev/tools)] [--out DIR]

Writes step_accuracy.md and step_accuracy.csv into DIR (default tools/bench/results).
"""
import argparse
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

HERE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
STEPS = [480, 240, 120, 60]  # per second
REFERENCE = 64 * max(STEPS)
BAR = 1e-4
TURN_SECONDS = 0.6
TUBE_MODULI = (1e8,)  # Pa
BAKE_SECONDS = 300  # a bake that takes longer is reported as such


def run(cmd, cwd, timeout=None):
    try:
        done = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        raise RuntimeError(f"{' '.join(cmd)}:\ntook more than {timeout:g} s")
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: exit {done.returncode}\n{done.stderr}")


def read_pc2(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:11] != b"POINTCACHE2":
        raise RuntimeError(f"{path}: not a .pc2 file")
    _, points, _, _, samples = struct.unpack_from("<iiffi", data, 12)
    values = struct.unpack_from(f"<{points * samples * 3}f", data, 32)
    return points, samples, values


def shortest_part(rig_path):
    rig = json.load(open(rig_path))
    lengths = []
    for sweep in rig["sweeps"]:
        centres = [s["center"] for s in sweep["sections"]]
        lengths.append(sum(math.dist(a, b) for a, b in zip(centres, centres[1:])))
    return min(lengths)


def largest_difference(a, b):
    pa, sa, va = a
    pb, sb, vb = b
    if (pa, sa) != (pb, sb):
        raise RuntimeError("bakes of different sizes")
    worst = 0.0
    for i in range(0, len(va), 3):
        d = (va[i] - vb[i]) ** 2 + (va[i + 1] - vb[i + 1]) ** 2 + (va[i + 2] - vb[i + 2]) ** 2
        if d > worst:
            worst = d
    return math.sqrt(worst)


def turn_keys():
    """The body's turn: 90° about +y in TURN_SECONDS, θ = 90° (3u² − 2u³), keyed in linear pieces."""
    n = 12
    return [(TURN_SECONDS * i / n, 90 * (3 * (i / n) ** 2 - 2 * (i / n) ** 3)) for i in range(n + 1)]


def turn_at(t):
    keys = turn_keys()
    for (t0, a0), (t1, a1) in zip(keys, keys[1:]):
        if t <= t1:
            return math.radians(a0 + (a1 - a0) * (t - t0) / (t1 - t0))
    return math.radians(keys[-1][1])


def swing(bake, rest, fps, length):
    """Largest distance of a vertex from the rest turned with the body, over the length."""
    points, samples, v = bake
    worst = 0.0
    for k in range(samples):
        a = turn_at(k / fps)
        c, s = math.cos(a), math.sin(a)
        for p in range(points):
            x, y, z = rest[p]
            o = 3 * (k * points + p)
            d = (v[o] - (c * x + s * z)) ** 2 + (v[o + 1] - y) ** 2 + (v[o + 2] - (-s * x + c * z)) ** 2
            worst = max(worst, d)
    return math.sqrt(worst) / length


def read_obj(path):
    return [tuple(map(float, line.split()[1:4])) for line in open(path) if line.startswith("v ")]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("bin", nargs="?", default=os.path.join(HERE, "build/dev/tools"))
    parser.add_argument("--out", default=os.path.join(HERE, "tools/bench/results"))
    parser.add_argument("--keep", help="work in this folder and keep it, reusing the bakes it holds (default: a "
                        "temporary folder)")
    args = parser.parse_args()
    b = os.path.abspath(args.bin)
    fit, bind, sim, tube = (os.path.join(b, t, t) for t in ("sweep-fit", "sweep-bind", "sweep-sim", "sweep-tube"))
    mesh = os.path.join(HERE, "meshes/cgal/diplodocus.off")
    if not os.path.isfile(mesh):
        sys.exit(f"error: {mesh} is missing (tools/setup-deps.sh)")
    work = args.keep or tempfile.mkdtemp()
    os.makedirs(work, exist_ok=True)
    rigs = os.path.join(HERE, "rigs")
    tail = ["--name", "tail", "--root=-0.29,-0.16,-0.015", "--tip=-0.5,-0.345,-0.012"]
    neck = ["--name", "neck", "--root", "0.26,0.08,0.062", "--tip", "0.36,0.45,0.11"]
    flesh = {"tail": os.path.join(rigs, "diplodocus-tail.material.json"),
             "neck": os.path.join(rigs, "diplodocus-neck.material.json")}
    # The rigs, as tools/run-demo.sh makes them.
    if not os.path.exists(os.path.join(work, "w.rig.bind")):
        for part in (tail, neck):
            run([fit, mesh, "-o", "d.rig.json", *part, "-q"], work)
            run([fit, mesh, "-o", "dm.rig.json", *part, "--material", flesh[part[1]], "-q"], work)
        run([sys.executable, os.path.join(HERE, "meshes/make_skinned_diplodocus.py"), mesh, "sk.glb"], work)
        for part in (tail, neck):
            run([fit, "sk.glb", "-o", "w.rig.json", *part, "--material", flesh[part[1]], "-q"], work)
        for rig in ("d", "dm", "w"):
            run([bind, f"{rig}.rig.json", "--blend", "0.02", "-q"], work)
    # The tube: 2 m along +z from the body's origin, in metres.
    if not os.path.exists(os.path.join(work, f"t{TUBE_MODULI[-1]:g}.rig.bind")):
        run([tube, "-o", "tube.obj", "--length", "2", "--radius", "0.05", "--rings", "41", "-q"], work)
        for youngs in TUBE_MODULI:
            json.dump({"youngs_modulus_pa": youngs, "poisson_ratio": 0.45, "density_kg_m3": 1100, "metres_per_unit": 1,
                       "damping_ratio": 0.05}, open(os.path.join(work, f"tube-{youngs:g}.material.json"), "w"))
            run([fit, "tube.obj", "-o", f"t{youngs:g}.rig.json", "--name", "tube", "--root", "0,0,0", "--tip", "0,0,2",
                 "--material", f"tube-{youngs:g}.material.json", "-q"], work)
            run([bind, f"t{youngs:g}.rig.json", "--blend", "0.02", "-q"], work)
    for dynamics in ("modal", "exact"):
        json.dump({"format": "sweep-scene", "version": 1, "duration": 2.0, "fps": 30, "gravity": [0, -9.81, 0],
                   "dynamics": dynamics,
                   "body": {"interpolation": "linear",
                            "keys": [{"time": t, "translation": [0, 0, 0], "turn_degrees": a} for t, a in turn_keys()]},
                   "forces": []}, open(os.path.join(work, f"swing-{dynamics}.scene.json"), "w"))
    scenes = [
        ("fig4", "Fig. 4 (springs, follower loads)", "d.rig.json", os.path.join(rigs, "diplodocus-fig4.scene.json"), []),
        ("path", "body path (springs, colliders)", "d.rig.json", os.path.join(rigs, "diplodocus-path.scene.json"), []),
        ("material", "material parts, gravity and pushes", "dm.rig.json",
         os.path.join(rigs, "diplodocus-material.scene.json"), []),
        ("wind", "material parts, body path, wind, colliders", "dm.rig.json",
         os.path.join(rigs, "diplodocus-path.scene.json"), []),
        ("walk", "skinned clip (walk), material", "w.rig.json", os.path.join(rigs, "diplodocus-walk.scene.json"),
         ["--under-skin"]),
        ("swing", "tube on a 90° body turn, modal", "t1e+08.rig.json", "swing-modal.scene.json", []),
        ("swing-exact", "tube on a 90° body turn, exact chain", "t1e+08.rig.json", "swing-exact.scene.json", []),
    ]

    def bake(scene, per_second):
        name, _, rig, path, extra = scene
        out = f"{name}-{per_second}.pc2"
        if args.keep and os.path.exists(os.path.join(work, out)):
            return None  # made by an earlier run in the kept folder
        try:
            run([sim, rig, "--scene", path, "--step", repr(1.0 / per_second), "--threads", "1", "-o", out, "-q", *extra],
                work, BAKE_SECONDS)
            return None
        except RuntimeError as e:
            return str(e).strip().splitlines()[-1]

    jobs = [(s, n) for s in scenes for n in [REFERENCE] + STEPS]
    with ThreadPoolExecutor(max_workers=2) as pool:
        failures = dict(zip([(s[0], n) for s, n in jobs], pool.map(lambda j: bake(*j), jobs)))

    md = ("| scene | swing / length | " + " | ".join(f"1/{n} s" for n in STEPS) + " |\n"
          "|---|---|" + "---|" * len(STEPS) + "\n")
    csv = "scene,step_s,largest_error_over_length\n"
    for name, label, rig, path, _ in scenes:
        length = shortest_part(os.path.join(work, rig))
        failed = failures[(name, REFERENCE)]
        if failed:
            md += f"| {label} | | the reference failed: {failed} |" + " |" * (len(STEPS) - 1) + "\n"
            continue
        ref = read_pc2(os.path.join(work, f"{name}-{REFERENCE}.pc2"))
        moved = ""
        if name.startswith("swing"):
            moved = f"{swing(ref, read_obj(os.path.join(work, 'tube.obj')), 30, length):.2f}"
        cells = []
        for n in STEPS:
            if failures[(name, n)]:
                cells.append(f"failed: {failures[(name, n)]}")
                csv += f"{name},{1.0 / n:.6g},failed\n"
                continue
            err = largest_difference(read_pc2(os.path.join(work, f"{name}-{n}.pc2")), ref) / length
            cells.append(f"{err:.2e}" + (" **over the bar**" if err > BAR else ""))
            csv += f"{name},{1.0 / n:.6g},{err:.6g}\n"
        md += f"| {label} | {moved} | " + " | ".join(cells) + " |\n"
    os.makedirs(args.out, exist_ok=True)
    open(os.path.join(args.out, "step_accuracy.md"), "w").write(md)
    open(os.path.join(args.out, "step_accuracy.csv"), "w").write(csv)
    sys.stdout.write(md)
    if not args.keep:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
