"""AMASS's .npz files (SMPL, SMPL-H and SMPL-X parameters) through the Python package, read as
the CLI reads them; each joint's rotation is the file's axis-angle, checked with numpy alone."""

import numpy as np
import pytest

import bvhview
from conftest import DATA, cli_positions

FILES = sorted((DATA / "smpl").glob("*.npz"))


@pytest.mark.parametrize("path", FILES, ids=[p.name for p in FILES])
def test_amass_files_load_as_the_cli_reads_them(cli, path):
    names, expected = cli_positions(cli, path)
    take = bvhview.load(path)
    assert take.point_names == names
    np.testing.assert_array_equal(take.positions()[:, take.point_joints], expected)


def rotation(axis_angle):
    """Rodrigues: the matrix of an axis-angle."""
    angle = np.linalg.norm(axis_angle)
    if angle < 1e-12:
        return np.eye(3)
    k = axis_angle / angle
    cross = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * cross + (1 - np.cos(angle)) * cross @ cross


def test_the_knee_turns_as_the_file_says():
    path = DATA / "smpl" / "amass_smplh_walk.npz"
    arrays = np.load(path)
    take = bvhview.load(path)
    rotations = take.local_rotations(kind="matrix")
    knee = take.index("left_knee")
    for f in (0, 17, 59):
        want = rotation(arrays["poses"][f, 3 * 4 : 3 * 4 + 3])
        np.testing.assert_allclose(rotations[f, knee], want, atol=1e-6)


def test_save_writes_amass_as_the_cli_does(cli, tmp_path):
    import subprocess

    path = DATA / "smpl" / "amass_smplx_walk.npz"
    bvhview.load(path).save(tmp_path / "mine.npz")
    subprocess.run([str(cli), "convert", "-q", str(path), "-o", str(tmp_path / "cli.npz")], check=True)
    assert (tmp_path / "mine.npz").read_bytes() == (tmp_path / "cli.npz").read_bytes()
    before, after = np.load(path), np.load(tmp_path / "mine.npz")
    np.testing.assert_allclose(after["poses"], before["poses"], atol=1e-6)
    np.testing.assert_allclose(after["trans"], before["trans"], atol=1e-6)
    assert str(after["surface_model_type"]) == "smplx"


def fake_model(kind, folder):
    """The fake model `scripts/make_smpl_models.py` makes, built on the rest joints of its
    committed reference (tests/smpl/), written in `folder`; and that reference."""
    import importlib.util

    from conftest import REPO

    spec = importlib.util.spec_from_file_location("make_smpl_models", REPO / "scripts" / "make_smpl_models.py")
    maker = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(maker)
    reference = np.load(REPO / "tests" / "smpl" / f"{kind}_smplx.npz")
    _, vertices, faces, shapes = maker.TYPES[kind]
    _, parents = maker.layout(kind)
    arrays = maker.model_arrays(reference["rest_joints"], parents, vertices, faces, shapes)
    path = folder / f"{kind.upper()}_NEUTRAL.npz"
    maker.write_model(str(path), kind, arrays, parents)
    return path, reference


@pytest.mark.parametrize("kind,width", [("smpl", 72), ("smplh", 156)])
def test_a_body_model_character_moves_as_smplx_moves_it(tmp_path, kind, width):
    model, reference = fake_model(kind, tmp_path)
    for i in (3, 14):
        character = bvhview.load_character(model, betas=reference["betas"][i])
        motion = tmp_path / f"body{i}.npz"
        np.savez(motion, poses=reference["poses"][i : i + 1], trans=reference["trans"][i : i + 1],
                 betas=reference["betas"][i], mocap_framerate=np.array(30.0))
        take = character.dress(bvhview.load(motion))
        vertices = character.vertices(take, frames=0)[reference["vertex_index"]]
        want = reference["vertices"][i]
        # smplx's Z up in bvhview's Y up: (x, y, z) -> (x, z, -y).
        want = np.stack([want[:, 0], want[:, 2], -want[:, 1]], axis=1)
        np.testing.assert_allclose(vertices, want, atol=1e-5)


def test_an_amass_file_read_on_a_model_stands_as_the_model_puts_it(tmp_path):
    model, _ = fake_model("smplh", tmp_path)
    plain = bvhview.load(DATA / "smpl" / "amass_smplh_walk.npz")
    on_model = bvhview.load(DATA / "smpl" / "amass_smplh_walk.npz", body_model=tmp_path)
    assert any("read on the body of" in w and model.name in w for w in on_model.warnings)
    # The same rotations; the pelvis placed from the model's rest pelvis, not trans alone.
    np.testing.assert_allclose(plain.local_rotations(kind="matrix"), on_model.local_rotations(kind="matrix"), atol=1e-6)


def test_a_pickled_amass_take_keeps_its_body(tmp_path):
    import pickle

    path = DATA / "smpl" / "amass_smplh_walk.npz"
    take = pickle.loads(pickle.dumps(bvhview.load(path)))
    out = tmp_path / "again.npz"
    take.save(out)
    written, source = np.load(out), np.load(path)
    np.testing.assert_array_equal(written["betas"], source["betas"])
    assert str(written["gender"]) == str(source["gender"])


def test_metrics_are_the_clis(cli):
    import subprocess

    path = DATA / "bvh" / "bvh11_131_01.bvh"
    measured = bvhview.metrics(bvhview.load(path))
    printed = subprocess.run([cli, "metrics", str(path)], capture_output=True, text=True, check=True).stdout
    assert f"skating ratio {measured['skating_ratio']:.4f};" in printed
    assert f"skate {measured['skate_mm']:.2f} mm;" in printed
    assert measured["phys_err_mm"] == pytest.approx(
        measured["penetrate_mm"] + measured["float_mm"] + measured["skate_mm"]
    )
    assert [f["point"] for f in measured["feet"]] == ["LeftToe", "RightToe"]
    with pytest.raises(ValueError, match="skate_speed=0"):
        bvhview.metrics(bvhview.load(path), skate_speed=0)


def test_keypoints_of_a_layout_become_a_take(cli, tmp_path):
    import subprocess

    walk = DATA / "bvh" / "bvh11_131_01.bvh"
    keypoints = tmp_path / "walk_coco.npy"
    subprocess.run([cli, "positions", str(walk), "--layout", "coco17", "--frames", "0..60",
                    "-o", str(keypoints)], check=True, capture_output=True)
    points = np.load(keypoints)
    assert points.shape == (60, 17, 4)
    with pytest.warns(UserWarning, match="coco17 has no pelvis"):
        take = bvhview.Motion.from_positions(points, walk, fps=120, layout="coco17")
    back = tmp_path / "back.bvh"
    subprocess.run([cli, "solve", str(keypoints), "--layout", "coco17", "--fps", "120", "--onto",
                    str(walk), "-o", str(back)], check=True, capture_output=True)
    np.testing.assert_allclose(take.positions(), bvhview.load(back).positions(), atol=1e-3)
    with pytest.raises(ValueError, match="18 points a frame; coco17 has 17"):
        bvhview.Motion.from_positions(np.zeros((2, 18, 3)), walk, fps=30, layout="coco17")
