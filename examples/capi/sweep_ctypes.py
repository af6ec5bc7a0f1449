#!/usr/bin/env python3
"""libsweep from Python through ctypes: the game loop of main.c, in a tool's language.

    python3 examples/capi/sweep_ctypes.py LIBSWEEP RIG BINDING MESH.obj [SETTINGS.scene.json]

LIBSWEEP is the shared library (e.g. /opt/sweep/lib/libsweep.so). MESH.obj stands for the engine's
mesh: only its `v` lines are read, in order. The body slides along x for two seconds at 60 fps while
the parts lag; prints the largest lag every 30 frames and exits with libsweep's error code, if any.
"""
import ctypes
import math
import sys


def load(path):
    lib = ctypes.CDLL(path)
    p, i, d = ctypes.c_void_p, ctypes.c_int, ctypes.c_double
    dp, fp, s = ctypes.POINTER(d), ctypes.POINTER(ctypes.c_float), ctypes.c_char_p
    lib.sweep_open.argtypes, lib.sweep_open.restype = [s, s, s, fp, i], p
    lib.sweep_close.argtypes, lib.sweep_close.restype = [p], None
    lib.sweep_last_error.argtypes, lib.sweep_last_error.restype = [], s
    lib.sweep_set_body.argtypes, lib.sweep_set_body.restype = [p, dp], i
    lib.sweep_add_force.argtypes, lib.sweep_add_force.restype = [p, s, dp, dp, d], i
    lib.sweep_advance.argtypes, lib.sweep_advance.restype = [p, d], i
    lib.sweep_positions.argtypes, lib.sweep_positions.restype = [p, fp], i
    lib.sweep_positions_local.argtypes, lib.sweep_positions_local.restype = [p, fp], i
    return lib


def main(argv):
    if len(argv) not in (5, 6):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 1
    lib = load(argv[1])
    rest = []
    with open(argv[4]) as obj:
        for line in obj:
            if line.startswith("v "):
                rest.extend(float(x) for x in line.split()[1:4])
    count = len(rest) // 3
    rest_c = (ctypes.c_float * len(rest))(*rest)
    settings = argv[5].encode() if len(argv) == 6 else None
    inst = lib.sweep_open(argv[2].encode(), argv[3].encode(), settings, rest_c, count)
    if not inst:
        print("error:", lib.sweep_last_error().decode(), file=sys.stderr)
        return 2
    out = (ctypes.c_float * len(rest))()

    def check(code):
        if code != 0:
            raise RuntimeError(f"libsweep error {code}: {lib.sweep_last_error().decode()}")

    try:
        dt = 1 / 60
        for frame in range(1, 121):
            x = 0.3 * math.sin(math.pi * frame * dt)  # where the body is at the end of this frame
            pose = (ctypes.c_double * 16)(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, x, 0, 0, 1)
            check(lib.sweep_set_body(inst, pose))
            check(lib.sweep_advance(inst, dt))
            # In the mesh's own space (an engine draws it under the body's pose, `pose`);
            # sweep_positions gives them in world space.
            check(lib.sweep_positions_local(inst, out))
            if frame % 30 == 0:
                lag = max(math.dist(out[3 * v:3 * v + 3], rest[3 * v:3 * v + 3]) for v in range(count))
                print(f"frame {frame}  t = {frame * dt:.3f} s  largest lag {lag:.6g}")
    except RuntimeError as e:
        print("error:", e, file=sys.stderr)
        return 2
    finally:
        lib.sweep_close(inst)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
