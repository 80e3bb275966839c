"""Characters (issue 49): a skinned mesh from FBX or glTF, takes put on it, skinned vertices."""

import json
from pathlib import Path

import numpy as np
import pytest

import bvhview

REPO = Path(__file__).resolve().parents[2]
CHARACTERS = REPO / "tests" / "data" / "characters"
KENNEY = CHARACTERS / "maya_kenney_character_7700_binary.fbx"


def obj_vertices(path):
    return np.array(
        [[float(x) for x in line.split()[1:4]] for line in open(path) if line.startswith("v ")]
    )


def test_the_kenney_character_lands_where_maya_put_it():
    kenney = bvhview.load_character(KENNEY)
    assert kenney.vertex_count == 804
    assert kenney.triangles.shape[1] == 3 and kenney.triangles.dtype == np.uint32
    assert kenney.triangles.max() < 804
    for frame in (4, 9):
        ours = kenney.vertices(frames=frame)
        assert ours.shape == (804, 3) and ours.dtype == np.float32
        maya = obj_vertices(CHARACTERS / f"maya_kenney_character_{frame}.obj") * 0.01
        height = np.ptp(maya[:, 1])
        assert np.abs(ours - maya).max() <= 1e-4 * height


def test_a_take_dressed_on_the_character_matches_the_cli():
    walk = bvhview.load(REPO / "tests" / "data" / "bvh" / "bvh11_131_01.bvh")
    capsule = bvhview.load_character(CHARACTERS / "capsule_mixamo.glb")
    dressed = capsule.dress(walk)
    assert dressed.frame_count == walk.frame_count
    assert dressed.joint_names == capsule.motion.joint_names
    vertices = capsule.vertices(dressed, frames=slice(0, 5))
    assert vertices.shape == (5, capsule.vertex_count, 3)
    # The walk's feet stay on its floor: the lowest vertex is near y = 0.
    assert abs(float(vertices[..., 1].min())) < 0.05


def test_a_take_not_on_the_skeleton_is_refused():
    walk = bvhview.load(REPO / "tests" / "data" / "bvh" / "bvh11_131_01.bvh")
    capsule = bvhview.load_character(CHARACTERS / "capsule_mixamo.fbx")
    with pytest.raises(ValueError, match="dress"):
        capsule.vertices(walk, frames=0)


def test_a_file_without_a_mesh_is_refused():
    with pytest.raises(ValueError, match="no mesh"):
        bvhview.load_character(REPO / "tests" / "data" / "fbx" / "bvh11_131_01.fbx")
    with pytest.raises(ValueError, match="FBX or glTF"):
        bvhview.load_character(REPO / "tests" / "data" / "bvh" / "bvh11_131_01.bvh")


def test_a_character_saved_as_fbx_and_glb_reads_back_with_every_vertex(tmp_path):
    walk = bvhview.load(REPO / "tests" / "data" / "bvh" / "bvh11_131_01.bvh").trim(0, 8)
    capsule = bvhview.load_character(CHARACTERS / "capsule_mixamo.fbx")
    dressed = capsule.dress(walk)
    want = capsule.vertices(dressed)
    height = np.ptp(want[0, :, 1])
    for name in ("walk.fbx", "walk.glb"):
        capsule.save(tmp_path / name, dressed)
        back = bvhview.load_character(tmp_path / name)
        got = back.vertices()
        assert got.shape == want.shape
        assert np.abs(got - want).max() <= 1e-5 * height
    # The character's own take by default; a take off its skeleton is refused by name.
    capsule.save(tmp_path / "own.fbx")
    assert bvhview.load_character(tmp_path / "own.fbx").vertex_count == capsule.vertex_count
    with pytest.raises(ValueError, match="dress"):
        capsule.save(tmp_path / "no.fbx", walk)
    assert not (tmp_path / "no.fbx").exists()
