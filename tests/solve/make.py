"""Writes walk_smpl22.npy, the example GUIDE's `solve` section reads: the first 120 frames of
tests/data/bvh/bvhparser_walk_01.bvh (CMU's walk as cgspeed converted it) retargeted onto the
built-in smpl22 by bvhview, its 22 joints in SMPL's order, in metres, float32: the layout of
HumanML3D's new_joints/*.npy. Run from the repository's root with the bvhview package
installed: python3 tests/solve/make.py"""

import numpy as np

import bvhview

SMPL22_ORDER = ["pelvis", "left_hip", "right_hip", "spine1", "left_knee", "right_knee", "spine2",
                "left_ankle", "right_ankle", "spine3", "left_foot", "right_foot", "neck",
                "left_collar", "right_collar", "head", "left_shoulder", "right_shoulder",
                "left_elbow", "right_elbow", "left_wrist", "right_wrist"]

walk = bvhview.load("tests/data/bvh/bvhparser_walk_01.bvh").trim(0, 120)
smpl = walk.retarget("smpl22")
order = [smpl.index(name) for name in SMPL22_ORDER]
np.save("tests/solve/walk_smpl22.npy", (smpl.positions()[:, order] / 100.0).astype("<f4"))
