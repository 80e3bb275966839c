"""Blender's own import of an FBX or glTF file against bvhview's reading of it.

Runs inside Blender:

    bvhview positions -q FILE -o FILE.csv
    blender -b --factory-startup --python tests/blender/check_import.py -- FILE FILE.csv FRAME_TIME

It imports FILE with Blender's importer (FBX: `import_scene.fbx`, leaf bones kept; glTF:
`import_scene.gltf`), and for every frame of the CSV compares the world position of each bone's
head with bvhview's position of the joint of the same name. Blender's Z up is turned back into
Y up, (X, Y, Z) → (X, Z, −Y). bvhview's frame f is at f × FRAME_TIME seconds after the take's
first key, which Blender puts at the action's first frame, at the scene's frame rate.

Prints the worst distance over all frames as a fraction of the figure's height (the spread of
frame 0's joints) and exits 0 when it is within 1e-4 (PASS), 1 when not (FAIL), 2 when nothing
could be compared.
"""

import csv
import math
import os
import sys

import bpy

TOLERANCE = 1e-4


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    if len(argv) != 3:
        print("usage: blender -b --python check_import.py -- FILE POSITIONS.csv FRAME_TIME")
        sys.exit(2)
    path, table, frame_time = argv[0], argv[1], float(argv[2])
    bpy.ops.wm.read_factory_settings(use_empty=True)
    extension = os.path.splitext(path)[1].lower()
    try:
        if extension == ".fbx":
            bpy.ops.import_scene.fbx(filepath=path, ignore_leaf_bones=False)
        else:
            bpy.ops.import_scene.gltf(filepath=path)
    except RuntimeError as error:
        # Blender 3.4's FBX importer reads binary FBX 7.1 and later only.
        message = str(error).strip().splitlines()[-1]
        print(f"check_import: Blender's importer cannot read it: {message}")
        sys.exit(2)

    wanted = {}
    for row in csv.DictReader(open(table)):
        wanted.setdefault(int(row["frame"]), {})[row["joint"]] = (
            float(row["x"]),
            float(row["y"]),
            float(row["z"]),
        )
    if not wanted:
        print("check_import: no frames in", table)
        sys.exit(2)
    first = list(wanted[0].values())
    height = max(max(p[i] for p in first) - min(p[i] for p in first) for i in range(3))
    # One node standing alone has no height: its distance counts as is.
    height = height if height > 0 else 1.0

    scene = bpy.context.scene
    armatures = [o for o in scene.objects if o.type == "ARMATURE"]
    # Without bones, bvhview's joints are the file's nodes: Blender's objects of the same names.
    objects = [o for o in scene.objects if o.type != "ARMATURE"]
    fps = scene.render.fps / scene.render.fps_base
    start = None
    for armature in scene.objects:
        data = armature.animation_data
        if data and data.action:
            begin = data.action.frame_range[0]
            start = begin if start is None else min(start, begin)
    start = start or scene.frame_start

    worst, where, compared = 0.0, None, 0
    for frame in sorted(wanted):
        at = start + frame * frame_time * fps
        whole = math.floor(at)
        scene.frame_set(int(whole), subframe=at - whole)
        for armature in armatures:
            for bone in armature.pose.bones:
                want = wanted[frame].get(bone.name)
                if want is None:
                    continue
                x, y, z = armature.matrix_world @ bone.head
                got = (x, z, -y)
                distance = math.dist(got, want) / height
                compared += 1
                if distance > worst:
                    worst, where = distance, (frame, bone.name, got, want)
        for thing in objects:
            want = wanted[frame].get(thing.name)
            if want is None:
                continue
            x, y, z = thing.matrix_world.translation
            got = (x, z, -y)
            distance = math.dist(got, want) / height
            compared += 1
            if distance > worst:
                worst, where = distance, (frame, thing.name, got, want)
    print(f"height {height:.6g}, {compared} bone heads compared over {len(wanted)} frames")
    if compared == 0:
        print("check_import: no bone or object of Blender's import has a joint's name")
        sys.exit(2)
    print(f"worst {worst:.3g} of the height at {where}")
    if worst <= TOLERANCE:
        print("PASS")
        sys.exit(0)
    print("FAIL")
    sys.exit(1)


main()
