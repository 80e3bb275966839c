"""Motion.retarget (issue 37): the same take as `bvhview retarget`, exact onto its own
skeleton, overridable by names, errors as ValueError."""

import numpy as np
import pytest

import bvhview
from conftest import DATA

MIXAMO = DATA / "bvh" / "bvhpython_test_freebvh.bvh"


def test_retarget_onto_the_built_in_skeleton():
    take = bvhview.load(MIXAMO)
    out = take.retarget("smpl22")
    assert len(out.joint_names) == 22 + 5
    assert out.joint_names[0] == "pelvis"
    assert out.frame_count == take.frame_count
    assert take.retarget_map("smpl22")["mixamorig:LeftUpLeg"] == "left_hip"


def test_retarget_onto_its_own_skeleton_is_exact():
    take = bvhview.load(MIXAMO)
    same = take.retarget(take)
    assert np.abs(same.values - take.values).max() <= 1e-6


def test_retarget_names_override_and_errors():
    take = bvhview.load(MIXAMO)
    target = bvhview.load(DATA.parent / "retarget" / "smpl.bvh")
    out = take.retarget(target, names={"mixamorig:LeftForeArm": ""})
    elbow = out.joint_names.index("left_elbow")
    first = out.first_channels[elbow]
    assert np.abs(out.values[:, first : first + 3]).max() < 1e-4
    with pytest.raises(ValueError, match="Nope"):
        take.retarget("smpl22", names={"Nope": "pelvis"})
    with pytest.raises(ValueError, match="no mappable chain"):
        take.retarget(DATA / "bvh" / "bvhanim_test_simple.bvh")
    with pytest.raises(TypeError):
        take.retarget(3)


def test_compile_dataset_onto_one_skeleton(tmp_path):
    with pytest.warns(bvhview.SkippedTake, match="no mappable chain"):
        manifest = bvhview.compile_dataset(DATA / "bvh", tmp_path / "out", onto="smpl22")
    assert len(manifest["groups"]) == 1
    assert manifest["groups"][0]["joints"][0] == "pelvis"
