"""Times Blender's own BVH → FBX inside Blender (its start-up not counted): the BVH importer,
then the FBX exporter with every frame baked, in a fresh empty scene each round.

    PYTHON bvh_to_fbx_time.py IN.bvh OUT.fbx [ROUNDS]     (PYTHON: one with `bpy`, Blender 5.2)
    blender -b --factory-startup --python bvh_to_fbx_time.py -- IN.bvh OUT.fbx [ROUNDS]

Prints `import S export S total S` per round, then `median total S` and `fastest total S`. It
is the yardstick of `bvhview convert IN.bvh -o OUT.fbx` (a whole command, its start-up counted):
TESTING.md gives the figures and how they were taken.
"""

import statistics
import sys
import time

import bpy


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else sys.argv[1:]
    source, target = argv[0], argv[1]
    rounds = int(argv[2]) if len(argv) > 2 else 3
    totals = []
    for _ in range(rounds):
        bpy.ops.wm.read_factory_settings(use_empty=True)
        start = time.perf_counter()
        bpy.ops.import_anim.bvh(filepath=source, update_scene_fps=True, update_scene_duration=True)
        imported = time.perf_counter()
        bpy.ops.export_scene.fbx(
            filepath=target,
            bake_anim=True,
            bake_anim_simplify_factor=0.0,
            add_leaf_bones=False,
        )
        done = time.perf_counter()
        totals.append(done - start)
        print(f"import {imported - start:.4f} export {done - imported:.4f} total {done - start:.4f}")
    print(f"median total {statistics.median(totals):.4f}")
    print(f"fastest total {min(totals):.4f}")


main()
