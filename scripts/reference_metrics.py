#!/usr/bin/env python3
"""What guided-motion-diffusion's own `calculate_skating_ratio` says of a few motions, for
tests/motion/plausibility_metrics.rs.

Runs the function from the user's checkout of https://github.com/korrawe/guided-motion-diffusion
(its `data_loaders/humanml/utils/metrics.py`, read from there, never copied here) on four
motions made from the repository's own positions (SMPL's 22 joints, metres, y up), and writes
what it returns to tests/metrics/gmd_skating.npz:

- `humanml3d`: tests/humanml3d/new_joints_012314.npy as it is (HumanML3D stands on y = 0);
- `walk_grounded`: tests/solve/walk_smpl22.npy moved up so that its lowest point is at 0;
- `walk_sliding`: that walk dragged along x 4 cm a frame (0.8 m/s at GMD's 20 frames a
  second): the feet slide when down;
- `walk_sunk`: that walk 3 cm under the floor (the feet always touch it).

Every motion is float64; GMD's function takes the rate as 20 frames a second.

    work=$(mktemp -d)   # a folder of your own for the venv and the checkout
    python3 -m venv "$work/venv" && "$work/venv/bin/pip" install torch numpy scipy
    git clone https://github.com/korrawe/guided-motion-diffusion "$work/gmd"
    "$work/venv/bin/python" scripts/reference_metrics.py --gmd "$work/gmd"
"""

import argparse
import os
import subprocess

import numpy as np
import torch


def variants(here):
    joints = np.load(os.path.join(here, "tests/humanml3d/new_joints_012314.npy")).astype(np.float64)
    walk = np.load(os.path.join(here, "tests/solve/walk_smpl22.npy")).astype(np.float64)
    grounded = walk.copy()
    grounded[..., 1] = grounded[..., 1] - walk[..., 1].min()
    sliding = grounded.copy()
    sliding[..., 0] = sliding[..., 0] + 0.04 * np.arange(len(walk))[:, None]
    sunk = grounded.copy()
    sunk[..., 1] = sunk[..., 1] - 0.03
    return {"humanml3d": joints, "walk_grounded": grounded, "walk_sliding": sliding,
            "walk_sunk": sunk}


def main():
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--gmd", required=True, help="a checkout of guided-motion-diffusion")
    args = parser.parse_args()
    source = os.path.join(args.gmd, "data_loaders/humanml/utils/metrics.py")
    namespace = {}
    exec(compile(open(source).read(), source, "exec"), namespace)
    skating = namespace["calculate_skating_ratio"]
    commit = subprocess.run(["git", "-C", args.gmd, "rev-parse", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    out = {"gmd_commit": np.array(commit or "unknown")}
    for name, motion in variants(here).items():
        # GMD's layout: [batch, joints, xyz, frames].
        batch = torch.tensor(motion.transpose(1, 2, 0)[None])
        ratio, skate_vel = skating(batch)
        out[name] = np.array(ratio[0])
        out[name + "_skate_vel"] = skate_vel[0]
        print(f"{name}: skating ratio {ratio[0]:.6f}")
    np.savez_compressed(os.path.join(here, "tests/metrics/gmd_skating.npz"), **out)


if __name__ == "__main__":
    main()
