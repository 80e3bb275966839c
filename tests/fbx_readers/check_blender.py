"""What Blender's FBX importer reads of an FBX file, as JSON on stdout, for compare.py.

Runs under a Python that has Blender as a module (`pip install bpy==5.2.3`, Python 3.13), not
inside the `blender` program:

    python check_blender.py FILE.fbx FRAMES F1 F2 …              (FRAMES: the take's frame count)
    python check_blender.py --mesh OUT.npy FILE.fbx FRAMES F1 F2 …

The importer is Blender 5.2's own, ufbx-based `wm.fbx_import` (not the old Python add-on
`import_scene.fbx`), with its defaults, in an empty factory scene. The dump has the shape
check_three.mjs prints:

- `messages`: every report the operator made (an error also stops it with RuntimeError) and every
  line printed to stdout or stderr during the import that says "warn" or "error" (Blender's log,
  `io.fbx | WARNING …`); the importer's "FBX import of '…' took …" is not one.
- `nodes`: the Armature object first, as the root, then its bones in the armature's order, each
  with its parent's index, then any other object. Blender makes bones, not nodes: the file's
  joints and End Sites (LimbNodes) become bones of one armature object the importer makes for the
  scene's root, which is not a node of the file, so compare.py leaves it out as it leaves out
  assimp's RootNode and three.js's Group. A bone's head is where its joint is.
- `animations`: one per action (an FBX take's layer), named as Blender names it (the stack's
  name). Blender samples each animated node's whole transform at every key time of any of its
  curves and keys location, rotation_quaternion and scale there; a bone with curves is a
  channel, its keys counted. The duration is first to last key, in frames, at the scene's rate
  (which the importer sets from the file).
- `unit_scale_factor` and `frames[].positions`: Blender's world is Z up and in metres; the
  importer puts the file's units and axes into the Armature object's matrix (ufbx's root scale,
  UnitScaleFactor / 100, and its turn to Z up). The positions are the world positions
  (matrix_world @ head for a bone) divided by that scale, so in the file's units and Blender's
  axes, and `unit_scale_factor` is that scale × 100; compare.py's positions × factor × 0.01 are
  then Blender's world metres exactly.
- a frame F is played at time F / (FRAMES − 1) × the duration, at Blender frame
  first key + time × rate (the importer puts FBX time 0 at frame 1: `anim_offset`), set with
  frame_set(whole, subframe=fraction).

With `--mesh OUT.npy` it also writes every MESH object's evaluated vertices (the armature's
deformation applied: the depsgraph's mesh) at those frames in Blender's world coordinates
(metres, Z up), the meshes concatenated in the order the importer made them (the file's), as a
float64 array (frames, vertices, 3); `mesh_objects` in the dump names them with their counts
and `mesh_file` says where the array is (for compare_mesh.py).
"""

import json
import math
import os
import re
import sys
import tempfile
import time

import bpy
import numpy as np  # bpy's own dependency


def captured(call):
    """Runs call() with file descriptors 1 and 2 sent to a file; (result, error, text printed)."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = os.dup(1), os.dup(2)
    with tempfile.TemporaryFile(mode="w+b") as sink:
        os.dup2(sink.fileno(), 1)
        os.dup2(sink.fileno(), 2)
        result, error = None, None
        try:
            result = call()
        except Exception as caught:  # the operator's error report, as RuntimeError
            error = caught
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])
        sink.seek(0)
        text = sink.read().decode("utf-8", "replace")
    return result, error, text


def said(text):
    """Lines that warn or err (a log line's continuation, `| …`, joined to it)."""
    lines = []
    for line in text.splitlines():
        if not line.strip():
            continue
        if re.match(r"^\s+\|", line) and lines:
            lines[-1][1].append(line.split("|", 1)[1].strip())
            continue
        lines.append((line, []))
    out = []
    for line, more in lines:
        if re.match(r"^FBX import of '.*' took ", line):
            continue  # the importer's timing, always printed
        if re.search(r"warn|error", line, re.I):
            out.append(" ".join([line.strip()] + [m for m in more if m]))
    return out


def fcurves_of(obj):
    """The F-curves of obj's action in obj's slot (Blender 5's layered actions)."""
    data = obj.animation_data
    if data is None or data.action is None:
        return []
    curves = []
    for layer in data.action.layers:
        for strip in layer.strips:
            bag = strip.channelbag(data.action_slot) if data.action_slot else None
            if bag is not None:
                curves.extend(bag.fcurves)
    return curves


def main(argv):
    mesh_out = None
    if argv[:1] == ["--mesh"]:
        mesh_out, argv = argv[1], argv[2:]
    if len(argv) < 2:
        print("usage: python check_blender.py [--mesh OUT.npy] FILE.fbx FRAMES [FRAME …]", file=sys.stderr)
        return 2
    path, frames, asked = argv[0], int(argv[1]), [int(a) for a in argv[2:]]
    out = {"reader": f"blender {bpy.app.version_string} wm.fbx_import", "messages": []}
    started = time.perf_counter()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    result, error, text = captured(lambda: bpy.ops.wm.fbx_import(filepath=os.path.abspath(path)))
    out["messages"] = said(text)
    out["import_seconds"] = time.perf_counter() - started
    if error is not None or result != {"FINISHED"}:
        out["error"] = str(error) if error is not None else f"the operator returned {sorted(result)}"
        print(json.dumps(out))
        return 1

    scene = bpy.context.scene
    rate = scene.render.fps / scene.render.fps_base
    # The import's objects in the order it made them: the importer adds each to the scene's
    # collection in turn (bpy.data.objects is sorted by name instead).
    objects = list(scene.collection.all_objects)
    armatures = [o for o in objects if o.type == "ARMATURE"]
    others = [o for o in objects if o.type != "ARMATURE"]

    # Nodes: each armature object, then its bones; then the other objects.
    nodes, where = [], {}
    for arm in armatures:
        where[("object", arm.name)] = len(nodes)
        nodes.append(("object", arm.name, arm.parent.name if arm.parent else None))
        for bone in arm.data.bones:
            where[(arm.name, bone.name)] = len(nodes)
            nodes.append((arm.name, bone.name, bone.parent.name if bone.parent else None))
    for obj in others:
        where[("object", obj.name)] = len(nodes)
        nodes.append(("object", obj.name, obj.parent.name if obj.parent else None))

    def parent_index(owner, name, parent):
        if owner == "object":
            obj = bpy.data.objects[name]
            if obj.parent is None:
                return -1
            if obj.parent_type == "BONE" and obj.parent_bone:
                return where[(obj.parent.name, obj.parent_bone)]
            return where[("object", obj.parent.name)]
        return where[(owner, parent)] if parent else where[("object", owner)]

    out["nodes"] = [[name, parent_index(owner, name, parent)] for owner, name, parent in nodes]

    # Animations: one per action; channels are the bones (or objects) its curves move.
    out["animations"] = []
    first_key, last_key = None, None
    for action in bpy.data.actions:
        channels = {}
        lo, hi = math.inf, -math.inf
        for obj in objects:
            if obj.animation_data is None or obj.animation_data.action != action:
                continue
            for curve in fcurves_of(obj):
                found = re.match(r'^pose\.bones\["(.*)"\]\.(\w+)$', curve.data_path)
                node, prop = (found.group(1), found.group(2)) if found else (obj.name, curve.data_path)
                keys = curve.keyframe_points
                entry = channels.setdefault(node, {"node": node, "position_keys": 0, "rotation_keys": 0})
                if prop == "location":
                    entry["position_keys"] = max(entry["position_keys"], len(keys))
                elif prop.startswith("rotation"):
                    entry["rotation_keys"] = max(entry["rotation_keys"], len(keys))
                if len(keys):
                    lo, hi = min(lo, keys[0].co.x), max(hi, keys[-1].co.x)
        if lo > hi:
            lo = hi = 0.0
        if first_key is None and channels:
            first_key, last_key = lo, hi
        out["animations"].append(
            {
                "name": action.name,
                "duration": hi - lo,
                "ticks_per_second": rate,
                "first_key_frame": lo,
                "channels": list(channels.values()),
            }
        )
    if first_key is None:
        first_key = last_key = 1.0  # no animation: the importer's frame for time 0

    # The file's units: the scale the importer gave the Armature object (ufbx's root scale).
    scale = 0.01
    if armatures:
        scale = armatures[0].matrix_world.to_scale()[0]
    out["unit_scale_factor"] = scale * 100.0
    out["blender_rate"] = rate

    meshes = [o for o in objects if o.type == "MESH"]
    out["mesh_objects"] = [[o.name, len(o.data.vertices)] for o in meshes]
    if mesh_out:
        out["mesh_file"] = os.path.abspath(mesh_out)
    mesh_frames = []
    out["frames"] = []
    duration = last_key - first_key
    for frame in asked:
        at = first_key + (duration * frame / (frames - 1) if frames > 1 else 0.0)
        whole = math.floor(at)
        scene.frame_set(whole, subframe=at - whole)
        graph = bpy.context.evaluated_depsgraph_get()
        positions = []
        for owner, name, _ in nodes:
            if owner == "object":
                world = bpy.data.objects[name].evaluated_get(graph).matrix_world.translation
            else:
                arm = bpy.data.objects[owner].evaluated_get(graph)
                world = arm.matrix_world @ arm.pose.bones[name].head
            positions.append([v / scale for v in world])
        out["frames"].append({"frame": frame, "blender_frame": at, "positions": positions})
        if mesh_out:
            every = []
            for mesh in meshes:
                evaluated = mesh.evaluated_get(graph)
                data = evaluated.to_mesh()
                co = np.empty(len(data.vertices) * 3, dtype=np.float64)
                data.vertices.foreach_get("co", co)
                world = np.array(evaluated.matrix_world, dtype=np.float64)
                every.append(co.reshape(-1, 3) @ world[:3, :3].T + world[:3, 3])
                evaluated.to_mesh_clear()
            mesh_frames.append(np.concatenate(every) if every else np.zeros((0, 3)))
    if mesh_out:
        np.save(mesh_out, np.array(mesh_frames, dtype=np.float64).reshape(len(asked), -1, 3))
    out["seconds"] = time.perf_counter() - started
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
