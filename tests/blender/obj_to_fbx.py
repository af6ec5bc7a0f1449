"""Writes an FBX of an OBJ (+ .mtl, textures embedded) with Blender, coordinates as in the OBJ, for
the FBX case of the .glb bake's passthrough test (tests/tools/gltf_passthrough_test.cpp).
    blender -b --factory-startup --python-exit-code 1 --python obj_to_fbx.py -- IN.obj OUT.fbx
"""
import sys

import numpy

numpy.bool = bool  # Debian's Blender 3.4 importers still use numpy.bool

import bpy  # noqa: E402

src, dst = sys.argv[sys.argv.index("--") + 1:][:2]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.wm.obj_import(filepath=src, forward_axis="Y", up_axis="Z")
bpy.ops.export_scene.fbx(filepath=dst, path_mode="COPY", embed_textures=True, axis_forward="Y", axis_up="Z",
                         apply_scale_options="FBX_SCALE_UNITS", bake_space_transform=True)
