#!/usr/bin/env python3
"""Writes the built-in skeletons of the SMPL family as BVH: assets/smpl24.bvh, smplh52.bvh and
smplx55.bvh.

Each is the published kinematic tree and joint names of its model type (SMPL's 24 joints,
SMPL-H's 52 with fifteen finger joints a hand, SMPL-X's 55 with a jaw and two eyes), in the
order of the model's joints, with lengths of bvhview's own adult figure in centimetres: the
body's are assets/smpl22.bvh's, the hands', jaw's and eyes' are measured on no model (no SMPL
file is read or shipped). A T-pose facing +z, Y up, the model's left side at +x, as the models
stand. Run from the repository's root; the files are committed.
"""

import os

BODY = [
    # name, parent, offset (cm) — smpl22's
    ("pelvis", None, (0, 0, 0)),
    ("left_hip", "pelvis", (6.5, -8.5, -1.5)),
    ("right_hip", "pelvis", (-6.5, -8.5, -1.5)),
    ("spine1", "pelvis", (0, 11, -2)),
    ("left_knee", "left_hip", (3, -38.5, 0.5)),
    ("right_knee", "right_hip", (-3, -38.5, 0.5)),
    ("spine2", "spine1", (0, 13.5, 1.5)),
    ("left_ankle", "left_knee", (-1.5, -42, -3.5)),
    ("right_ankle", "right_knee", (1.5, -42, -3.5)),
    ("spine3", "spine2", (0, 5.5, 0.5)),
    ("left_foot", "left_ankle", (3, -6, 12.5)),
    ("right_foot", "right_ankle", (-3, -6, 12.5)),
    ("neck", "spine3", (0, 21.5, -3)),
    ("left_collar", "spine3", (7.5, 11.5, -1.5)),
    ("right_collar", "spine3", (-7.5, 11.5, -1.5)),
    ("head", "neck", (0, 9, 4.5)),
    ("left_shoulder", "left_collar", (12, 4.5, -1.5)),
    ("right_shoulder", "right_collar", (-12, 4.5, -1.5)),
    ("left_elbow", "left_shoulder", (26, 0, -1.5)),
    ("right_elbow", "right_shoulder", (-26, 0, -1.5)),
    ("left_wrist", "left_elbow", (26, 0, 0)),
    ("right_wrist", "right_elbow", (-26, 0, 0)),
]

# A left hand's fingers in SMPL-H's order, each three joints: (first joint from the wrist, the
# next two along the finger), then the fingertip's End Site.
FINGERS = [
    ("index", (9.5, -0.5, 2.5), [(3.5, 0, 0), (2.2, 0, 0)], (2.0, 0, 0)),
    ("middle", (9.8, -0.5, 0.5), [(3.8, 0, 0), (2.5, 0, 0)], (2.2, 0, 0)),
    ("pinky", (8.5, -0.8, -3.0), [(2.6, 0, 0), (1.8, 0, 0)], (1.6, 0, 0)),
    ("ring", (9.2, -0.6, -1.3), [(3.4, 0, 0), (2.3, 0, 0)], (2.0, 0, 0)),
    ("thumb", (2.5, -1.5, 3.0), [(2.8, -0.5, 2.0), (2.5, -0.3, 1.2)], (2.0, -0.2, 1.0)),
]

END_SITES = {
    "left_foot": (0, 0, 5),
    "right_foot": (0, 0, 5),
    "head": (0, 18, 0),
    "left_hand": (8, 0, 0),
    "right_hand": (-8, 0, 0),
    "jaw": (0, -4, 7),
    "left_eye_smplhf": (0, 0, 1.5),
    "right_eye_smplhf": (0, 0, 1.5),
}


def mirrored(offset):
    x, y, z = offset
    return (-x, y, z)


def hand(side):
    joints = []
    wrist = f"{side}_wrist"
    for finger, first, rest, tip in FINGERS:
        parent = wrist
        for k, offset in enumerate([first] + rest, start=1):
            name = f"{side}_{finger}{k}"
            joints.append((name, parent, offset if side == "left" else mirrored(offset)))
            parent = name
        END_SITES[parent] = tip if side == "left" else mirrored(tip)
    return joints


def model(kind):
    joints = list(BODY)
    if kind == "smpl24":
        joints += [
            ("left_hand", "left_wrist", (9, 0, 0)),
            ("right_hand", "right_wrist", (-9, 0, 0)),
        ]
    if kind == "smplx55":
        joints += [
            ("jaw", "head", (0, -1.5, 2.0)),
            ("left_eye_smplhf", "head", (3.2, 7.0, 8.0)),
            ("right_eye_smplhf", "head", (-3.2, 7.0, 8.0)),
        ]
    if kind in ("smplh52", "smplx55"):
        joints += hand("left") + hand("right")
    return joints


def number(v):
    return f"{v:g}"


def bvh(joints):
    children = {}
    for name, parent, _ in joints:
        children.setdefault(parent, []).append(name)
    offsets = {name: offset for name, _, offset in joints}
    lines = ["HIERARCHY"]
    order = []

    def write(name, depth):
        pad = "  " * depth
        kind = "ROOT" if depth == 0 else "JOINT"
        lines.append(f"{pad}{kind} {name}")
        lines.append(f"{pad}{{")
        lines.append(f"{pad}  OFFSET {' '.join(number(v) for v in offsets[name])}")
        channels = "Zrotation Yrotation Xrotation"
        if depth == 0:
            lines.append(f"{pad}  CHANNELS 6 Xposition Yposition Zposition {channels}")
        else:
            lines.append(f"{pad}  CHANNELS 3 {channels}")
        order.append(name)
        for child in children.get(name, []):
            write(child, depth + 1)
        if name not in children:
            tip = END_SITES[name]
            lines.append(f"{pad}  End Site")
            lines.append(f"{pad}  {{")
            lines.append(f"{pad}    OFFSET {' '.join(number(v) for v in tip)}")
            lines.append(f"{pad}  }}")
        lines.append(f"{pad}}}")

    write("pelvis", 0)
    values = ["0", "97", "0"] + ["0"] * (3 * len(order) - 0)
    lines += ["MOTION", "Frames: 1", "Frame Time: 0.05", " ".join(values)]
    return "\n".join(lines) + "\n"


def main():
    for kind in ("smpl24", "smplh52", "smplx55"):
        with open(os.path.join("assets", f"{kind}.bvh"), "w", encoding="ascii") as out:
            out.write(bvh(model(kind)))


if __name__ == "__main__":
    main()
