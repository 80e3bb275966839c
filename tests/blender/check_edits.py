"""Checks `bvhview convert` edits against Blender's own BVH importer (run inside Blender):

    blender -b --factory-startup --python tests/blender/check_edits.py -- \
        ORIGINAL.bvh EDITED.bvh KIND [ARG] [--tolerance T]

KIND is how Blender does the same edit while importing ORIGINAL, compared with EDITED imported
plainly:
    scale S     ORIGINAL with global_scale=S
    up-z        ORIGINAL with the default axes (Y up); EDITED (written Z-up) with axis_up='Z',
                axis_forward='Y', which Blender maps to its world unchanged
    up-y        ORIGINAL (Z-up) with axis_up='Z', axis_forward='Y'; EDITED with the default axes
    frames A    EDITED's frame k is ORIGINAL's frame A + k
    fps K       EDITED's frame k is ORIGINAL's frame K·k (a rate divided by a whole K)
Every pose bone's head and tail in world space are compared at EDITED's first, second, middle
and last frames. Prints the worst distance as a fraction of the armature's rest height, then
PASS or FAIL; exits 0 on PASS, 1 on FAIL, 2 on a usage error.
"""

import sys

import bpy
from mathutils import Vector


def arguments():
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    tolerance = 1e-4
    if "--tolerance" in args:
        at = args.index("--tolerance")
        tolerance = float(args[at + 1])
        del args[at:at + 2]
    if len(args) < 3:
        print(__doc__)
        sys.exit(2)
    return args[0], args[1], args[2], args[3:], tolerance


def patch_importer():
    """Blender 3.4's importer opens files with mode 'rU', which the Python 3.11 that Debian's
    Blender runs no longer accepts; it gets 'r' (universal newlines are the default anyway)."""
    import builtins

    import io_anim_bvh.import_bvh as importer

    def open_without_u(path, mode="r", *args, **kwargs):
        return builtins.open(path, mode.replace("U", ""), *args, **kwargs)

    importer.open = open_without_u


def clear():
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()


def load(path, **options):
    before = set(bpy.data.objects)
    bpy.ops.import_anim.bvh(filepath=path, rotate_mode="NATIVE", frame_start=0, **options)
    (armature,) = [o for o in bpy.data.objects if o not in before and o.type == "ARMATURE"]
    action = armature.animation_data.action
    first, last = (int(round(f)) for f in action.frame_range)
    return armature, first, last


def points(armature, frame):
    bpy.context.scene.frame_set(frame)
    bpy.context.view_layer.update()
    world = armature.matrix_world
    out = {}
    for bone in armature.pose.bones:
        out[bone.name + ".head"] = world @ bone.head
        # A bone of no length (a joint without End Site or child straight along it) gets a
        # made-up tail from the importer; only real tails (End Sites, children) are compared.
        if bone.bone.length > 1e-3 * bone.id_data.dimensions.length:
            out[bone.name + ".tail"] = world @ bone.tail
    return out


def main():
    original, edited, kind, extra, tolerance = arguments()
    patch_importer()
    clear()
    if kind == "scale":
        theirs = load(original, global_scale=float(extra[0]))
        ours = load(edited)
        step, offset = 1, 0
    elif kind == "up-z":
        theirs = load(original)
        ours = load(edited, axis_up="Z", axis_forward="Y")
        step, offset = 1, 0
    elif kind == "up-y":
        theirs = load(original, axis_up="Z", axis_forward="Y")
        ours = load(edited)
        step, offset = 1, 0
    elif kind == "frames":
        theirs = load(original)
        ours = load(edited)
        step, offset = 1, int(extra[0])
    elif kind == "fps":
        theirs = load(original)
        ours = load(edited)
        step, offset = int(extra[0]), 0
    else:
        print(__doc__)
        sys.exit(2)
    (their_armature, their_first, _), (our_armature, first, last) = theirs, ours
    rest = [their_armature.matrix_world @ b.head_local for b in their_armature.data.bones]
    rest += [their_armature.matrix_world @ b.tail_local for b in their_armature.data.bones]
    zs = [p.z for p in rest]
    height = max(zs) - min(zs)
    worst = 0.0
    for frame in sorted({first, first + 1, (first + last) // 2, last}):
        a = points(their_armature, their_first + offset + step * (frame - first))
        b = points(our_armature, frame)
        if set(a) != set(b):
            print("the two armatures have different bones")
            sys.exit(2)
        here = max((a[k] - b[k]).length for k in a)
        print(f"frame {frame}: worst {here:.3e} = {here / height:.3e} of the height {height:.4g}")
        worst = max(worst, here)
    verdict = "PASS" if worst <= tolerance * height else "FAIL"
    print(f"{verdict}: {kind} {' '.join(extra)}: worst {worst / height:.3e} of the height "
          f"(tolerance {tolerance:.0e})")
    sys.exit(0 if verdict == "PASS" else 1)


main()
