"""Times Blender's own import of an FBX or glTF file, inside Blender (its start-up not counted):

    blender -b --factory-startup --python tests/blender/import_time.py -- FILE [ROUNDS]

Prints `import SECONDS` per round (a fresh empty scene each time), then the median.
"""

import os
import statistics
import sys
import time

import bpy


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :]
    path, rounds = argv[0], int(argv[1]) if len(argv) > 1 else 3
    times = []
    for _ in range(rounds):
        bpy.ops.wm.read_factory_settings(use_empty=True)
        start = time.perf_counter()
        if os.path.splitext(path)[1].lower() == ".fbx":
            bpy.ops.import_scene.fbx(filepath=path)
        else:
            bpy.ops.import_scene.gltf(filepath=path)
        times.append(time.perf_counter() - start)
        print(f"import {times[-1]:.3f}")
    print(f"median {statistics.median(times):.3f}")


main()
