"""Blender's evaluated mesh of a character file at given times, for tests/motion/character_skinning.rs.

Run with Blender 5.2 as a Python module (bpy from PyPI, Python 3.13):

    python tests/blender/evaluated_mesh.py FILE.fbx|.glb OUT.npy SECONDS,SECONDS,...

Imports FILE with Blender's own importer (`wm.fbx_import`, Blender's ufbx-based FBX importer, or
`import_scene.gltf`), sets the scene to each time (seconds as the file counts them: the FBX
importer puts second t at frame 1 + t × the scene's rate, the glTF importer at frame t × the
rate), and writes every skinned mesh's evaluated vertices in world coordinates,
meshes in name order, turned from Blender's Z up to Y up (x, z, −y), as a float32 array of shape
(times, vertices, 3).
"""

import sys

import bpy
import numpy as np

path, out, times = sys.argv[-3], sys.argv[-2], [float(t) for t in sys.argv[-1].split(",")]
bpy.ops.wm.read_factory_settings(use_empty=True)
fbx = path.lower().endswith(".fbx")
if fbx:
    bpy.ops.wm.fbx_import(filepath=path)
else:
    bpy.ops.import_scene.gltf(filepath=path)
scene = bpy.context.scene
rate = scene.render.fps / scene.render.fps_base
# The skinned meshes (the glTF importer adds a mesh of its own for the bones' shapes).
meshes = sorted(
    (o for o in scene.objects if o.type == "MESH" and any(m.type == "ARMATURE" for m in o.modifiers)),
    key=lambda o: o.name,
)
frames = []
for seconds in times:
    frame = (1.0 if fbx else 0.0) + seconds * rate
    scene.frame_set(int(frame), subframe=frame - int(frame))
    graph = bpy.context.evaluated_depsgraph_get()
    every = []
    for mesh in meshes:
        evaluated = mesh.evaluated_get(graph)
        data = evaluated.to_mesh()
        co = np.empty(len(data.vertices) * 3, dtype=np.float64)
        data.vertices.foreach_get("co", co)
        world = np.array(evaluated.matrix_world)
        co = co.reshape(-1, 3) @ world[:3, :3].T + world[:3, 3]
        every.append(np.stack([co[:, 0], co[:, 2], -co[:, 1]], axis=1))
        evaluated.to_mesh_clear()
    frames.append(np.concatenate(every))
np.save(out, np.array(frames, dtype=np.float32))
print(f"{path}: {len(meshes)} meshes, {frames[0].shape[0]} vertices, {len(times)} times at {rate} fps")
