#!/usr/bin/env python3
"""Writes the sample skeletons of tests/body/ that pin one class of reading each (issue 59):
where names mislead (MakeHuman's `shoulder01` above `upperarm01`, palms and carpals before the
fingers, `LeftForeFoot`, a `face` under the neck), where names say the wrong side or none, and
bodies that are no person (a hand alone, an eight-legged crab). Each is a made-up skeleton with
plausible places in centimetres, two frames (the second moves the root). `tests/motion/body_reading.rs`
asserts bvhview's reading of each. Run from tests/body/."""


def write(path, joints):
    """joints: (name, parent or None, (x, y, z) place in the rest pose), parents first."""
    at = {name: place for name, _, place in joints}
    children = {}
    for name, parent, _ in joints:
        children.setdefault(parent, []).append(name)
    lines, channels = ["HIERARCHY"], 0

    def fmt(v):
        return " ".join(f"{round(a, 3):g}" for a in v)

    def emit(name, parent, depth):
        nonlocal channels
        pad = "\t" * depth
        here = at[name]
        there = at[parent] if parent else (0, 0, 0)
        lines.append(f"{pad}{'ROOT' if parent is None else 'JOINT'} {name}")
        lines.append(f"{pad}{{")
        lines.append(f"{pad}\tOFFSET {fmt(h - t for h, t in zip(here, there)) if parent else '0 0 0'}")
        if parent is None:
            lines.append(f"{pad}\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation")
            channels += 6
        else:
            lines.append(f"{pad}\tCHANNELS 3 Zrotation Xrotation Yrotation")
            channels += 3
        kids = children.get(name, [])
        if not kids:
            # An end site a third of the bone on, along it.
            bone = [h - t for h, t in zip(here, there)] if parent else [0, 5, 0]
            lines.extend([f"{pad}\tEnd Site", f"{pad}\t{{", f"{pad}\t\tOFFSET {fmt(b / 3 for b in bone)}",
                      f"{pad}\t}}"])
        for kid in kids:
            emit(kid, name, depth + 1)
        lines.append(f"{pad}}}")

    root = children[None][0]
    emit(root, None, 0)
    lines += ["MOTION", "Frames: 2", "Frame Time: 0.0333333"]
    first = list(at[root])
    rest = ["0"] * (channels - 3)
    lines.append(fmt(first) + " " + " ".join(rest))
    moved = [first[0] + 2, first[1], first[2] + 1]
    lines.append(fmt(moved) + " " + " ".join(rest))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def mirror(p):
    return (-p[0], p[1], p[2])


def person(names, left_at=1, facing=1, extra=()):
    """A standing person, Y up: `names` maps a part to its name per side ('{s}' filled with
    the side's mark from `names['sides']`), None leaves it out. `left_at`: +1 puts the left
    side at +x, -1 at -x; `facing`: the toes point to +z (1) or -z (-1)."""
    place = {
        "hips": (0, 95, 0), "spine": (0, 110, 0), "chest": (0, 130, 0), "neck": (0, 148, 0),
        "head": (0, 158, 0),
        "clavicle": (3, 143, 0), "upperarm": (17, 145, 0), "forearm": (44, 145, 0),
        "hand": (69, 145, 0),
        "thigh": (9, 91, 0), "shin": (9, 50, 0), "foot": (9, 8, 0), "toe": (9, 1, 12),
    }
    sides = names.get("sides", ("L", "R"))
    joints = []

    def at(part, side):
        x, y, z = place[part]
        sign = left_at if side == 0 else -left_at
        return (sign * x, y, facing * z)

    def add(name, parent, where):
        if name is not None:
            joints.append((name, parent, where))

    add(names["hips"], None, at("hips", 0))
    add(names["spine"], names["hips"], at("spine", 0))
    add(names["chest"], names["spine"], at("chest", 0))
    add(names["neck"], names["chest"], at("neck", 0))
    add(names["head"], names["neck"], at("head", 0))
    for side, mark in enumerate(sides):
        def n(part):
            name = names.get(part)
            return name.format(s=mark) if name else None
        add(n("clavicle"), names["chest"], at("clavicle", side))
        add(n("upperarm"), n("clavicle"), at("upperarm", side))
        add(n("forearm"), n("upperarm"), at("forearm", side))
        add(n("hand"), n("forearm"), at("hand", side))
        add(n("thigh"), names["hips"], at("thigh", side))
        add(n("shin"), n("thigh"), at("shin", side))
        add(n("foot"), n("shin"), at("foot", side))
        add(n("toe"), n("foot"), at("toe", side))
    for name, parent, where, side in extra:
        joints.append((name, parent, at_point(where, side, left_at, facing)))
    return joints


def at_point(where, side, left_at, facing):
    x, y, z = where
    sign = left_at if side == 0 else -left_at
    return (sign * x, y, facing * z)


LAFAN = {
    "hips": "Hips", "spine": "Spine", "chest": "Spine1", "neck": "Neck", "head": "Head",
    "clavicle": "{s}Shoulder", "upperarm": "{s}Arm", "forearm": "{s}ForeArm", "hand": "{s}Hand",
    "thigh": "{s}UpLeg", "shin": "{s}Leg", "foot": "{s}Foot", "toe": "{s}Toe",
    "sides": ("Left", "Right"),
}

# MakeHuman's default skeleton: a shoulder piece (`shoulder01`) between the clavicle and the
# upper arm, the upper arm and forearm split in two for their twist, pelvis bones at the root.
mh = []
mh.append(("root", None, (0, 97, 0)))
for s, k in (("L", 1), ("R", -1)):
    mh.append((f"pelvis.{s}", "root", (k * 2, 95, 0)))
    mh.append((f"upperleg01.{s}", f"pelvis.{s}", (k * 9, 91, 0)))
    mh.append((f"upperleg02.{s}", f"upperleg01.{s}", (k * 9, 70, 0)))
    mh.append((f"lowerleg01.{s}", f"upperleg02.{s}", (k * 9, 50, 0)))
    mh.append((f"foot.{s}", f"lowerleg01.{s}", (k * 9, 8, 0)))
    mh.append((f"toe1-1.{s}", f"foot.{s}", (k * 9, 1, 12)))
mh.append(("spine03", "root", (0, 110, 0)))
mh.append(("spine01", "spine03", (0, 130, 0)))
mh.append(("neck01", "spine01", (0, 148, 0)))
mh.append(("head", "neck01", (0, 158, 0)))
for s, k in (("L", 1), ("R", -1)):
    mh.append((f"clavicle.{s}", "spine01", (k * 3, 143, 2)))
    mh.append((f"shoulder01.{s}", f"clavicle.{s}", (k * 12, 146, -2)))
    mh.append((f"upperarm01.{s}", f"shoulder01.{s}", (k * 17, 144, 0)))
    mh.append((f"upperarm02.{s}", f"upperarm01.{s}", (k * 30, 144, 0)))
    mh.append((f"lowerarm01.{s}", f"upperarm02.{s}", (k * 44, 144, 0)))
    mh.append((f"lowerarm02.{s}", f"lowerarm01.{s}", (k * 56, 144, 0)))
    mh.append((f"wrist.{s}", f"lowerarm02.{s}", (k * 69, 144, 0)))
write("makehuman_shoulder01.bvh", mh)

# Rigify: palms before the finger roots, the head `spine.006` under `spine.005`, the face under
# the head.
rg = [("DEF-spine", None, (0, 95, 0)), ("DEF-spine.001", "DEF-spine", (0, 105, 0)),
      ("DEF-spine.002", "DEF-spine.001", (0, 117, 0)), ("DEF-spine.003", "DEF-spine.002", (0, 129, 0)),
      ("DEF-spine.004", "DEF-spine.003", (0, 145, 0)), ("DEF-spine.005", "DEF-spine.004", (0, 150, 0)),
      ("DEF-spine.006", "DEF-spine.005", (0, 157, 2)), ("ORG-face", "DEF-spine.006", (0, 160, 8)),
      ("DEF-jaw", "ORG-face", (0, 154, 9))]
for s, k in (("L", 1), ("R", -1)):
    rg += [(f"DEF-shoulder.{s}", "DEF-spine.003", (k * 3, 140, 0)),
           (f"DEF-upper_arm.{s}", f"DEF-shoulder.{s}", (k * 17, 142, 0)),
           (f"DEF-forearm.{s}", f"DEF-upper_arm.{s}", (k * 44, 142, 0)),
           (f"DEF-hand.{s}", f"DEF-forearm.{s}", (k * 69, 142, 0)),
           (f"DEF-thumb.01.{s}", f"DEF-hand.{s}", (k * 71, 141, 3)),
           (f"DEF-thumb.02.{s}", f"DEF-thumb.01.{s}", (k * 74, 141, 5)),
           (f"DEF-thumb.03.{s}", f"DEF-thumb.02.{s}", (k * 77, 141, 6))]
    for f, z in (("index", 2), ("middle", 0), ("ring", -2), ("pinky", -4)):
        palm = {"index": "01", "middle": "02", "ring": "03", "pinky": "04"}[f]
        rg += [(f"DEF-palm.{palm}.{s}", f"DEF-hand.{s}", (k * 70, 142, z * 0.5)),
               (f"DEF-f_{f}.01.{s}", f"DEF-palm.{palm}.{s}", (k * 78, 142, z)),
               (f"DEF-f_{f}.02.{s}", f"DEF-f_{f}.01.{s}", (k * 82, 142, z)),
               (f"DEF-f_{f}.03.{s}", f"DEF-f_{f}.02.{s}", (k * 85, 142, z))]
    rg += [(f"DEF-thigh.{s}", "DEF-spine", (k * 9, 91, 0)), (f"DEF-shin.{s}", f"DEF-thigh.{s}", (k * 9, 50, 0)),
           (f"DEF-foot.{s}", f"DEF-shin.{s}", (k * 9, 8, 0)), (f"DEF-toe.{s}", f"DEF-foot.{s}", (k * 9, 1, 12))]
write("rigify_palms_face.bvh", rg)

# Daz: carpals before the fingers; a pinky whose metacarpal is named for it (`lPinky0`), a
# ring finger counted 1 to 4 with a fingertip marker.
dz = person({"hips": "hip", "spine": "abdomen", "chest": "chest", "neck": "neck", "head": "head",
             "clavicle": "{s}Collar", "upperarm": "{s}Shldr", "forearm": "{s}ForeArm",
             "hand": "{s}Hand", "thigh": "{s}Thigh", "shin": "{s}Shin", "foot": "{s}Foot",
             "toe": "{s}Toe", "sides": ("l", "r")})
for side, s in enumerate(("l", "r")):
    def p(x, y, z, side=side):
        return at_point((x, y, z), side, 1, 1)
    dz += [(f"{s}Thumb1", f"{s}Hand", p(71, 144, 3)), (f"{s}Thumb2", f"{s}Thumb1", p(74, 144, 5)),
           (f"{s}Thumb3", f"{s}Thumb2", p(77, 144, 6)),
           (f"{s}Carpal1", f"{s}Hand", p(70, 145, 1)), (f"{s}Index1", f"{s}Carpal1", p(78, 145, 2)),
           (f"{s}Index2", f"{s}Index1", p(82, 145, 2)), (f"{s}Index3", f"{s}Index2", p(85, 145, 2)),
           (f"{s}Carpal2", f"{s}Hand", p(70, 145, 0)), (f"{s}Mid1", f"{s}Carpal2", p(78, 145, 0)),
           (f"{s}Mid2", f"{s}Mid1", p(83, 145, 0)), (f"{s}Mid3", f"{s}Mid2", p(86, 145, 0)),
           (f"{s}Ring1", f"{s}Hand", p(77, 145, -2)), (f"{s}Ring2", f"{s}Ring1", p(81, 145, -2)),
           (f"{s}Ring3", f"{s}Ring2", p(84, 145, -2)), (f"{s}Ring4", f"{s}Ring3", p(86, 145, -2)),
           (f"{s}Pinky0", f"{s}Hand", p(70, 145, -3)), (f"{s}Pinky1", f"{s}Pinky0", p(76, 145, -4)),
           (f"{s}Pinky2", f"{s}Pinky1", p(79, 145, -4)), (f"{s}Pinky3", f"{s}Pinky2", p(81, 145, -4))]
write("daz_carpal.bvh", dz)

# A ball of the foot named `LeftForeFoot` (no `Toe`).
write("forefoot.bvh", person(dict(LAFAN, toe="{s}ForeFoot")))

# A face hung from the neck: the head is the face.
write("face_under_neck.bvh", person(dict(LAFAN, head="Face")))

# Left and right names on the wrong sides: the toes face +z, the up is +y, so the body's left
# is at +x, where the joints named Right lie.
write("sides_swapped.bvh", person(LAFAN, left_at=-1))

# No side in any name (Blender's `Bone.001`), facing -z: the body's left is at -x.
plain = person({"hips": "Bone", "spine": "Bone.001", "chest": "Bone.002", "neck": "Bone.003",
                "head": "Bone.004", "clavicle": "Bone.{s}0", "upperarm": "Bone.{s}1",
                "forearm": "Bone.{s}2", "hand": "Bone.{s}3", "thigh": "Bone.{s}4",
                "shin": "Bone.{s}5", "foot": "Bone.{s}6", "toe": "Bone.{s}7",
                "sides": ("01", "02")}, facing=-1)
write("no_side_names.bvh", plain)

# A left hand alone, lying flat (fingers along z, palm in the x-z plane).
hand = [("lHand", None, (0, 0, 0))]
for f, x in (("Thumb", 4), ("Index", 2), ("Mid", 0), ("Ring", -2), ("Pinky", -4)):
    start = 2 if f == "Thumb" else 9
    for b in range(1, 4):
        parent = "lHand" if b == 1 else f"l{f}{b - 1}"
        hand.append((f"l{f}{b}", parent, (x + (1.5 * b if f == "Thumb" else 0), 0, start + 3 * b)))
write("hand_alone.bvh", hand)

# A crab: eight legs and two claws round a flat body, wider and deeper than it is tall.
crab = [("Body", None, (0, 12, 0))]
for s, k in (("L", 1), ("R", -1)):
    for i, z in enumerate((9, 3, -3, -9), start=1):
        crab += [(f"leg{i}.{s}", "Body", (k * 8, 12, z)),
                 (f"leg{i}.{s}.001", f"leg{i}.{s}", (k * 18, 16, z * 1.3)),
                 (f"leg{i}.{s}.002", f"leg{i}.{s}.001", (k * 28, 8, z * 1.6)),
                 (f"leg{i}.{s}.003", f"leg{i}.{s}.002", (k * 34, 0, z * 1.8))]
    crab += [(f"claw.{s}", "Body", (k * 6, 12, 12)), (f"claw.{s}.001", f"claw.{s}", (k * 10, 13, 22)),
             (f"claw.{s}.002", f"claw.{s}.001", (k * 8, 13, 32))]
write("crab.bvh", crab)
