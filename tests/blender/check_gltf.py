"""Check a bvhview glTF export against `bvhview positions`, using Blender's importer.

Run (headless; Blender's own Python needs numpy for the glTF importer, on
Debian: `apt-get install blender python3-numpy`):

    blender -b --factory-startup --python tests/blender/check_gltf.py -- \
        FILE.glb POSITIONS.csv [options] FRAME [FRAME ...]

    FILE.glb       written by `bvhview convert IN -o FILE.glb`
    POSITIONS.csv  written by `bvhview positions IN` (CSV `frame,joint,x,y,z`;
                   it must hold every FRAME asked for, e.g. leave --frames out)
    FRAME          frame numbers (0-based) to compare

Options:
    --frame-time S    seconds per frame of the source file (`bvhview info`):
                      frame i is evaluated at time i*S, which also checks the
                      exporter's time accessor.  Without it, frame i is
                      evaluated at the i-th value of the glTF time accessor.
    --rest REST.csv   a `bvhview positions` CSV of the rest pose; the height
                      (max - min of y over all joints) is taken from it.
                      Without it, from the lowest frame in POSITIONS.csv.
    --height H        the height itself (overrides --rest)
    --tolerance F     allowed distance as a fraction of the height (1e-4)
    --bone-ends       POSITIONS.csv names ASF bones (root, then each bone's
                      END point) instead of nodes: a row named X is compared
                      with node X if X is a root node, else with X's first
                      child node (the next bone's start, or X_End).
    --skin            FILE.glb was written with `convert --skin`: also check
                      the skinned mesh as Blender deforms it (see below).

Output: one line per frame with the worst distance (file units and fraction
of the height) and the joint it occurs at, then PASS or FAIL.  With --skin,
a second line per frame for the skin (worst ring, as cylinder j->c ring r).
Exit code 0 on PASS, 1 on FAIL, 2 on a usage or matching error.

What Blender 3.4's importer does (io_scene_gltf2 3.4.50), and how it is undone
here:
  * Nodes without a skin or mesh become EMPTY objects (no armature), one per
    glTF node, parented as in the file, named after the node (Blender renames
    duplicates to NAME.001 and truncates to 63 bytes; we match by walking the
    hierarchy, so that does not matter).
  * With a skin (`convert --skin`) there are no empties for the joints: the
    deepest common ancestor of the skin's joints (here the scene root, since
    node 0 is itself a joint) becomes one ARMATURE object named after the
    skin ("skin"), and every joint node becomes a BONE of it, parented as in
    the file and matched the same way.  A node's world position is then the
    armature's matrix_world times the pose bone's head (the bone heuristic
    only turns the edit bones; heads stay at the nodes).  The mesh node is
    moved under the armature as a MESH object ("skin.001", since "skin" is
    taken) with an Armature modifier and one vertex group per skin joint, in
    the skin's joint order.  With guess_original_bind_pose (default) the rest
    pose is taken from the inverse bind matrices.
  * Vertices: with merge_vertices=False (the default, passed explicitly) the
    importer keeps one Blender vertex per glTF vertex, in file order (it only
    drops vertices no triangle uses; every skin vertex is used).  The script
    checks this: the vertex count, and every vertex's groups and weights
    against JOINTS_0 / WEIGHTS_0.  merge_vertices=True would merge equal
    positions and reorder them.
  * numpy: the importer calls np.bool for every mesh, which numpy 1.24 (Debian
    12's python3-numpy) removed, so importing a skin fails with
    AttributeError.  The script sets numpy.bool = numpy.bool_ first (in
    Blender's Python only; nothing installed is changed).
  * Axes: a glTF point (x, y, z) becomes Blender (x, -z, y); we map the world
    position (X, Y, Z) back with x = X, y = Z, z = -Y.
  * Time: keyframes are put at frame = t * scene.render.fps (fps_base is NOT
    applied; the default scene has fps 24, fps_base 1), with no offset for
    frame_start.  F-curves are evaluated in frame units, so to see glTF time t
    we set the scene to the fractional frame t * fps with
    scene.frame_set(int, subframe=fraction).
  * Quaternions: glTF (x, y, z, w) is reordered to Blender's (w, x, y, z).
    LINEAR samplers become LINEAR f-curves (component-wise between keys; at
    the keys themselves, which is where we evaluate, that is exact).

The skin check (--skin).  bvhview's skin (src/render/body.rs) is, for every
joint j in node order and each child c of j in children order, an open
cylinder of 7 rings (ring r at t = r/6 from j's rest position a to c's rest
position b) of 10 vertices each, ring-major; a cylinder is left out when
|b - a| < size * 1e-4, size being the largest side of the bounding box of all
rest joint positions (at least 1e-3).  Rings 2, 3 and 4 (t = 1/3, 1/2, 2/3)
are weighted to j alone, so they move rigidly with j: at any frame the mean
of a ring's 10 vertices is a + (b - a) * t in j's posed frame, which is
P_j + (P_c - P_j) * t with the positions of POSITIONS.csv (as long as c has no
translation track; such cylinders would be skipped with a note).  The script
rebuilds the cylinder list from the glTF node hierarchy and the nodes' rest
TRS, checks that the mesh has 70 vertices per cylinder (else exit 2), takes
the mesh as Blender deforms it (evaluated depsgraph, to_mesh()) at each
frame, and compares those ring means with the CSV.  With --bone-ends, a node
that no CSV row names (an ASF bone's start shared with its parent's or a
sibling's: translation 0, or the same translation as a sibling) takes the
position of the node it coincides with.
"""

import csv
import json
import math
import struct
import sys
import warnings

import bpy
import numpy


# ---------------------------------------------------------------- arguments

def usage(msg):
    print("check_gltf: " + msg, file=sys.stderr)
    print(__doc__.split("Options:")[0], file=sys.stderr)
    sys.exit(2)


def mismatch(msg):
    """A matching error (the file is not what the check expects): exit 2."""
    print("check_gltf: " + msg)
    sys.exit(2)


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    opts = {"frame_time": None, "rest": None, "height": None,
            "tolerance": 1e-4, "bone_ends": False, "skin": False}
    pos = []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("--frame-time", "--rest", "--height", "--tolerance"):
            if i + 1 >= len(argv):
                usage(a + " needs a value")
            v = argv[i + 1]
            key = a[2:].replace("-", "_")
            opts[key] = v if key == "rest" else float(v)
            i += 2
        elif a in ("--bone-ends", "--skin"):
            opts[a[2:].replace("-", "_")] = True
            i += 1
        elif a.startswith("--"):
            usage("unknown option " + a)
        else:
            pos.append(a)
            i += 1
    if len(pos) < 3:
        usage("need FILE.glb POSITIONS.csv FRAME [FRAME ...]")
    opts["glb"], opts["csv"] = pos[0], pos[1]
    opts["frames"] = [int(f) for f in pos[2:]]
    return opts


# ------------------------------------------------------- reading the .glb

def read_glb(path):
    """Return (json dict, binary chunk bytes) of a .glb file."""
    data = open(path, "rb").read()
    magic, version, length = struct.unpack_from("<III", data, 0)
    if magic != 0x46546C67 or version != 2:
        raise ValueError("%s: not a glTF 2.0 binary" % path)
    off, js, binary = 12, None, b""
    while off < length:
        clen, ctype = struct.unpack_from("<II", data, off)
        chunk = data[off + 8: off + 8 + clen]
        if ctype == 0x4E4F534A:      # 'JSON'
            js = json.loads(chunk.decode("utf-8"))
        elif ctype == 0x004E4942:    # 'BIN\0'
            binary = chunk
        off += 8 + clen
    return js, binary


COMPONENTS = {5121: ("B", 1), 5123: ("H", 2), 5125: ("I", 4), 5126: ("f", 4)}
WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}


def read_accessor(gltf, binary, index):
    """Read an accessor as a list of tuples (raw values: no normalisation,
    no sparse support, no matrix column padding, which MAT4 never needs)."""
    acc = gltf["accessors"][index]
    if acc.get("componentType") not in COMPONENTS or "sparse" in acc:
        raise ValueError("accessor %d: component type %s or sparse not handled"
                         % (index, acc.get("componentType")))
    code, size = COMPONENTS[acc["componentType"]]
    n = WIDTH[acc["type"]]
    view = gltf["bufferViews"][acc["bufferView"]]
    stride = view.get("byteStride", size * n)
    base = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    fmt = "<%d%s" % (n, code)
    return [struct.unpack_from(fmt, binary, base + k * stride)
            for k in range(acc["count"])]


def read_float_accessor(gltf, binary, index):
    if gltf["accessors"][index].get("componentType") != 5126:
        raise ValueError("accessor %d: not a float accessor" % index)
    return read_accessor(gltf, binary, index)


# ------------------------------------------------------------ other input

def read_positions(path):
    """{frame: {joint: (x, y, z)}} from a `bvhview positions` CSV."""
    out = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            out.setdefault(int(row["frame"]), {})[row["joint"]] = (
                float(row["x"]), float(row["y"]), float(row["z"]))
    return out


def y_extent(joints):
    ys = [p[1] for p in joints.values()]
    return max(ys) - min(ys)


def dist(a, b):
    return math.sqrt(sum((p - q) ** 2 for p, q in zip(a, b)))


def to_gltf_axes(v):
    """Blender Z-up (X, Y, Z) -> glTF Y-up (X, Z, -Y)."""
    return (v[0], v[2], -v[1])


# ------------------------------------------------------- glTF node rest pose

def local_matrix(node):
    """A node's rest transform (matrix, or T * R * S) as a float64 4x4."""
    if "matrix" in node:
        return numpy.array(node["matrix"], dtype=float).reshape(4, 4).T
    x, y, z, w = node.get("rotation", (0.0, 0.0, 0.0, 1.0))
    r = numpy.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    m = numpy.identity(4)
    m[:3, :3] = r * numpy.array(node.get("scale", (1.0, 1.0, 1.0)), dtype=float)
    m[:3, 3] = node.get("translation", (0.0, 0.0, 0.0))
    return m


def rest_world_positions(gltf):
    """{node index: rest world position (glTF axes)}."""
    nodes = gltf["nodes"]
    parent_of = {c: i for i, n in enumerate(nodes) for c in n.get("children", [])}
    world = {}

    def get(i):
        if i not in world:
            m = local_matrix(nodes[i])
            if i in parent_of:
                m = get(parent_of[i]) @ m
            world[i] = m
        return world[i]

    return {i: get(i)[:3, 3].copy() for i in range(len(nodes))}


# ------------------------------------------- glTF nodes -> Blender objects

def base_name(name):
    """Strip Blender's ".001" style suffix."""
    if len(name) > 4 and name[-4] == "." and name[-3:].isdigit():
        return name[:-4]
    return name


def match_tree(nodes, roots, candidates, children_of, accept=lambda i: True):
    """Map glTF node indices to the Blender objects (or bones) made for them.

    Matched top-down from `roots`: a node's item is one of its parent's
    item's children (for a root, one of `candidates`) whose name is the
    node's name (truncated to 63 bytes), or that plus Blender's '.NNN'
    duplicate suffix; siblings with the same name are taken in the file's
    order.  Children for which accept(i) is false are not looked for.
    """
    result = {}

    def want(i):
        return nodes[i].get("name", "")[:63]

    def assign(indices, pool):
        pool = sorted(pool, key=lambda o: o.name)  # NAME before NAME.001
        for i in indices:
            if not accept(i):
                continue
            hit = next((o for o in pool if o.name == want(i)), None) or \
                next((o for o in pool if base_name(o.name) == want(i)), None)
            if hit is None:
                raise LookupError("no Blender object or bone for glTF node %d %r"
                                  % (i, nodes[i].get("name")))
            pool.remove(hit)
            result[i] = hit
            assign(nodes[i].get("children", []), children_of(hit))

    assign(roots, candidates)
    return result


# ------------------------------------------------------------- skin plan

SIDES, RINGS = 10, 7
CHECKED_RINGS = (2, 3, 4)


def plan_skin(gltf, binary):
    """The cylinders (j, c) of bvhview's generated skin, rebuilt from the
    node hierarchy, and what the file says about the mesh."""
    nodes = gltf["nodes"]
    skins = gltf.get("skins", [])
    if len(skins) != 1:
        mismatch("--skin: expected one glTF skin, the file has %d "
                 "(was it converted with --skin?)" % len(skins))
    skin = skins[0]
    joints = skin["joints"]
    joint_set = set(joints)
    mesh_nodes = [i for i, n in enumerate(nodes) if "skin" in n and "mesh" in n]
    if len(mesh_nodes) != 1:
        mismatch("--skin: expected one skinned mesh node, found %d" % len(mesh_nodes))
    mesh = gltf["meshes"][nodes[mesh_nodes[0]]["mesh"]]
    if len(mesh["primitives"]) != 1:
        mismatch("--skin: expected one primitive, found %d" % len(mesh["primitives"]))
    attributes = mesh["primitives"][0]["attributes"]
    count = gltf["accessors"][attributes["POSITION"]]["count"]

    rest = rest_world_positions(gltf)
    pts = numpy.array([rest[j] for j in joints])
    size = max(float((pts.max(axis=0) - pts.min(axis=0)).max()), 1e-3)
    cylinders, skipped = [], []
    for j in joints:
        for c in nodes[j].get("children", []):
            if c not in joint_set:
                continue
            length = float(numpy.linalg.norm(rest[c] - rest[j]))
            (skipped if length < size * 1e-4 else cylinders).append((j, c, length))
    expected = SIDES * RINGS * len(cylinders)
    print("skin: %d joints, size %.6g, %d cylinders (%d skipped as shorter than "
          "size * 1e-4), %d x %d = %d vertices expected, the file has %d"
          % (len(joints), size, len(cylinders), len(skipped), len(cylinders),
             SIDES * RINGS, expected, count))
    if cylinders:
        print("skin: shortest cylinder kept %.3g x size; longest skipped %s"
              % (min(c[2] for c in cylinders) / size,
                 "%.3g x size" % (max(c[2] for c in skipped) / size)
                 if skipped else "-"))
    if count != expected:
        mismatch("--skin: the mesh has %d vertices, but the skeleton gives %d "
                 "cylinders x %d = %d: it was not generated as this check "
                 "assumes (src/render/body.rs), or the skeleton differs"
                 % (count, len(cylinders), SIDES * RINGS, expected))
    # Per-vertex influences from the file: {skin joint slot: summed weight}.
    js = read_accessor(gltf, binary, attributes["JOINTS_0"])
    ws = read_accessor(gltf, binary, attributes["WEIGHTS_0"])
    influences = []
    for jj, ww in zip(js, ws):
        d = {}
        for slot, w in zip(jj, ww):
            if w != 0:
                d[slot] = d.get(slot, 0.0) + w
        influences.append(d)
    positions = numpy.array(read_accessor(gltf, binary, attributes["POSITION"]))
    return {"joints": joints, "cylinders": cylinders, "count": count,
            "influences": influences, "positions": positions}


def check_vertex_order(plan, mesh_obj, bone_name_of_slot):
    """Exit 2 unless the imported mesh has the file's vertices in the file's
    order: same count, and each vertex's groups and weights equal to its
    JOINTS_0 / WEIGHTS_0.  Prints how far the rest mesh is from POSITION."""
    me = mesh_obj.data
    if len(me.vertices) != plan["count"]:
        mismatch("--skin: Blender's mesh has %d vertices, the file %d: the "
                 "importer merged or dropped vertices"
                 % (len(me.vertices), plan["count"]))
    groups = mesh_obj.vertex_groups
    for slot, name in enumerate(bone_name_of_slot):
        if slot >= len(groups) or groups[slot].name != name:
            mismatch("--skin: vertex group %d is %r, expected bone %r"
                     % (slot, groups[slot].name if slot < len(groups) else None, name))
    worst_w, bad = 0.0, 0
    for v, want in zip(me.vertices, plan["influences"]):
        got = {g.group: g.weight for g in v.groups if g.weight != 0}
        if set(got) != set(want):
            bad += 1
            continue
        worst_w = max([worst_w] + [abs(got[k] - want[k]) for k in got])
    if bad or worst_w > 1e-6:
        mismatch("--skin: %d vertices have other groups than in the file, worst "
                 "weight difference %.3g: the importer reordered vertices"
                 % (bad, worst_w))
    co = numpy.empty(3 * len(me.vertices))
    me.vertices.foreach_get("co", co)
    m = numpy.array(mesh_obj.matrix_world)
    co = co.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]
    co = numpy.stack([co[:, 0], co[:, 2], -co[:, 1]], axis=1)
    d = float(numpy.linalg.norm(co - plan["positions"], axis=1).max())
    print("skin: %d vertices in file order (groups and weights match "
          "JOINTS_0/WEIGHTS_0, worst weight difference %.1e); imported rest "
          "mesh vs POSITION: worst %.3e units" % (len(me.vertices), worst_w, d))


# -------------------------------------------------------------------- main

def main():
    opts = parse_args()
    gltf, binary = read_glb(opts["glb"])
    nodes = gltf["nodes"]
    index_of = {}
    for i, n in enumerate(nodes):
        index_of.setdefault(n.get("name"), i)
    parent_of = {c: i for i, n in enumerate(nodes) for c in n.get("children", [])}

    # The animation's key times (the exporter writes one shared accessor).
    times = None
    translated = set()   # nodes with a translation track
    anims = gltf.get("animations", [])
    if anims:
        inputs = {s["input"] for s in anims[0]["samplers"]}
        print("time accessors: %d" % len(inputs))
        times = [t[0] for t in read_float_accessor(gltf, binary, min(inputs))]
        # Sanity: rotation outputs should be unit quaternions.
        worst_norm = 0.0
        for ch in anims[0]["channels"]:
            if ch["target"]["path"] == "translation":
                translated.add(ch["target"]["node"])
            if ch["target"]["path"] == "rotation":
                s = anims[0]["samplers"][ch["sampler"]]
                for q in read_float_accessor(gltf, binary, s["output"]):
                    worst_norm = max(worst_norm,
                                     abs(math.sqrt(sum(c * c for c in q)) - 1))
        print("worst | |q| - 1 | over rotation keys: %.2e" % worst_norm)
        if opts["frame_time"] is not None:
            dt = max(abs(t - k * opts["frame_time"]) for k, t in enumerate(times))
            print("worst |time[i] - i * %g| = %.3e s" % (opts["frame_time"], dt))

    positions = read_positions(opts["csv"])
    missing = [f for f in opts["frames"] if f not in positions]
    if missing:
        usage("frames %s not in %s" % (missing, opts["csv"]))

    # Height for the tolerance.
    if opts["height"] is not None:
        height, source = opts["height"], "--height"
    elif opts["rest"] is not None:
        rest = read_positions(opts["rest"])
        height, source = y_extent(rest[min(rest)]), opts["rest"]
    else:
        first = min(positions)
        height, source = y_extent(positions[first]), "frame %d" % first
    limit = opts["tolerance"] * height
    print("height %.6g (from %s), tolerance %.3g = %.6g units"
          % (height, source, opts["tolerance"], limit))

    # Which glTF node each CSV joint name is compared with.
    def node_for(name):
        if name not in index_of:
            return None
        i = index_of[name]
        if not opts["bone_ends"]:
            return i
        is_root = i not in parent_of
        kids = nodes[i].get("children", [])
        return i if is_root else (kids[0] if kids else None)

    plan = plan_skin(gltf, binary) if opts["skin"] else None
    if plan:
        # The CSV row giving each cylinder end's position.
        row_of = {}
        for name in positions[opts["frames"][0]]:
            i = node_for(name)
            if i is not None:
                row_of.setdefault(i, name)

        def same_place(i):
            """A row for node i, or for a node that is always where i is."""
            if i in row_of:
                return row_of[i]
            if i in translated or i not in parent_of:
                return None
            t = nodes[i].get("translation", [0.0, 0.0, 0.0])
            if "matrix" in nodes[i]:
                return None
            p = parent_of[i]
            if all(x == 0 for x in t):
                return same_place(p)
            for s in nodes[p].get("children", []):
                if s != i and s in row_of and s not in translated and \
                        "matrix" not in nodes[s] and \
                        nodes[s].get("translation", [0.0, 0.0, 0.0]) == t:
                    return row_of[s]
            return None

        ends, derived, skipped = [], 0, 0
        for k, (j, c, _) in enumerate(plan["cylinders"]):
            if c in translated:
                skipped += 1
                continue
            a, b = same_place(j), same_place(c)
            if a is None or b is None:
                mismatch("--skin: no CSV row for node %r (cylinder %d, %r -> %r)"
                         % (nodes[j if a is None else c].get("name"), k,
                            nodes[j].get("name"), nodes[c].get("name")))
            derived += (j not in row_of) + (c not in row_of)
            ends.append((k, j, c, a, b))
        print("skin: %d cylinders x rings %s compared; %d ends taken from a "
              "coinciding node's row%s"
              % (len(ends), "/".join(map(str, CHECKED_RINGS)), derived,
                 "; %d skipped (child has a translation track)" % skipped
                 if skipped else ""))

    # Import into an empty scene.
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o, do_unlink=True)
    scene = bpy.context.scene
    fps = scene.render.fps   # the importer multiplies glTF seconds by this
    print("scene fps %d, fps_base %g (importer: frame = t * %d)"
          % (fps, scene.render.fps_base, fps))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if not hasattr(numpy, "bool"):   # removed in numpy 1.24; see above
            numpy.bool = numpy.bool_
            print("note: numpy %s has no numpy.bool, which the importer uses "
                  "for meshes; set to numpy.bool_" % numpy.__version__)
    bpy.ops.import_scene.gltf(filepath=opts["glb"], merge_vertices=False)
    if scene.render.fps != fps:
        print("note: importer changed scene fps to %d" % scene.render.fps)

    # Joints of a skin are bones of an armature; other nodes are objects.
    joint_set = {j for s in gltf.get("skins", []) for j in s["joints"]}
    skinned_mesh_nodes = {i for i, n in enumerate(nodes) if "skin" in n and "mesh" in n}
    armatures = [o for o in bpy.data.objects if o.type == "ARMATURE"]
    arm = None
    bones = {}
    if joint_set:
        if len(armatures) != 1:
            mismatch("expected one armature for the skin, got %d" % len(armatures))
        arm = armatures[0]
        joint_roots = [j for j in sorted(joint_set) if parent_of.get(j) not in joint_set]
        bones = match_tree(nodes, joint_roots,
                           [b for b in arm.data.bones if b.parent is None],
                           lambda b: list(b.children), lambda i: i in joint_set)
    other_roots = [i for i in range(len(nodes)) if i not in parent_of
                   and i not in joint_set and i not in skinned_mesh_nodes]
    objs = match_tree(nodes, other_roots,
                      [o for o in bpy.data.objects if o.parent is None and o is not arm],
                      lambda o: list(o.children),
                      lambda i: i not in joint_set and i not in skinned_mesh_nodes)
    kinds = sorted({o.type for o in objs.values()})
    print("imported %d nodes: %d as bones of armature %s, %d as %sobjects"
          % (len(bones) + len(objs), len(bones), arm.name if arm else "-",
             len(objs), "/".join(kinds) + " " if kinds else ""))
    if kinds not in ([], ["EMPTY"]):
        mismatch("expected only EMPTY objects for nodes, got %s" % kinds)

    mesh_obj = None
    if plan:
        meshes = [o for o in bpy.data.objects if o.type == "MESH" and any(
            m.type == "ARMATURE" and m.object == arm for m in o.modifiers)]
        if len(meshes) != 1:
            mismatch("--skin: expected one mesh deformed by the armature, got %d"
                     % len(meshes))
        mesh_obj = meshes[0]
        print("skin: mesh object %r, parent %r, Armature modifier"
              % (mesh_obj.name, mesh_obj.parent.name if mesh_obj.parent else None))
        check_vertex_order(plan, mesh_obj, [bones[j].name for j in plan["joints"]])

    def node_position(i, depsgraph):
        if i in bones:
            a = arm.evaluated_get(depsgraph)
            return to_gltf_axes(a.matrix_world @ a.pose.bones[bones[i].name].head)
        return to_gltf_axes(objs[i].matrix_world.translation)

    failed = False
    overall, overall_skin = 0.0, 0.0
    frac = (lambda d: d / height) if height else (lambda d: float("inf"))
    for frame in opts["frames"]:
        if opts["frame_time"] is not None:
            t = frame * opts["frame_time"]
        elif times is not None:
            t = times[frame]
        else:
            t = 0.0
        f = t * fps
        whole = math.floor(f)
        scene.frame_set(int(whole), subframe=f - whole)
        bpy.context.view_layer.update()
        depsgraph = bpy.context.evaluated_depsgraph_get()

        worst, worst_name, unmatched = 0.0, "-", []
        for name, expected in positions[frame].items():
            i = node_for(name)
            if i is None or (i not in bones and i not in objs):
                unmatched.append(name)
                continue
            d = dist(node_position(i, depsgraph), expected)
            if d > worst:
                worst, worst_name = d, name
        if unmatched:
            print("frame %d: %d CSV joints with no node: %s"
                  % (frame, len(unmatched), ", ".join(unmatched[:10])))
            failed = True
        ok = worst <= limit
        failed |= not ok
        overall = max(overall, worst)
        print("frame %d (t=%.6f s, blender frame %.5f): worst %.3e units "
              "= %.3e of height at %s over %d joints: %s"
              % (frame, t, f, worst, frac(worst), worst_name,
                 len(positions[frame]), "ok" if ok else "OVER"))

        if plan:
            ev = mesh_obj.evaluated_get(depsgraph)
            me = ev.to_mesh()
            co = numpy.empty(3 * len(me.vertices))
            me.vertices.foreach_get("co", co)
            ev.to_mesh_clear()
            if len(co) != 3 * plan["count"]:
                mismatch("--skin: the deformed mesh has %d vertices, not %d"
                         % (len(co) // 3, plan["count"]))
            m = numpy.array(ev.matrix_world)
            co = co.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]
            co = numpy.stack([co[:, 0], co[:, 2], -co[:, 1]], axis=1)
            means = co.reshape(-1, RINGS, SIDES, 3).mean(axis=2)
            row = positions[frame]
            sworst, where = 0.0, "-"
            for k, j, c, a, b in ends:
                pa, pb = numpy.array(row[a]), numpy.array(row[b])
                for r in CHECKED_RINGS:
                    want = pa + (pb - pa) * (r / (RINGS - 1))
                    d = float(numpy.linalg.norm(means[k, r] - want))
                    if d > sworst:
                        sworst, where = d, "%s->%s ring %d" % (
                            nodes[j].get("name"), nodes[c].get("name"), r)
            ok = sworst <= limit
            failed |= not ok
            overall_skin = max(overall_skin, sworst)
            print("skin frame %d: worst %.3e units = %.3e of height at %s over "
                  "%d rings: %s" % (frame, sworst, frac(sworst), where,
                                    len(ends) * len(CHECKED_RINGS),
                                    "ok" if ok else "OVER"))

    if plan:
        print("worst nodes %.3e units = %.3e of height; worst skin %.3e units "
              "= %.3e of height" % (overall, frac(overall), overall_skin,
                                    frac(overall_skin)))
    both = max(overall, overall_skin)
    print("%s: worst %.3e units = %.3e of height (tolerance %.1e)"
          % ("FAIL" if failed else "PASS", both, frac(both), opts["tolerance"]))
    sys.exit(1 if failed else 0)


try:
    main()
except SystemExit:
    raise
except Exception as e:   # make Blender exit non-zero on any error
    import traceback
    traceback.print_exc()
    sys.exit(2)
