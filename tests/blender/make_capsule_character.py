"""Builds bvhview's test character "capsule man" and writes it as a Mixamo-style FBX and a glTF.

Run with Blender 5.2 as a Python module (bpy from PyPI, Python 3.13):

    python tests/blender/make_capsule_character.py OUT_FOLDER [--fine]

The figure is a chain of capsules around an armature with Mixamo's `mixamorig:` bone names,
weighted by bvhview's own rule (each vertex to every bone within reach, falling off with
distance: up to eight influences a vertex), animated for 30 frames at 30 fps (a walk in place
with a turn of the spine and a nod). Blender's FBX exporter writes `capsule_mixamo.fbx`, its
glTF exporter (every influence kept) `capsule_mixamo.glb`. With `--fine`, the capsules have
36 sides and 38 rings (30,888 vertices: the bench's 30,000-vertex character), written as
`capsule_fine.glb` only.
"""

import math
import os
import sys

import bpy
from mathutils import Vector

FINE = sys.argv[-1] == "--fine"
OUT = sys.argv[-2] if FINE else sys.argv[-1]
PREFIX = "mixamorig:"

# (name, parent, head, tail) in metres, Z up, facing -Y (Blender's front).
BONES = [
    ("Hips", None, (0, 0, 0.95), (0, 0, 1.05)),
    ("Spine", "Hips", (0, 0, 1.05), (0, 0, 1.18)),
    ("Spine1", "Spine", (0, 0, 1.18), (0, 0, 1.31)),
    ("Spine2", "Spine1", (0, 0, 1.31), (0, 0, 1.44)),
    ("Neck", "Spine2", (0, 0, 1.44), (0, 0, 1.54)),
    ("Head", "Neck", (0, 0, 1.54), (0, 0, 1.74)),
]
for side, sign in (("Left", 1), ("Right", -1)):
    s = sign
    BONES += [
        (f"{side}Shoulder", "Spine2", (0.04 * s, 0, 1.40), (0.17 * s, 0, 1.40)),
        (f"{side}Arm", f"{side}Shoulder", (0.17 * s, 0, 1.40), (0.45 * s, 0, 1.40)),
        (f"{side}ForeArm", f"{side}Arm", (0.45 * s, 0, 1.40), (0.70 * s, 0, 1.40)),
        (f"{side}Hand", f"{side}ForeArm", (0.70 * s, 0, 1.40), (0.80 * s, 0, 1.40)),
        (f"{side}UpLeg", "Hips", (0.10 * s, 0, 0.95), (0.10 * s, 0, 0.52)),
        (f"{side}Leg", f"{side}UpLeg", (0.10 * s, 0, 0.52), (0.10 * s, 0, 0.10)),
        (f"{side}Foot", f"{side}Leg", (0.10 * s, 0, 0.10), (0.10 * s, -0.12, 0.02)),
        (f"{side}ToeBase", f"{side}Foot", (0.10 * s, -0.12, 0.02), (0.10 * s, -0.20, 0.02)),
    ]
RADIUS = {"Head": 0.11, "Hips": 0.13, "Spine": 0.13, "Spine1": 0.13, "Spine2": 0.14, "Neck": 0.05}


def radius(name):
    for key, r in RADIUS.items():
        if name == key:
            return r
    if "Leg" in name:
        return 0.065
    if "Arm" in name:
        return 0.045
    if "Foot" in name or "Toe" in name:
        return 0.045
    return 0.04


def main():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = 30
    scene.frame_start, scene.frame_end = 1, 30

    armature = bpy.data.armatures.new("capsule_man")
    rig = bpy.data.objects.new("Armature", armature)
    scene.collection.objects.link(rig)
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="EDIT")
    for name, parent, head, tail in BONES:
        bone = armature.edit_bones.new(PREFIX + name)
        bone.head, bone.tail = Vector(head), Vector(tail)
        if parent:
            bone.parent = armature.edit_bones[PREFIX + parent]
            bone.use_connect = False
    bpy.ops.object.mode_set(mode="OBJECT")

    # One mesh: a capsule (a UV sphere stretched along the bone) around every bone.
    verts, faces = [], []
    rings, sides = (38, 36) if FINE else (10, 12)
    for name, _, head, tail in BONES:
        a, b = Vector(head), Vector(tail)
        axis = b - a
        length = axis.length
        r = radius(name)
        z = axis.normalized()
        x = z.orthogonal().normalized()
        y = z.cross(x)
        first = len(verts)
        for i in range(rings + 1):
            t = i / rings
            # Around the bone's middle, rounded at both ends past the joints by the radius.
            along = -r + t * (length + 2 * r)
            cap = max(abs(along - length / 2) - length / 2, 0.0)
            ring_r = math.sqrt(max(r * r - cap * cap, 0.0))
            for j in range(sides):
                phi = 2 * math.pi * j / sides
                p = a + z * along + (x * math.cos(phi) + y * math.sin(phi)) * ring_r
                verts.append(p)
        for i in range(rings):
            for j in range(sides):
                k = first + i * sides + j
                n = first + i * sides + (j + 1) % sides
                faces.append((k, n, n + sides, k + sides))
    mesh = bpy.data.meshes.new("capsule_man_body")
    mesh.from_pydata([tuple(v) for v in verts], [], faces)
    if FINE:
        # Smooth shading: one normal a vertex, so the glTF keeps one vertex per capsule point.
        for polygon in mesh.polygons:
            polygon.use_smooth = True
    mesh.update()
    body = bpy.data.objects.new("Body", mesh)
    scene.collection.objects.link(body)
    body.parent = rig
    modifier = body.modifiers.new("Armature", "ARMATURE")
    modifier.object = rig

    # Weights: every bone whose segment lies within reach of the vertex, falling off smoothly
    # with the distance to the segment; all kept (up to eight a vertex).
    groups = {name: body.vertex_groups.new(name=PREFIX + name) for name, *_ in BONES}
    for index, p in enumerate(verts):
        weights = []
        for name, _, head, tail in BONES:
            a, b = Vector(head), Vector(tail)
            ab = b - a
            t = max(0.0, min(1.0, (p - a).dot(ab) / ab.length_squared))
            d = (p - (a + ab * t)).length
            reach = radius(name) * 2.2
            if d < reach:
                weights.append((name, (1.0 - d / reach) ** 3))
        weights.sort(key=lambda w: -w[1])
        weights = weights[:8]
        total = sum(w for _, w in weights)
        for name, w in weights:
            groups[name].add([index], w / total, "REPLACE")

    # 30 frames: legs and arms swing, the spine turns, the head nods, the hips bob and sway.
    bpy.context.view_layer.objects.active = rig
    bpy.ops.object.mode_set(mode="POSE")
    for frame in range(1, 31):
        phase = 2 * math.pi * (frame - 1) / 30
        pose = rig.pose.bones
        for bone in pose:
            bone.rotation_mode = "XYZ"

        def key(name, x=0.0, y=0.0, z=0.0):
            bone = pose[PREFIX + name]
            bone.rotation_euler = (x, y, z)
            bone.keyframe_insert("rotation_euler", frame=frame)

        swing = 0.5 * math.sin(phase)
        key("LeftUpLeg", x=swing)
        key("RightUpLeg", x=-swing)
        key("LeftLeg", x=-0.6 * max(0.0, -math.sin(phase)))
        key("RightLeg", x=-0.6 * max(0.0, math.sin(phase)))
        key("LeftArm", x=-0.4 * math.sin(phase), z=0.9)
        key("RightArm", x=0.4 * math.sin(phase), z=-0.9)
        key("LeftForeArm", x=0.3 + 0.3 * math.sin(phase))
        key("RightForeArm", x=0.3 - 0.3 * math.sin(phase))
        key("Spine1", y=0.25 * math.sin(phase))
        key("Head", x=0.2 * math.sin(2 * phase))
        hips = pose[PREFIX + "Hips"]
        hips.location = (0.03 * math.sin(phase), 0.02 * math.cos(2 * phase), 0.0)
        hips.keyframe_insert("location", frame=frame)
    bpy.ops.object.mode_set(mode="OBJECT")

    os.makedirs(OUT, exist_ok=True)
    if FINE:
        bpy.ops.export_scene.gltf(
            filepath=os.path.join(OUT, "capsule_fine.glb"),
            export_format="GLB",
            export_all_influences=True,
            export_animations=True,
            export_force_sampling=True,
        )
        return
    bpy.ops.export_scene.fbx(
        filepath=os.path.join(OUT, "capsule_mixamo.fbx"),
        add_leaf_bones=False,
        bake_anim=True,
        bake_anim_use_all_actions=False,
        bake_anim_use_nla_strips=False,
        bake_anim_simplify_factor=0.0,
    )
    bpy.ops.export_scene.gltf(
        filepath=os.path.join(OUT, "capsule_mixamo.glb"),
        export_format="GLB",
        export_all_influences=True,
        export_animations=True,
        export_force_sampling=True,
    )


main()
