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
