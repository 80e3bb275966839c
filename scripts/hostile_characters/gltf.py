# Crafts hostile glTF characters: gltf.py OUT CASE [NUMBERS]; README.md lists them.
import json, struct, sys, os
OUT = sys.argv[1]

BIPED = [("Hips", None, [0, 1, 0]), ("Spine", 0, [0, .1, 0]), ("Chest", 1, [0, .2, 0]),
         ("Neck", 2, [0, .2, 0]), ("Head", 3, [0, .1, 0]),
         ("LeftShoulder", 2, [.05, .15, 0]), ("LeftArm", 5, [.1, 0, 0]), ("LeftForeArm", 6, [.25, 0, 0]), ("LeftHand", 7, [.25, 0, 0]),
         ("RightShoulder", 2, [-.05, .15, 0]), ("RightArm", 9, [-.1, 0, 0]), ("RightForeArm", 10, [-.25, 0, 0]), ("RightHand", 11, [-.25, 0, 0]),
         ("LeftUpLeg", 0, [.1, 0, 0]), ("LeftLeg", 13, [0, -.45, 0]), ("LeftFoot", 14, [0, -.45, 0]), ("LeftToeBase", 15, [0, -.05, .1]),
         ("RightUpLeg", 0, [-.1, 0, 0]), ("RightLeg", 17, [0, -.45, 0]), ("RightFoot", 18, [0, -.45, 0]), ("RightToeBase", 19, [0, -.05, .1])]

class G:
    def __init__(s):
        s.bin = bytearray(); s.views = []; s.acc = []
    def add(s, data, comp, typ, count, stride=None, minmax=None):
        while len(s.bin) % 4: s.bin.append(0)
        off = len(s.bin); s.bin += data
        v = {"buffer": 0, "byteOffset": off, "byteLength": len(data)}
        if stride: v["byteStride"] = stride
        s.views.append(v)
        a = {"bufferView": len(s.views) - 1, "componentType": comp, "count": count, "type": typ}
        if minmax: a["min"], a["max"] = minmax
        s.acc.append(a); return len(s.acc) - 1

def character(path, extra_joints=0, ibm_scale=None, weights_rows=None, joints_rows=None,
              positions=None, indices=None, nsets=1, extra_nodes=0, anim_frames=0, stride=None, glb=True):
    g = G()
    nodes = []
    for name, parent, t in BIPED:
        nodes.append({"name": name, "translation": t, "children": []})
    for i, (name, parent, t) in enumerate(BIPED):
        if parent is not None: nodes[parent]["children"].append(i)
    for k in range(extra_joints):
        nodes.append({"name": "x%d" % k}); nodes[4]["children"].append(len(nodes) - 1)
    njoints = len(nodes)
    mesh_node = len(nodes)
    nodes.append({"name": "body", "mesh": 0, "skin": 0})
    roots = [0, mesh_node]
    for k in range(extra_nodes):
        nodes.append({"name": "n%d" % k}); roots.append(len(nodes) - 1)
    for n in nodes:
        if not n.get("children"): n.pop("children", None)
    positions = positions or [[0, 1, 0], [.1, 1, 0], [0, 1.1, 0]]
    nv = len(positions)
    pos = g.add(b"".join(struct.pack("<3f", *p) for p in positions), 5126, "VEC3", nv,
                stride=stride, minmax=([min(p[i] for p in positions) for i in range(3)], [max(p[i] for p in positions) for i in range(3)]))
    attrs = {"POSITION": pos}
    if weights_rows is None:
        weights_rows = [[[1, 0, 0, 0]] * nv] * nsets
        joints_rows = [[[0, 0, 0, 0]] * nv] * nsets
    for s in range(len(weights_rows)):
        j = g.add(b"".join(struct.pack("<4H", *r) for r in joints_rows[s]), 5123, "VEC4", nv)
        w = g.add(b"".join(struct.pack("<4f", *r) for r in weights_rows[s]), 5126, "VEC4", nv)
        attrs["JOINTS_%d" % s] = j; attrs["WEIGHTS_%d" % s] = w
    indices = indices if indices is not None else list(range(nv - nv % 3))
    ind = g.add(b"".join(struct.pack("<I", i) for i in indices), 5125, "SCALAR", len(indices))
    skin = {"joints": list(range(njoints))}
    if ibm_scale is not None:
        m = b""
        for k in range(njoints):
            s = ibm_scale if k == 0 else 1.0
            m += struct.pack("<16f", s, 0, 0, 0, 0, s, 0, 0, 0, 0, s, 0, 0, 0, 0, 1)
        skin["inverseBindMatrices"] = g.add(m, 5126, "MAT4", njoints)
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": roots}], "nodes": nodes,
           "skins": [skin], "meshes": [{"name": "body", "primitives": [{"attributes": attrs, "indices": ind}]}]}
    if anim_frames:
        times = g.add(b"".join(struct.pack("<f", f / 30) for f in range(anim_frames)), 5126, "SCALAR", anim_frames,
                      minmax=([0], [(anim_frames - 1) / 30]))
        rots = g.add(b"".join(struct.pack("<4f", 0, 0, 0, 1) for f in range(anim_frames)), 5126, "VEC4", anim_frames)
        doc["animations"] = [{"samplers": [{"input": times, "output": rots}], "channels": [{"sampler": 0, "target": {"node": 0, "path": "rotation"}}]}]
    while len(g.bin) % 4: g.bin.append(0)
    doc["buffers"] = [{"byteLength": len(g.bin)}]
    doc["bufferViews"] = g.views; doc["accessors"] = g.acc
    js = json.dumps(doc, separators=(",", ":")).encode()
    while len(js) % 4: js += b" "
    out = struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(js) + 8 + len(g.bin))
    out += struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(g.bin), 0x004E4942) + bytes(g.bin)
    open(path, "wb").write(out)
    print(path, len(out))

def take_bvh(path, frames):
    # Biped BVH with only the root's channels moving, many frames.
    lines = ["HIERARCHY", "ROOT Hips", "{", "OFFSET 0 0 0", "CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation"]
    def joint(name, off, kids, depth):
        out = ["JOINT %s" % name, "{", "OFFSET %g %g %g" % tuple(off), "CHANNELS 3 Zrotation Xrotation Yrotation"]
        for k in kids: out += k
        if not kids: out += ["End Site", "{", "OFFSET 0 1 0", "}"]
        return out + ["}"]
    chain = lambda names, offs: (joint(names[0], offs[0], [chain(names[1:], offs[1:])] if len(names) > 1 else [], 0))
    lines += chain(["Spine", "Chest", "Neck", "Head"], [[0,10,0]]*4)
    lines += chain(["LeftUpLeg", "LeftLeg", "LeftFoot", "LeftToeBase"], [[10,0,0],[0,-45,0],[0,-45,0],[0,-5,10]])
    lines += chain(["RightUpLeg", "RightLeg", "RightFoot", "RightToeBase"], [[-10,0,0],[0,-45,0],[0,-45,0],[0,-5,10]])
    lines += chain(["LeftArm", "LeftForeArm", "LeftHand"], [[10,50,0],[25,0,0],[25,0,0]])
    lines += chain(["RightArm", "RightForeArm", "RightHand"], [[-10,50,0],[-25,0,0],[-25,0,0]])
    lines += ["}", "MOTION", "Frames: %d" % frames, "Frame Time: 0.008333"]
    nch = 6 + 3 * 18
    row = " ".join(["0"] * nch)
    lines += [row] * frames
    open(path, "w").write("\n".join(lines) + "\n")
    print(path, os.path.getsize(path))

if __name__ == "__main__":
    which = sys.argv[2]
    if which == "f1":
        character(OUT + "/f1_17000_joints.glb", extra_joints=17000)
        take_bvh(OUT + "/f1_take.bvh", 8000)
    if which == "f2":
        # One vertex with 100,000 influences: 25,000 sets of 4 (only vertex 0 weighted in later sets).
        nv, ns = 3, 25000
        W = [[[1, 1, 1, 1] if v == 0 else ([1, 0, 0, 0] if s == 0 else [0, 0, 0, 0]) for v in range(nv)] for s in range(ns)]
        J = [[[0, 1, 2, 3]] * nv for s in range(ns)]
        character(OUT + "/f2_many_influences.glb", weights_rows=W, joints_rows=J)
    if which == "f4":
        character(OUT + "/f4_nodes_frames.glb", extra_nodes=int(sys.argv[3]), anim_frames=int(sys.argv[4]))
    if which == "f5":
        W = [[[3e38, 3e38, 0, 0], [1, 0, 0, 0], [1, 0, 0, 0]]]
        J = [[[0, 1, 0, 0]] * 3]
        character(OUT + "/f5_overflow.glb", weights_rows=W, joints_rows=J)
        ns = 50000
        W = [[[1, 1, 1, 1] if v == 0 else ([1, 0, 0, 0] if s == 0 else [0, 0, 0, 0]) for v in range(3)] for s in range(ns)]
        J = [[[s % 20, (s + 1) % 20, (s + 2) % 20, (s + 3) % 20]] * 3 for s in range(ns)]
        character(OUT + "/f5_drift.glb", weights_rows=W, joints_rows=J)
    if which == "f6":
        character(OUT + "/f6_infinite.glb", ibm_scale=3e38)
    if which == "f7":
        character(OUT + "/f7_stride.glb", stride=4)
        character(OUT + "/f7_trailing.glb", positions=[[0,1,0],[.1,1,0],[0,1.1,0],[.1,1.1,0]], indices=[0, 1, 2, 3])
