#!/usr/bin/env python3
"""Writes synthetic AMASS-layout files under tests/data/smpl/ (AMASS's own motion is licensed
and never committed): the keys, shapes and dtypes AMASS's SMPL+H, SMPL-X and a SMPL file hold,
with a made-up walk in place (hips swinging, knees bending, arms swaying, the body turning
slowly and moving forward) so that a picture of them shows a person. Run from the repository's
root with numpy; the files are committed.
"""

import numpy as np

FRAMES = 60


def walk(joints, fps):
    t = np.arange(FRAMES) / fps
    poses = np.zeros((FRAMES, joints, 3))
    # Standing in AMASS's Z up: the model's Y-up template turned +90° about X, then a slow turn
    # about the world's up.
    yaw = 0.3 * np.sin(2 * np.pi * t / 2.0)
    for f in range(FRAMES):
        c, s = np.cos(yaw[f]), np.sin(yaw[f])
        turn = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
        stand = np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]])
        poses[f, 0] = rotvec(turn @ stand)
    phase = 2 * np.pi * t / 1.0
    poses[:, 1, 0] = 0.5 * np.sin(phase)  # left hip
    poses[:, 2, 0] = -0.5 * np.sin(phase)  # right hip
    poses[:, 4, 0] = 0.6 * (1 + np.sin(phase + 1.2)) / 2  # left knee
    poses[:, 5, 0] = 0.6 * (1 - np.sin(phase + 1.2)) / 2  # right knee
    poses[:, 16, 2] = -1.2 + 0.2 * np.sin(phase)  # left shoulder, arm down
    poses[:, 17, 2] = 1.2 + 0.2 * np.sin(phase)  # right shoulder
    poses[:, 18, 1] = -0.3  # elbows
    poses[:, 19, 1] = 0.3
    trans = np.zeros((FRAMES, 3))
    trans[:, 1] = 1.2 * t  # forward along AMASS's y
    trans[:, 2] = 0.9 + 0.02 * np.sin(2 * phase)
    return poses, trans


def rotvec(m):
    angle = np.arccos(np.clip((np.trace(m) - 1) / 2, -1, 1))
    if angle < 1e-12:
        return np.zeros(3)
    axis = np.array([m[2, 1] - m[1, 2], m[0, 2] - m[2, 0], m[1, 0] - m[0, 1]])
    return axis / (2 * np.sin(angle)) * angle


def main():
    fps = 120.0
    poses, trans = walk(52, fps)
    np.savez(
        "tests/data/smpl/amass_smplh_walk.npz",
        poses=poses.reshape(FRAMES, -1),
        trans=trans,
        betas=np.linspace(-0.5, 0.5, 16),
        gender=np.array("male"),
        mocap_framerate=np.array(fps),
        dmpls=np.zeros((FRAMES, 8)),
    )
    poses, trans = walk(55, 30.0)
    flat = poses.reshape(FRAMES, -1)
    np.savez(
        "tests/data/smpl/amass_smplx_walk.npz",
        gender=np.array("female"),
        surface_model_type=np.array("smplx"),
        mocap_frame_rate=np.array(30.0),
        mocap_time_length=np.array(FRAMES / 30.0),
        betas=np.zeros(16),
        trans=trans,
        poses=flat,
        root_orient=flat[:, 0:3],
        pose_body=flat[:, 3:66],
        pose_jaw=flat[:, 66:69],
        pose_eye=flat[:, 69:75],
        pose_hand=flat[:, 75:165],
    )
    poses, trans = walk(24, 60.0)
    np.savez_compressed(
        "tests/data/smpl/smpl_walk_compressed.npz",
        poses=poses.reshape(FRAMES, -1).astype(np.float32),
        trans=trans.astype(np.float32),
        mocap_framerate=np.array(60.0),
    )


if __name__ == "__main__":
    main()
