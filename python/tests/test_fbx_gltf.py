"""FBX and glTF takes through the Python package, and an FBX converted to BVH read by other BVH
readers (pybvh, bvhio) that owe nothing to bvhview (issue 36)."""

import subprocess

import numpy as np
import pytest

import bvhview
from conftest import DATA, cli_positions

# Blender's exports of repository takes (tests/data/fbx/README.md) and a ufbx test file.
FILES = [
    DATA / "fbx" / "bvh11_131_01.fbx",
    DATA / "fbx" / "bvhpython_test_freebvh.fbx",
    DATA / "gltf" / "bvh11_131_01.glb",
    DATA / "gltf" / "bvh11_131_01.gltf",
    DATA / "fbx" / "ufbx" / "maya_human_ik_7400_binary.fbx",
]


@pytest.mark.parametrize("path", FILES, ids=[p.name for p in FILES])
def test_fbx_and_gltf_load_as_the_cli_reads_them(cli, path):
    names, expected = cli_positions(cli, path)
    take = bvhview.load(path)
    assert take.point_names == names
    np.testing.assert_array_equal(take.positions()[:, take.point_joints], expected)


def test_load_many_takes_fbx_and_gltf_beside_bvh():
    paths = [FILES[0], FILES[2], DATA / "bvh" / "bvh11_131_01.bvh"]
    takes = bvhview.load_many(paths)
    assert [t.frame_count for t in takes] == [60, 60, 994]
    # The first 60 frames of the source take, as Blender wrote them: within 1e-4 of the height.
    source = takes[2].positions()[:60]
    height = np.ptp(source[0], axis=0).max()
    for take in takes[:2]:
        columns = [takes[2].point_names.index(n) for n in take.point_names if n in takes[2].point_names]
        mine = [i for i, n in enumerate(take.point_names) if n in takes[2].point_names]
        got = take.positions()[:, mine]
        assert np.abs(got - source[:, columns]).max() <= 1e-4 * height


def test_a_file_without_a_skeleton_raises_an_error():
    with pytest.raises(Exception, match="no skeleton"):
        bvhview.load(DATA / "fbx" / "ufbx" / "motionbuilder_actor_7700_binary.fbx")


@pytest.fixture(scope="module")
def converted(cli, tmp_path_factory):
    """bvh11_131_01.fbx converted to BVH by the CLI."""
    out = tmp_path_factory.mktemp("fbx") / "walk.bvh"
    subprocess.run([str(cli), "convert", "-q", str(FILES[0]), "-o", str(out)], check=True)
    return out


def test_the_converted_bvh_reads_back_in_bvhview(converted):
    fbx = bvhview.load(FILES[0])
    bvh = bvhview.load(converted)
    assert bvh.frame_count == fbx.frame_count == 60
    assert bvh.frame_time == pytest.approx(fbx.frame_time, abs=1e-7)
    assert bvh.point_names == fbx.point_names
    height = np.ptp(fbx.positions()[0], axis=0).max()
    assert np.abs(bvh.positions() - fbx.positions()).max() <= 1e-5 * height


def test_pybvh_reads_the_converted_bvh(converted):
    pybvh = pytest.importorskip("pybvh")
    theirs = pybvh.read_bvh_file(converted)
    ours = bvhview.load(converted)
    assert theirs.frame_count == ours.frame_count
    assert theirs.frame_time == pytest.approx(ours.frame_time, abs=1e-7)
    joints = [n for n, end in zip(ours.joint_names, ours.end_sites) if not end]
    assert list(theirs.joint_names) == joints


def test_bvhio_reads_the_converted_bvh(converted):
    bvhio = pytest.importorskip("bvhio")
    container = bvhio.readAsBvh(str(converted))
    ours = bvhview.load(converted)
    assert container.FrameCount == ours.frame_count
    assert container.FrameTime == pytest.approx(ours.frame_time, abs=1e-7)
    # Its world positions of every joint in the last frame equal ours.
    root = bvhio.readAsHierarchy(str(converted))
    last = ours.frame_count - 1
    root.loadPose(last)
    positions = ours.positions()[last]
    height = np.ptp(ours.positions()[0], axis=0).max()
    compared = 0
    for joint, _, _ in root.layout():
        if joint.Name in ours.point_names:
            want = positions[ours.point_names.index(joint.Name)]
            got = np.array(list(joint.PositionWorld))
            assert np.abs(got - want).max() <= 1e-4 * height, joint.Name
            compared += 1
    assert compared >= 24
