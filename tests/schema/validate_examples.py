#!/usr/bin/python3
"""Checks every example in rigs/ against its JSON Schema (rigs/rig.schema.json for *.rig.json,
rigs/scene.schema.json for *.scene.json and a rig's "scene" member, the rig schema's material for
*.material.json), and that the schemas
themselves are valid. Prints 'N passed, M failed' and exits non-zero on any failure."""
import json
import pathlib
import sys

import jsonschema

rigs = pathlib.Path(sys.argv[1])
rig_schema = json.loads((rigs / "rig.schema.json").read_text())
scene_schema = json.loads((rigs / "scene.schema.json").read_text())
checks = []
for schema in (rig_schema, scene_schema):
    jsonschema.Draft202012Validator.check_schema(schema)
for path in sorted(rigs.glob("*.rig.json")):
    doc = json.loads(path.read_text())
    checks.append((path.name, rig_schema, doc))
    if "scene" in doc:
        checks.append((path.name + "#/scene", scene_schema, doc["scene"]))
for path in sorted(rigs.glob("*.scene.json")):
    checks.append((path.name, scene_schema, json.loads(path.read_text())))
# A material file (sweep-fit --material) is a rig sweep's "material" on its own.
material_schema = {"$schema": rig_schema.get("$schema"), "$defs": rig_schema["$defs"], "$ref": "#/$defs/material"}
for path in sorted(rigs.glob("*.material.json")):
    checks.append((path.name, material_schema, json.loads(path.read_text())))
failed = 0
for name, schema, doc in checks:
    errors = sorted(jsonschema.Draft202012Validator(schema).iter_errors(doc), key=lambda e: list(e.path))
    for e in errors:
        print(f"{name}: /{'/'.join(map(str, e.path))}: {e.message}")
    failed += bool(errors)
if not checks:
    print("no examples found")
    failed = 1
print(f"{len(checks) - failed} passed, {failed} failed")
sys.exit(1 if failed else 0)
