#!/usr/bin/env python3
"""Checks that the reference pages document everything a user can set: every key of the scene
schema (rigs/scene.schema.json) appears in docs/scenes.md, and every option each tool's --help
lists appears in docs/tools.md. A key or option counts as documented when the page shows it in
code (between backquotes). Exit 0 when all are, else 1 with the missing ones listed.

    tools/check-docs.py BUILD_DIR      (the folder holding tools/sweep-fit/sweep-fit, …)
"""
import json
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
TOOLS = ["sweep-fit", "sweep-bind", "sweep-sim"]


def schema_keys(node, out):
    """Every property name anywhere in a JSON schema."""
    if isinstance(node, dict):
        for name, sub in node.get("properties", {}).items():
            out.add(name)
            schema_keys(sub, out)
        for key, sub in node.items():
            if key != "properties":
                schema_keys(sub, out)
    elif isinstance(node, list):
        for sub in node:
            schema_keys(sub, out)
    return out


def in_code(page, word):
    """Whether `word` appears as a whole word inside a code span of the page."""
    pattern = re.compile(r"(?<![\w-])" + re.escape(word) + r"(?![\w-])")
    return any(pattern.search(span) for span in re.findall(r"`([^`]*)`", page))


def help_options(binary):
    text = subprocess.run([binary, "--help"], capture_output=True, text=True, check=True).stdout
    return sorted(set(re.findall(r"(?<![\w-])(--[a-z][a-z0-9-]*)", text)) - {"--help", "--version"})


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    build = pathlib.Path(sys.argv[1])
    missing = []
    scenes = (ROOT / "docs/scenes.md").read_text()
    schema = json.loads((ROOT / "rigs/scene.schema.json").read_text())
    for key in sorted(schema_keys(schema, set())):
        if not in_code(scenes, key):
            missing.append(f"docs/scenes.md: scene key {key!r} (rigs/scene.schema.json) is not documented")
    tools = (ROOT / "docs/tools.md").read_text()
    for tool in TOOLS:
        for option in help_options(build / "tools" / tool / tool):
            if not in_code(tools, option):
                missing.append(f"docs/tools.md: {tool} {option} (from its --help) is not documented")
    for line in missing:
        print(line, file=sys.stderr)
    print(f"check-docs: {'FAILED' if missing else 'ok'} ({len(missing)} missing)", file=sys.stderr)
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
