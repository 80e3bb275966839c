#!/usr/bin/env python3
"""Fake SMPL, SMPL-H and SMPL-X model files, and what the `smplx` package computes on them.

Real model files are licensed and never committed. This script makes a model of each type with
the published layout (the keys, the array shapes of each type: 6,890 or 10,475 vertices, the
kinematic tree, 207/459/486 pose blend shape features, SMPL 1.0's 10 shape components,
AMASS's SMPL-H with 16, SMPL-X 2020's 300 + 100 expression) and made-up values: a tube of
vertices along each bone of bvhview's built-in figure of that type, weights shared by a bone's
two joints, joints regressed from four vertices each, and shape and pose blend shapes of noise.

The values come from integers by a splitmix64 hash and the four exactly rounded operations
only, so `tests/common/smpl_models.rs` makes the very same model in Rust without the file. The
script runs `smplx` (64-bit floats, full hand poses, flat hand mean) on 20 random bodies of each
type and writes `tests/smpl/<type>_smplx.npz`: the inputs, every joint, a sample
of the vertices, and the rest joints the model was built on. bvhview's forward pass must agree
with it (tests/formats/smpl_model.rs).

    work=$(mktemp -d)   # a folder of your own for the venv (and the models, if kept)
    python3 -m venv "$work/venv" && "$work/venv/bin/pip" install torch smplx numpy
    cargo build && "$work/venv/bin/python" scripts/make_smpl_models.py [--models "$work/models"]

`--models DIR` keeps the model files there (to try `--body-model`, `--character`).
"""

import argparse
import csv
import io
import os
import subprocess
import sys
import tempfile

import numpy as np

GOLDEN = np.uint64(0x9E3779B97F4A7C15)
MIX1 = np.uint64(0xBF58476D1CE4E5B9)
MIX2 = np.uint64(0x94D049BB133111EB)

# The octagon around a bone: cosines and sines of eighth turns, as decimal literals both
# languages read to the same doubles.
CORNER_C = [1.0, 0.7071067811865476, 0.0, -0.7071067811865476, -1.0, -0.7071067811865476, 0.0,
            0.7071067811865476]
CORNER_S = [0.0, 0.7071067811865476, 1.0, 0.7071067811865476, 0.0, -0.7071067811865476, -1.0,
            -0.7071067811865476]

# Per type: built-in skeleton, vertices, triangles, shape components (SMPL-X: + expression).
TYPES = {
    "smpl": ("smpl24", 6890, 13776, 10),
    "smplh": ("smplh52", 6890, 13776, 16),
    "smplx": ("smplx55", 10475, 20908, 400),
}

POSES = 20


def noise(seed, count, scale):
    """`count` values in [-scale, scale): splitmix64 of (seed << 40) + i, top 53 bits."""
    with np.errstate(over="ignore"):
        z = (np.arange(count, dtype=np.uint64) + np.uint64(seed << 40)) * GOLDEN
        z = (z ^ (z >> np.uint64(30))) * MIX1
        z = (z ^ (z >> np.uint64(27))) * MIX2
        z = z ^ (z >> np.uint64(31))
    unit = (z >> np.uint64(11)).astype(np.float64) * 2.0**-53
    return (unit * 2.0 - 1.0) * scale


def rest_joints(cli, built_in, names):
    """The built-in figure's joints at rest, metres, in the model type's order."""
    out = subprocess.run([cli, "positions", built_in, "-o", "-", "--format", "csv"],
                         check=True, capture_output=True, text=True).stdout
    at = {row["joint"]: [float(row[k]) * 0.01 for k in "xyz"]
          for row in csv.DictReader(io.StringIO(out))}
    return np.array([at[n] for n in names], dtype=np.float64)


def model_arrays(rest, parents, vertices, faces, shapes):
    """The model's arrays, as the Rust twin makes them."""
    joints = len(parents)
    nb = joints - 1
    v = np.arange(vertices)
    bone = 1 + v % nb
    k = v // nb
    m = k % 9
    corner = (k // 9) % 8
    layer = (k // 72) % 4
    t = m / 8.0
    radius = (2.0 + layer) / 100.0
    par = np.array([parents[b] for b in bone])
    d = rest[bone] - rest[par]
    c = np.array(CORNER_C)[corner] * radius
    s = np.array(CORNER_S)[corner] * radius
    horizontal = np.abs(d[:, 0]) > np.abs(d[:, 1])
    off = np.zeros((vertices, 3))
    off[:, 0] = np.where(horizontal, 0.0, c)
    off[:, 1] = np.where(horizontal, c, 0.0)
    off[:, 2] = s
    template = (rest[par] + d * t[:, None]) + off
    weights = np.zeros((vertices, joints))
    weights[v, par] = 1.0 - t / 2.0
    weights[v, bone] = t / 2.0
    regressor = np.zeros((joints, vertices))
    first_child = min(b for b in range(1, joints) if parents[b] == 0)
    for j in range(joints):
        for a in (0, 2, 4, 6):
            if j == 0:
                regressor[0, (first_child - 1) + nb * (9 * a)] = 0.25
            else:
                regressor[j, (j - 1) + nb * (8 + 9 * a)] = 0.25
    features = 9 * nb
    i = np.arange(faces)
    return {
        "v_template": template,
        "weights": weights,
        "J_regressor": regressor,
        "shapedirs": shape_dirs(template, rest, par, bone, shapes),
        "posedirs": noise(2, vertices * 3 * features, 0.001).reshape(vertices, 3, features),
        "f": tube_faces(faces, vertices, nb),
    }


def shape_dirs(template, rest, par, bone, shapes):
    """Noise, and a stretch: component l (of the first ten) moves each vertex of the bones
    numbered l modulo ten away from the bone's parent joint by 5% a unit, so that the betas
    lengthen bones as a real model's do."""
    vertices = len(template)
    dirs = noise(1, vertices * 3 * shapes, 0.002).reshape(vertices, 3, shapes)
    stretch = 0.05 * (template - rest[par])
    for l in range(min(10, shapes)):
        on = bone % 10 == l
        dirs[on, :, l] = dirs[on, :, l] + stretch[on]
    return dirs


def tube_faces(faces, vertices, nb):
    """Two triangles a quad of a bone's tube: from step m to m + 1 along it, corner a to a + 1
    around it, in one layer; a corner past the last vertex folds to the quad's first."""
    out = []
    for i in range(faces):
        v0 = (i // 2) % vertices
        b0, k = v0 % nb, v0 // nb
        m, a, layer = min(k % 9, 7), (k // 9) % 8, k // 72
        # A quad past the last vertex (the last layer is cut short) folds to a point.
        vid = lambda m, a: (lambda v: v if v < vertices else v0)(b0 + nb * (m + 9 * a + 72 * layer))
        a1 = (a + 1) % 8
        if i % 2 == 0:
            out.append((vid(m, a), vid(m + 1, a), vid(m + 1, a1)))
        else:
            out.append((vid(m, a), vid(m + 1, a1), vid(m, a1)))
    return np.array(out, dtype=np.uint32)


def layout(kind):
    """Joint names and parents of each type, from bvhview's own list (its Python package
    is not needed: the names follow SMPL's published order)."""
    body = ["pelvis", "left_hip", "right_hip", "spine1", "left_knee", "right_knee", "spine2",
            "left_ankle", "right_ankle", "spine3", "left_foot", "right_foot", "neck",
            "left_collar", "right_collar", "head", "left_shoulder", "right_shoulder",
            "left_elbow", "right_elbow", "left_wrist", "right_wrist"]
    parents = [-1, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 9, 9, 12, 13, 14, 16, 17, 18, 19]
    if kind == "smpl":
        return body + ["left_hand", "right_hand"], parents + [20, 21]
    names, parents = list(body), list(parents)
    if kind == "smplx":
        names += ["jaw", "left_eye_smplhf", "right_eye_smplhf"]
        parents += [15, 15, 15]
    for side, wrist in (("left", 20), ("right", 21)):
        for finger in ("index", "middle", "pinky", "ring", "thumb"):
            first = len(names)
            names += [f"{side}_{finger}{n}" for n in (1, 2, 3)]
            parents += [wrist, first, first + 1]
    return names, parents


def write_model(path, kind, arrays, parents):
    joints = len(parents)
    extra = {}
    tree = np.array([parents, list(range(joints))], dtype=np.int64)
    if kind == "smplx":
        tree = tree.astype(np.int32)  # root -1, as SMPL-X's files have it
    else:
        tree[0, 0] = 4294967295  # the root as SMPL's files say it
    if kind in ("smplh", "smplx"):
        for side in "lr":
            extra[f"hands_components{side}"] = noise(3, 45 * 45, 1.0).reshape(45, 45)
            extra[f"hands_mean{side}"] = noise(4, 45, 0.3)
    if kind == "smplx":
        extra["lmk_faces_idx"] = np.zeros(51, dtype=np.int64)
        extra["lmk_bary_coords"] = np.full((51, 3), 1.0 / 3.0)
        extra["dynamic_lmk_faces_idx"] = np.zeros((79, 17), dtype=np.int64)
        extra["dynamic_lmk_bary_coords"] = np.full((79, 17, 3), 1.0 / 3.0)
        # Published files hold pickled dictionaries too; bvhview never loads them.
        extra["joint2num"] = np.array({"pelvis": 0}, dtype=object)
    np.savez(path, kintree_table=tree, **arrays, **extra)


def reference(path, kind, joints):
    import torch
    import smplx

    rng = np.random.RandomState({"smpl": 24, "smplh": 52, "smplx": 55}[kind])
    betas = rng.uniform(-2.0, 2.0, (POSES, 10))
    poses = rng.uniform(-0.6, 0.6, (POSES, 3 * joints))
    poses[0] = 0.0  # the rest pose: no pose blend shape at all
    trans = rng.uniform(-1.0, 1.0, (POSES, 3))
    expression = rng.uniform(-1.0, 1.0, (POSES, 10))
    data = dict(np.load(path, allow_pickle=True))
    common = dict(dtype=torch.float64, batch_size=POSES, num_betas=10)
    t = lambda a: torch.tensor(a, dtype=torch.float64)
    if kind == "smpl":
        model = smplx.SMPL(path, data_struct=smplx.utils.Struct(**data), **common)
        out = model(betas=t(betas), global_orient=t(poses[:, :3]), body_pose=t(poses[:, 3:]),
                    transl=t(trans))
    elif kind == "smplh":
        model = smplx.SMPLH(path, data_struct=smplx.utils.Struct(**data), use_pca=False,
                            flat_hand_mean=True, **common)
        out = model(betas=t(betas), global_orient=t(poses[:, :3]), body_pose=t(poses[:, 3:66]),
                    left_hand_pose=t(poses[:, 66:111]), right_hand_pose=t(poses[:, 111:]),
                    transl=t(trans))
    else:
        model = smplx.SMPLX(path, use_pca=False, flat_hand_mean=True, num_expression_coeffs=10,
                            **common)
        out = model(betas=t(betas), expression=t(expression), global_orient=t(poses[:, :3]),
                    body_pose=t(poses[:, 3:66]), jaw_pose=t(poses[:, 66:69]),
                    leye_pose=t(poses[:, 69:72]), reye_pose=t(poses[:, 72:75]),
                    left_hand_pose=t(poses[:, 75:120]), right_hand_pose=t(poses[:, 120:]),
                    transl=t(trans))
    vertices = out.vertices.detach().numpy()
    sample = np.arange(0, vertices.shape[1], 13)
    return {
        "betas": betas,
        "poses": poses,
        "trans": trans,
        "expression": expression if kind == "smplx" else np.zeros((POSES, 0)),
        "joints": out.joints.detach().numpy()[:, :joints],
        "vertex_index": sample.astype(np.int64),
        "vertices": vertices[:, sample],
        "template_sample": data["v_template"][sample],
        "smplx_version": np.array(f"smplx {smplx_version()}, torch {torch.__version__}"),
    }


def smplx_version():
    from importlib.metadata import version
    return version("smplx")


def main():
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cli", default=os.path.join(here, "target/debug/bvhview"))
    parser.add_argument("--models", help="keep the model files in this folder")
    parser.add_argument("--out", default=os.path.join(here, "tests/smpl"))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    with tempfile.TemporaryDirectory() as scratch:
        folder = args.models or scratch
        os.makedirs(folder, exist_ok=True)
        for kind, (built_in, vertices, faces, shapes) in TYPES.items():
            names, parents = layout(kind)
            rest = rest_joints(args.cli, built_in, names)
            arrays = model_arrays(rest, parents, vertices, faces, shapes)
            path = os.path.join(folder, f"{kind.upper()}_NEUTRAL.npz")
            write_model(path, kind, arrays, parents)
            out = reference(path, kind, len(names))
            out["rest_joints"] = rest
            target = os.path.join(args.out, f"{kind}_smplx.npz")
            np.savez_compressed(target, **out)
            print(f"{target}: {POSES} bodies, {len(names)} joints, "
                  f"{len(out['vertex_index'])} of {vertices} vertices", file=sys.stderr)


if __name__ == "__main__":
    main()
