#!/usr/bin/python3
"""Checks what the tools write against rigs/rig.schema.json, not only the hand-written examples:
sweep-fit fits the committed bent tube (a sweep with part seeds, then a second one in material mode
added to the same rig), a stretch of a generated torus cut at its tip too (version 2) and, where CGAL's meshes are installed, every part of the diplodocus
(--all); each written rig must validate against the schema (a sweep, its part, sections, springs
and material allow no member the schema does not describe; the top level does) and hold the sweeps
asked for. The tools' JSON reports have no schema.

usage: validate_tool_rigs.py SWEEP-FIT SOURCE_DIR SCRATCH_DIR [tube|diplodocus]
(both when neither is given; the diplodocus is its own test so that the default sanitizer run,
tools/run-sanitizers.sh, leaves its fits out like the other tests on CGAL's meshes)"""
import json
import pathlib
import shutil
import subprocess
import sys

import jsonschema

fit_exe, source, scratch = sys.argv[1], pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
which = sys.argv[4] if len(sys.argv) > 4 else "both"
rigs = source / "rigs"
schema = json.loads((rigs / "rig.schema.json").read_text())
jsonschema.Draft202012Validator.check_schema(schema)
validator = jsonschema.Draft202012Validator(schema)
shutil.rmtree(scratch, ignore_errors=True)
scratch.mkdir(parents=True)


def fit(*args):
    run = subprocess.run([fit_exe, *map(str, args)], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"sweep-fit {' '.join(map(str, args))}: exit {run.returncode}\n{run.stderr}")


failed = 0
checked = 0


def check(rig_path, names, material_sweeps=()):
    """The rig at rig_path validates and holds exactly the sweeps `names` (those in
    material_sweeps in material mode, the others not)."""
    global failed, checked
    doc = json.loads(rig_path.read_text())
    problems = [f"/{'/'.join(map(str, e.path))}: {e.message}"
                for e in sorted(validator.iter_errors(doc), key=lambda e: list(e.path))]
    written = [s.get("name") for s in doc.get("sweeps", [])]
    if written != list(names):
        problems.append(f"sweeps {written}, expected {list(names)}")
    for s in doc.get("sweeps", []):
        if ("material" in s) != (s.get("name") in material_sweeps):
            problems.append(f"sweep {s.get('name')}: material {'present' if 'material' in s else 'missing'}")
    for p in problems:
        print(f"{rig_path.name}: {p}")
    failed += bool(problems)
    checked += 1


# The bent tube (ring by ring, then the root and the tip cap centres: the last vertex is the tip).
if which in ("tube", "both"):
    tube = source / "meshes" / "tube_bent.obj"
    tip_vertex = sum(1 for line in tube.open() if line.startswith("v ")) - 1
    rig = scratch / "tube.rig.json"
    # The paper's springs (--springs), then a material file: a rig of both kinds.
    fit(tube, "-o", rig, "--name", "tube", "--root", "0,0,0", "--tip-vertex", tip_vertex, "--springs")
    check(rig, ["tube"])
    fit(tube, "-o", rig, "--name", "tube-material", "--root", "0,0,0", "--tip-vertex", tip_vertex,
        "--material", rigs / "diplodocus-tail.material.json", "-k", 12, "-n", 16)
    check(rig, ["tube", "tube-material"], material_sweeps=["tube-material"])

# A stretch of a torus, root and tip mid-tube: cut at the tip too, a version 2 rig.
if which in ("tube", "both"):
    import math
    torus = scratch / "torus.off"
    rings, segments = 128, 16
    lines = ["OFF", f"{rings * segments} {rings * segments} 0"]
    for i in range(rings):
        u = 2 * math.pi * i / rings
        for j in range(segments):
            v = 2 * math.pi * j / segments
            rho = 1 + 0.15 * math.cos(v)
            lines.append(f"{rho * math.cos(u):.17g} {rho * math.sin(u):.17g} {0.15 * math.sin(v):.17g}")
    for i in range(rings):
        for j in range(segments):
            ids = [(i % rings) * segments + j, ((i + 1) % rings) * segments + j,
                   ((i + 1) % rings) * segments + (j + 1) % segments, (i % rings) * segments + (j + 1) % segments]
            lines.append("4 " + " ".join(map(str, ids)))
    torus.write_text("\n".join(lines) + "\n")
    rig = scratch / "torus.rig.json"
    fit(torus, "-o", rig, "--name", "hose", "--root", "1.15,0,0", "--tip", "0,1.15,0")
    check(rig, ["hose"], material_sweeps=["hose"])  # no option: the preset its name chooses
    doc = json.loads(rig.read_text())
    if doc["version"] != 2 or doc["sweeps"][0]["part"].get("tip_cut") is not True:
        print(f"{rig.name}: expected version 2 and part.tip_cut true, got version {doc['version']}, "
              f"part {doc['sweeps'][0]['part']}")
        failed += 1

dino = source / "meshes" / "cgal" / "diplodocus.off"
if which in ("diplodocus", "both") and dino.exists():
    rig = scratch / "diplodocus.rig.json"
    fit(dino, "--list", "--report", scratch / "parts.json")
    parts = [p["name"] for p in json.loads((scratch / "parts.json").read_text())["parts"]]
    if not parts:
        sys.exit("sweep-fit --list found no part of the diplodocus")
    # --force: what is written when a part breaks a limit must validate too.
    fit(dino, "--all", "--force", "-o", rig)
    check(rig, parts, material_sweeps=parts)  # each the preset its name chooses
elif which in ("diplodocus", "both"):
    print("CGAL's diplodocus is absent (tools/setup-deps.sh): not checked")
    if which == "diplodocus":
        sys.exit(77)  # skipped (SKIP_RETURN_CODE in tests/schema/CMakeLists.txt)

print(f"{checked - failed} passed, {failed} failed")
sys.exit(1 if failed else 0)
