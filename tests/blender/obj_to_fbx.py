"""Writes an FBX of an OBJ (+ .mtl, textures embedded) with Blender, coordinates as in the OBJ, for
the FBX case of the .glb bake's passthrough test (tests/tools/gltf_passthrough_test.cpp).
    blender -b --factory-startup --python-exit-code 1 --python obj_to_fbx.py -- IN.obj OUT.fbx
        [SCALE_LENGTH APPLY_SCALE_OPTIONS]
SCALE_LENGTH (the scene's unit scale, default 1: metres) and APPLY_SCALE_OPTIONS (the exporter's,
default FBX_SCALE_UNITS) make files of other units for the unit test: 1 and
FBX_SCALE_NONE write the coordinates × 100 with UnitScaleFactor 1 (centimetres).
"""
import sys

import numpy

numpy.bool = bool  # Debian's Blender 3.4 importers still use numpy.bool

import bpy  # noqa: E402

args = sys.argv[sys.argv.index("--") + 1:]
src, dst = args[:2]
scale_length = float(args[2]) if len(args) > 2 else 1.0
scale_options = args[3] if len(args) > 3 else "FBX_SCALE_UNITS"
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.wm.obj_import(filepath=src, forward_axis="Y", up_axis="Z")
bpy.context.scene.unit_settings.scale_length = scale_length
bpy.ops.export_scene.fbx(filepath=dst, path_mode="COPY", embed_textures=True, axis_forward="Y", axis_up="Z",
                         apply_scale_options=scale_options, bake_space_transform=True)
