"""Makes the FBX and glTF references of tests/data/fbx and tests/data/gltf with Blender.

Runs inside Blender (3.4, Debian's package):

    blender -b --factory-startup --python tests/blender/export_fbx_gltf.py -- OUT_DIR SOURCE.bvh...

For each source BVH it imports the take with Blender's BVH importer (scale 1, the scene's frame
rate set to the BVH's), keeps its first 60 frames, and exports the armature with Blender's own
exporters:

- OUT_DIR/fbx/NAME.fbx: binary FBX 7.4, every frame baked (no simplification), leaf bones added
  (the BVH's End Sites), Y up and -Z forward (the exporter's defaults, which undo the BVH
  importer's conversion to Blender's Z up);
- OUT_DIR/gltf/NAME.glb: glTF binary, every frame sampled;
- OUT_DIR/gltf/NAME.gltf + NAME.bin for the first source only (the separate-files form).

bvhview reads them back in tests/formats/fbx_gltf_reading.rs and compares every joint's world position in every
frame with the source BVH's. The files are written by Blender, not by bvhview: a reference that
is not bvhview's own.
"""

import os
import sys

import bpy

# Frames kept; BVHVIEW_FRAMES=0 keeps the whole take (the speed benchmark's large files).
FRAMES = int(os.environ.get("BVHVIEW_FRAMES", "60")) or 10**9


def clear():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # Debian's Blender 3.4 runs Python 3.11, which refuses the BVH importer's open(..., 'rU');
    # plain 'r' reads the same (universal newlines are the default).
    import builtins

    import io_anim_bvh.import_bvh as importer

    importer.open = lambda path, mode="r", *rest, **named: builtins.open(
        path, mode.replace("U", ""), *rest, **named
    )


def export(source, out_dir, separate):
    clear()
    name = os.path.splitext(os.path.basename(source))[0]
    bpy.ops.import_anim.bvh(
        filepath=source,
        global_scale=1.0,
        frame_start=1,
        use_fps_scale=False,
        update_scene_fps=True,
        update_scene_duration=True,
        rotate_mode="NATIVE",
        axis_forward="-Z",
        axis_up="Y",
    )
    scene = bpy.context.scene
    scene.frame_start = 1
    scene.frame_end = min(scene.frame_end, FRAMES)
    # The exporters bake the whole action, whatever the scene's range: its keys past the last
    # kept frame go.
    for armature in [o for o in scene.objects if o.type == "ARMATURE"]:
        for curve in armature.animation_data.action.fcurves:
            points = curve.keyframe_points
            while len(points) > FRAMES:
                points.remove(points[len(points) - 1], fast=True)
            curve.update()
    print(f"{name}: fps {scene.render.fps}/{scene.render.fps_base}, frames 1..{scene.frame_end}")
    os.makedirs(os.path.join(out_dir, "fbx"), exist_ok=True)
    os.makedirs(os.path.join(out_dir, "gltf"), exist_ok=True)
    bpy.ops.export_scene.fbx(
        filepath=os.path.join(out_dir, "fbx", name + ".fbx"),
        object_types={"ARMATURE"},
        add_leaf_bones=True,
        bake_anim=True,
        bake_anim_use_all_bones=True,
        bake_anim_use_nla_strips=False,
        bake_anim_use_all_actions=False,
        bake_anim_force_startend_keying=True,
        bake_anim_step=1.0,
        bake_anim_simplify_factor=0.0,
        axis_forward="-Z",
        axis_up="Y",
    )
    forms = [("GLB", ".glb")]
    if separate:
        forms.append(("GLTF_SEPARATE", ".gltf"))
    for form, extension in forms:
        bpy.ops.export_scene.gltf(
            filepath=os.path.join(out_dir, "gltf", name + extension),
            export_format=form,
            export_animations=True,
            export_frame_range=True,
            export_force_sampling=True,
            export_frame_step=1,
            export_def_bones=False,
            export_yup=True,
        )


def main():
    argv = sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else []
    if len(argv) < 2:
        print("usage: blender -b --python export_fbx_gltf.py -- OUT_DIR SOURCE.bvh...")
        sys.exit(2)
    out_dir = argv[0]
    for i, source in enumerate(argv[1:]):
        export(os.path.abspath(source), out_dir, separate=(i == 0))


main()
