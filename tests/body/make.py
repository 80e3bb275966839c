#!/usr/bin/env python3
"""Writes three of the sample skeletons of tests/body/ (the others are written by hand): cgspeed's
lowercase conversion of CMU, a person and an elephant rigged with 3ds Max Biped's names. Names as
each tool writes them, a human's proportions in centimetres, Y up, facing +Z, left at +X, one
frame of zeros. `tests/motion/body_reading.rs` asserts bvhview's whole reading of each. Run from
tests/body/."""

# Where each part sits in the rest pose (left side; the right mirrors x).
AT = {
    "root": (0, 0, 0), "hips": (0, 95, 0), "spine0": (0, 105, 0), "spine1": (0, 115, 0),
    "spine2": (0, 125, 0), "spine3": (0, 135, 0), "neck": (0, 150, 0), "neck1": (0, 155, 0),
    "head": (0, 160, 0), "headtop": (0, 178, 0), "eye": (3, 165, 8),
    "hiphelper": (5, 93, 0), "thigh": (10, 92, 0), "shin": (10, 50, 0), "ankle": (10, 8, 0),
    "toe": (10, 0, 12), "toetip": (10, 0, 18),
    "clavicle": (3, 145, 0), "upperarm": (18, 145, 0), "forearm": (45, 145, 0),
    "hand": (70, 145, 0), "finger": (80, 145, 0), "fingertip": (88, 145, 0),
    "thumb": (74, 145, 4), "thumbtip": (80, 145, 6),
    # A quadruped's front legs: under the chest, reaching the floor.
    "q_shoulder": (15, 130, 60), "q_upper": (15, 100, 60), "q_fore": (15, 50, 60),
    "q_hand": (15, 8, 60), "q_finger": (15, 0, 70),
    "q_hips": (0, 130, -60), "q_spine": (0, 132, 0), "q_chest": (0, 134, 50),
    "q_neck": (0, 150, 80), "q_head": (0, 160, 110), "q_headtop": (0, 165, 140),
    "q_thigh": (15, 125, -60), "q_shin": (15, 60, -60), "q_ankle": (15, 8, -60),
    "q_toe": (15, 0, -50),
}


def place(slot, side):
    x, y, z = AT[slot]
    return (-x if side == "R" else x, y, z)


def write(path, joints):
    """joints: (name, parent name or None, slot, side 'L'/'R'/None, end: bool)."""
    by_name = {}
    children = {}
    for j in joints:
        by_name[j[0]] = j
        children.setdefault(j[1], []).append(j[0])
    lines, channels = ["HIERARCHY"], 0

    def emit(name, depth):
        nonlocal channels
        _, parent, slot, side, end = by_name[name]
        pad = "  " * depth
        here = place(slot, side)
        there = place(by_name[parent][2], by_name[parent][3]) if parent else (0, 0, 0)
        offset = " ".join(f"{a - b:g}" for a, b in zip(here, there))
        if end:
            lines.extend([f"{pad}End Site", f"{pad}{{", f"{pad}  OFFSET {offset}", f"{pad}}}"])
            return
        lines.append(f"{pad}{'ROOT' if parent is None else 'JOINT'} {name}")
        lines.append(f"{pad}{{")
        lines.append(f"{pad}  OFFSET {offset}")
        if parent is None:
            lines.append(f"{pad}  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation")
            channels += 6
        else:
            lines.append(f"{pad}  CHANNELS 3 Zrotation Xrotation Yrotation")
            channels += 3
        for child in children.get(name, []):
            emit(child, depth + 1)
        lines.append(f"{pad}}}")

    roots = children[None]
    assert len(roots) == 1, path
    emit(roots[0], 0)
    lines += ["MOTION", "Frames: 1", "Frame Time: 0.0333333"]
    first = place(by_name[roots[0]][2], by_name[roots[0]][3])
    lines.append(" ".join([f"{v:g}" for v in first] + ["0"] * (channels - 3)))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def human(names, extra=()):
    """A human from `names`: slot -> name (left side with {s}/{S}/{side} filled per side),
    None to leave a part out. Central slots are plain names."""
    out = []

    def add(slot, parent_slot, side=None, end=False):
        name = names.get(slot)
        if name is None:
            return None
        if side is not None:
            name = name.format(s=side.lower(), S=side, side={"L": "Left", "R": "Right"}[side],
                               lside={"L": "left", "R": "right"}[side])
        out.append((name, parent_slot, slot, side, end))
        return name

    # Central chain.
    chain = ["root", "hips", "spine0", "spine1", "spine2", "spine3", "neck", "neck1", "head"]
    parent = None
    named = {}
    for slot in chain:
        name = add(slot, parent)
        if name:
            named[slot] = name
            parent = name
    top = parent
    out.append((top + "_tip", top, "headtop", None, True))
    chest = named.get(names.get("chest_slot", "spine3")) or named.get("spine2") or named.get("spine1")
    for side in "LR":
        p = chest
        for slot in ["clavicle", "upperarm", "forearm", "hand"]:
            n = add(slot, p, side)
            if n:
                p = n
        hand = p
        for slot, tip in [("finger", "fingertip"), ("thumb", "thumbtip")]:
            n = add(slot, hand, side)
            if n:
                out.append((n + "_tip", n, tip, side, True))
        p = named[names.get("legs_from", "hips")]
        for slot in ["hiphelper", "thigh", "shin", "ankle", "toe"]:
            n = add(slot, p, side)
            if n:
                p = n
        out.append((p + "_tip", p, "toetip" if names.get("toe") else "toe", side, True))
    return out + list(extra)


FAMILIES = {
    "cgspeed_lowercase": dict(hips="hip", spine0="lowerback", spine1="upperback", spine2="thorax",
                              neck="lowerneck", neck1="upperneck", head="head", chest_slot="spine2",
                              clavicle="{s}clavicle", upperarm="{s}shoulder", forearm="{s}elbow",
                              hand="{s}wrist", hiphelper="{s}hipjoint", thigh="{s}buttock",
                              shin="{s}knee", ankle="{s}ankle", toe="{s}toe"),
    "biped_human": dict(root="Bip01", hips="Bip01 Pelvis", spine0="Bip01 Spine", spine1="Bip01 Spine1",
                        spine2="Bip01 Spine2", neck="Bip01 Neck", head="Bip01 Head", chest_slot="spine2",
                        clavicle="Bip01 {S} Clavicle", upperarm="Bip01 {S} UpperArm",
                        forearm="Bip01 {S} Forearm", hand="Bip01 {S} Hand", finger="Bip01 {S} Finger0",
                        thigh="Bip01 {S} Thigh", shin="Bip01 {S} Calf", ankle="Bip01 {S} Foot",
                        toe="Bip01 {S} Toe0"),
}


def quadruped():
    """An elephant rigged with 3ds Max Biped: human names on four legs."""
    j = [("Bip01", None, "root", None, False), ("Bip01 Pelvis", "Bip01", "q_hips", None, False),
         ("Bip01 Spine", "Bip01 Pelvis", "q_spine", None, False),
         ("Bip01 Spine1", "Bip01 Spine", "q_chest", None, False),
         ("Bip01 Neck", "Bip01 Spine1", "q_neck", None, False),
         ("Bip01 Head", "Bip01 Neck", "q_head", None, False),
         ("Bip01 HeadNub", "Bip01 Head", "q_headtop", None, True)]
    for s in "LR":
        j += [(f"Bip01 {s} Clavicle", "Bip01 Spine1", "q_shoulder", s, False),
              (f"Bip01 {s} UpperArm", f"Bip01 {s} Clavicle", "q_upper", s, False),
              (f"Bip01 {s} Forearm", f"Bip01 {s} UpperArm", "q_fore", s, False),
              (f"Bip01 {s} Hand", f"Bip01 {s} Forearm", "q_hand", s, False),
              (f"Bip01 {s} Finger0", f"Bip01 {s} Hand", "q_finger", s, True),
              (f"Bip01 {s} Thigh", "Bip01 Pelvis", "q_thigh", s, False),
              (f"Bip01 {s} Calf", f"Bip01 {s} Thigh", "q_shin", s, False),
              (f"Bip01 {s} Foot", f"Bip01 {s} Calf", "q_ankle", s, False),
              (f"Bip01 {s} Toe0", f"Bip01 {s} Foot", "q_toe", s, True)]
    return j


if __name__ == "__main__":
    for family, names in FAMILIES.items():
        write(f"{family}.bvh", human(names))
    write("biped_elephant.bvh", quadruped())
