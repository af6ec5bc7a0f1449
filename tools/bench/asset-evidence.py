#!/usr/bin/env python3
"""The whole path on real assets from Debian packages, in the formats people bring: for each asset,
`sweep-fit --list` (the parts found and their names), `--all` (with --force, so that a part whose
fit is refused is left out and the rest still run: its exit and each part's RMS), `sweep-bind`,
`sweep-sim` with a push at each part's tip baked to a .glb, and the Khronos validator on it
(tests/gltf-validator). Then a Markdown table (stdout and --markdown) against the parts a person
counts on the asset's picture (the last column of ASSETS: counted by looking at the previews), and a
shaded preview per asset (tools/sweep-preview.py on a .pc2 of the same bake) to count them from.

  tools/bench/asset-evidence.py [--bin DIR] [--models DIR] [--out DIR]

Assets absent on this machine (their package not installed, or not unpacked at --models) are
skipped and said so: the table is made by hand, not in CI. The assimp test models come from
Debian's assimp-testmodels (`apt-get download assimp-testmodels; dpkg -x *.deb x`, then
--models x/usr/share/assimp/models).
"""
import argparse
import json
import os
import subprocess
import sys

# path under --models, format, what it is, the tubular parts a person counts on its picture
ASSETS = [
    ("Collada/human.zae", "Collada (.zae)", "a standing human, hands forward",
     "2 arms, 2 legs, neck (and fingers, toes)"),
    ("BLEND/HUMAN.blend", "Blender (.blend)", "a human, Z up", "2 arms, 2 legs, neck"),
    ("X/BCN_Epileptic.X", "DirectX (.x)", "a human in three meshes (torso, head, legs), lying along Z",
     "2 arms, 2 legs, neck"),
    ("FBX/spider.fbx", "FBX", "a spider", "8 legs, 4 mouthparts"),
    ("OBJ/spider.obj", "OBJ", "the same spider", "8 legs, 4 mouthparts"),
    ("STL/Spider_binary.stl", "STL", "the same spider, unwelded triangles", "8 legs, 4 mouthparts"),
    ("OBJ/WusonOBJ.obj", "OBJ", "Wuson, a round cartoon beast", "2 legs, tail"),
    ("PLY/Wuson.ply", "PLY", "Wuson", "2 legs, tail"),
    ("X/Testwuson.X", "DirectX (.x)", "Wuson", "2 legs, tail"),
    ("MD2/sydney.md2", "Quake II (.md2)", "a human holding a gun", "2 arms, 2 legs, neck"),
    ("MD2/faerie.md2", "Quake II (.md2)", "a winged faerie with a staff", "2 arms, 2 legs, neck"),
    ("IQM/mrfixit.iqm", "Inter-Quake (.iqm)", "a robed figure", "2 arms, neck (legs under the robe)"),
    ("SIB/heffalump.sib", "Silo (.sib)", "an elephant (by its name)", "not looked at: nothing baked to preview"),
    ("COB/dwarf.cob", "Caligari (.cob)", "an armoured dwarf, horned helmet, axe", "2 arms, 2 legs, 2 horns"),
    ("FBX/animation_with_skeleton.fbx", "FBX", "a bar with a skeleton", "1 (the bar)"),
]


def tail_line(run):
    text = run.stderr.strip()
    return text.splitlines()[-1] if text else ""


def run(command):
    return subprocess.run(command, capture_output=True, text=True)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(os.path.dirname(here))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default=os.path.join(root, "build/release/tools"),
                    help="folder of the built tools (sweep-fit/sweep-fit, ...)")
    ap.add_argument("--models", default="/usr/share/assimp/models",
                    help="assimp-testmodels' folder of models")
    ap.add_argument("--out", default=os.path.join(root, "out/asset-evidence"))
    ap.add_argument("--markdown", default=os.path.join(here, "results/asset-evidence.md"))
    ap.add_argument("--no-previews", action="store_true", help="skip the pictures (quicker)")
    args = ap.parse_args()
    tool = {name: os.path.join(args.bin, name, name) for name in ("sweep-fit", "sweep-bind", "sweep-sim")}
    validator = os.path.join(root, "tests/gltf-validator/validate.js")
    os.makedirs(args.out, exist_ok=True)

    table = ["| asset | format | what | a person counts | --list finds (names) | --all | fits (RMS) | "
             "bind | bake | validator |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for path, fmt, what, person in ASSETS:
        source = os.path.join(args.models, path)
        if not os.path.exists(source):
            print(f"{path}: absent, skipped", file=sys.stderr)
            continue
        base = os.path.join(args.out, os.path.splitext(path.replace("/", "-"))[0])
        for stale in (".parts.json", ".rig.json", ".fit.json", ".glb", ".pc2"):
            if os.path.exists(base + stale):
                os.remove(base + stale)
        listed = run([tool["sweep-fit"], source, "--list", "--report", base + ".parts.json"])
        parts = json.load(open(base + ".parts.json"))["parts"] if listed.returncode == 0 else []
        names = ", ".join(p["name"] for p in parts) or "none"
        cells = [f"exit {listed.returncode}: {tail_line(listed)}" if listed.returncode else
                 f"{len(parts)}: {names}"]
        fit = run([tool["sweep-fit"], source, "--all", "-o", base + ".rig.json", "--force",
                   "--report", base + ".fit.json"])
        fitted = []
        if os.path.exists(base + ".fit.json"):
            fitted = json.load(open(base + ".fit.json"))["sweeps"]
        refused = [p["name"] for p in fitted if not p.get("ok", True)]
        left_out = fit.stderr.count("left out (--force)")
        fits = f"{len(fitted) - len(refused)} of {len(parts)} fit"
        if fitted:
            rms = sorted(100 * p["fit_rms_relative"] for p in fitted)
            fits += f" ({rms[0]:.1f}–{rms[-1]:.1f} %)"
        if refused:
            fits += "; over a limit: " + ", ".join(refused)
        if left_out:
            fits += f"; {left_out} left out"
        cells += [f"exit {fit.returncode}", fits]
        if fit.returncode or not os.path.exists(base + ".rig.json"):
            cells += ["—", "—", "—"]
            print(f"{path}: --all: {tail_line(fit)}", file=sys.stderr)
        else:
            bind = run([tool["sweep-bind"], base + ".rig.json"])
            rig = json.load(open(base + ".rig.json"))
            scene = {"format": "sweep-scene", "version": 1, "duration": 1.0, "fps": 24,
                     "forces": [{"sweep": s["name"], "t": 1.0, "theta": 0.0, "vector": [0, 0, 1.0],
                                 "start": 0.0, "end": 0.5, "components": ["rotational"]}
                                for s in rig["sweeps"]]}
            with open(base + ".scene.json", "w") as f:
                json.dump(scene, f)
            bake = run([tool["sweep-sim"], base + ".rig.json", "--scene", base + ".scene.json",
                        "-o", base + ".glb"])
            valid = "—"
            if bake.returncode == 0:
                check = run(["node", validator, base + ".glb"])
                try:
                    issues = json.loads(check.stdout)["issues"]
                    valid = f"{issues['numErrors']} errors, {issues['numWarnings']} warnings"
                except (ValueError, KeyError):
                    valid = f"exit {check.returncode}"
            cells += [f"exit {bind.returncode}", f"exit {bake.returncode}", valid]
            for step, r in (("sweep-bind", bind), ("sweep-sim", bake)):
                if r.returncode:
                    print(f"{path}: {step}: {tail_line(r)}", file=sys.stderr)
            if not args.no_previews and bake.returncode == 0:
                run([tool["sweep-sim"], base + ".rig.json", "--scene", base + ".scene.json", "-o", base + ".pc2"])
                run([os.path.join(root, "tools/sweep-preview.py"), base + ".pc2", "-o", base + ".png",
                     "--mesh", base + ".rig.json", "--sweep-fit", tool["sweep-fit"], "--frames", "peak"])
        table.append(f"| {path} | {fmt} | {what} | {person} | " + " | ".join(cells) + " |")
        print(table[-1], file=sys.stderr)
    os.makedirs(os.path.dirname(args.markdown), exist_ok=True)
    with open(args.markdown, "w") as f:
        f.write("\n".join(table) + "\n")
    print("\n".join(table))


if __name__ == "__main__":
    main()
