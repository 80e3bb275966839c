"""Motion.retarget (issue 37): the same take as `bvhview retarget`, exact onto its own
skeleton, overridable by names, errors as ValueError."""

import subprocess

import numpy as np
import pytest

import bvhview
from conftest import DATA, SMPL22_ORDER

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
    target = bvhview.load(DATA.parent / "body" / "smpl.bvh")
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


BODY = DATA.parent / "body"


def test_a_four_legged_body_is_refused_onto_a_person_unless_insisted():
    elephant = bvhview.load(BODY / "biped_elephant.bvh")
    with pytest.raises(ValueError, match="not a two-legged body .* `any_body` retargets it anyway"):
        elephant.retarget("smpl22")
    assert elephant.retarget("smpl22", any_body=True).joint_names[0] == "pelvis"
    # cgspeed's lowercase CMU names read as a person: onto itself, exactly.
    lowercase = bvhview.load(BODY / "cgspeed_lowercase.bvh")
    assert np.abs(lowercase.retarget(lowercase).values - lowercase.values).max() <= 1e-6


def test_compile_dataset_grounds_and_keeps_quaternions_continuous(tmp_path):
    manifest = bvhview.compile_dataset(
        DATA / "bvh",
        tmp_path / "out",
        rotations="quat",
        ground=True,
        quat_continuous=True,
        takes=[("bvhparser_walk_01.bvh", None)],
    )
    assert manifest["options"]["ground"] is True
    assert manifest["options"]["quat_continuous"] is True
    group = manifest["groups"][0]
    positions = np.load(tmp_path / "out" / group["name"] / "positions.npy")
    feet = group["feet"]
    assert [group["joints"][i] for i in feet] == ["LeftFoot", "LeftToeBase", "RightFoot", "RightToeBase"]
    assert positions[:, feet, 1].min() == 0.0
    rotations = np.load(tmp_path / "out" / group["name"] / "rotations.npy")
    dots = (rotations[1:] * rotations[:-1]).sum(-1)
    assert (dots >= 0).all()
    with pytest.raises(ValueError, match="quat_continuous"):
        bvhview.compile_dataset(DATA / "bvh", tmp_path / "six_d", quat_continuous=True)


def test_lock_feet_holds_planted_ankles_as_the_command_does(cli, tmp_path):
    path = DATA / "bvh" / "bvh11_131_01.bvh"
    take = bvhview.load(path)
    locked = take.lock_feet()
    assert locked.values.shape == take.values.shape
    # Only the legs' rotation channels change.
    changed = np.nonzero(np.any(locked.values != take.values, axis=0))[0]
    joints = {take.channel_names[c].rsplit("_", 1)[0] for c in changed}
    assert joints == {"LeftHip", "LeftKnee", "LeftAnkle", "RightHip", "RightKnee", "RightAnkle"}
    out = tmp_path / "locked.bvh"
    run = subprocess.run(
        [str(cli), "convert", str(path), "--lock-feet", "-q", "-o", str(out)],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr
    assert np.abs(bvhview.load(out).values - locked.values).max() < 1e-3
    manifest = bvhview.compile_dataset(
        DATA / "bvh", tmp_path / "ds", lock_feet=True, takes=[("bvh11_131_01.bvh", None)]
    )
    assert manifest["options"]["lock_feet"] is True


def test_one_map_file_per_rig_from_python(cli, tmp_path):
    lafan1, mixamo = BODY / "lafan1.bvh", BODY / "mixamo.bvh"
    fingerprints = {}
    for path in (lafan1, mixamo):
        info = subprocess.run([str(cli), "info", str(path)], capture_output=True, text=True).stdout
        fingerprints[path] = next(l.split()[1] for l in info.splitlines() if l.startswith("fingerprint:"))
    map_file = tmp_path / "rigs.toml"
    map_file.write_text(
        f'[skeleton.{fingerprints[lafan1]}]\n"LeftToe" = ""\n'
        f'[skeleton.{fingerprints[mixamo]}]\n"mixamorig:LeftToeBase" = ""\n'
    )
    # Each take takes its own rig's pair: the left toe left at rest.
    for path, toe in ((lafan1, "LeftToe"), (mixamo, "mixamorig:LeftToeBase")):
        take = bvhview.load(path)
        assert take.retarget_map("smpl22")[toe] == "left_foot"
        out = take.retarget("smpl22", names=map_file)
        foot = out.joint_names.index("left_foot")
        first = out.first_channels[foot]
        assert np.abs(out.values[:, first : first + 3]).max() < 1e-4
    (tmp_path / "takes").mkdir()
    for path in (lafan1, mixamo):
        (tmp_path / "takes" / path.name).write_bytes(path.read_bytes())
    manifest = bvhview.compile_dataset(tmp_path / "takes", tmp_path / "ds", onto="smpl22", names=map_file)
    assert len(manifest["clips"]) == 2 and manifest["skipped"] == []
    assert len(manifest["options"]["map"]["by_skeleton"]) == 2



def test_from_positions_solves_a_models_joints_back_onto_smpl22():
    """Motion.from_positions, as `bvhview solve`: a walk's 22 joints on smpl22, in SMPL's order
    and in metres as HumanML3D keeps them, solved back onto smpl22 stand where they stood."""
    walk = bvhview.load(DATA / "bvh" / "bvhparser_walk_01.bvh").trim(0, 90)
    smpl = walk.retarget("smpl22")
    points = smpl.positions()
    order = [smpl.index(name) for name in SMPL22_ORDER]
    joints = points[:, order] / 100.0
    solved = bvhview.Motion.from_positions(joints, "smpl22", fps=120)
    assert solved.frame_count == 90 and solved.fps == pytest.approx(120)
    np.testing.assert_allclose(solved.positions()[:, order], points[:, order], atol=2e-3)
    # Named in another order: the same take.
    shuffled = list(reversed(range(22)))
    again = bvhview.Motion.from_positions(
        joints[:, shuffled], smpl, joints=[SMPL22_ORDER[k] for k in shuffled], fps=120)
    np.testing.assert_allclose(again.values, solved.values, atol=1e-3)
    with pytest.raises(ValueError, match="5 joints a frame"):
        bvhview.Motion.from_positions(joints[:, :5], "smpl22", fps=20)
    with pytest.raises(ValueError, match="not a finite position"):
        bad = joints.copy()
        bad[3, 4, 1] = np.nan
        bvhview.Motion.from_positions(bad, "smpl22", fps=20)


def test_smooth_cuts_jitter_and_keeps_the_take():
    """smooth(hz), as `convert --smooth`, and from_positions(smooth=): a walk's joints with
    jitter added come back nearer the clean ones."""
    # From frame 10 on: the file's first frame is a T-pose, a jump any low-pass spreads.
    walk = bvhview.load(DATA / "bvh" / "bvhparser_walk_01.bvh").trim(10, None)
    clean = walk.positions()
    rng = np.random.default_rng(48)
    noisy_points = clean + rng.uniform(-0.2, 0.2, clean.shape).astype(np.float32)
    names = walk.joint_names  # End Sites as exports name them, LeftToeBase_End
    raw = bvhview.Motion.from_positions(noisy_points, walk, joints=names, fps=walk.fps)
    smooth = bvhview.Motion.from_positions(
        noisy_points, walk, joints=names, fps=walk.fps, smooth=6)
    error = lambda m: float(np.linalg.norm(m.positions() - clean, axis=-1).mean())
    assert error(smooth) <= 0.5 * error(raw)
    np.testing.assert_allclose(walk.smooth(6).positions(), clean, atol=1.0)
    with pytest.raises(ValueError, match="below half the frame rate"):
        walk.smooth(61)


def test_from_humanml3d_recovers_its_own_positions():
    """Motion.from_humanml3d, as `solve --from humanml3d`: HumanML3D's own pair (tests/humanml3d)
    recovered and solved onto smpl22, each bone along the recovered positions' bones."""
    root = DATA.parent / "humanml3d"
    vectors = np.load(root / "new_joint_vecs_012314.npy")
    joints = np.load(root / "new_joints_012314.npy")
    # smpl22's bones are not HumanML3D's: the points off the data are said, the head first.
    with pytest.warns(UserWarning, match=r"off the data \(skeleton units\): head by 3\.92"):
        take = bvhview.Motion.from_humanml3d(vectors)
    assert take.frame_count == 170 and take.fps == pytest.approx(20)
    points = take.positions()
    order = [take.index(name) for name in SMPL22_ORDER]
    # smpl22's bones are not HumanML3D's: their directions agree, within a degree.
    for parent, child in [(1, 4), (4, 7), (16, 18), (18, 20)]:
        a = points[:, order[child]] - points[:, order[parent]]
        b = joints[:, child] - joints[:, parent]
        cos = (a * b).sum(-1) / np.linalg.norm(a, axis=-1) / np.linalg.norm(b, axis=-1)
        assert float(cos.min()) > np.cos(np.radians(1.0))
    with pytest.raises(ValueError, match="263"):
        bvhview.Motion.from_humanml3d(vectors[:, :200])


def test_compile_dataset_onto_a_four_legged_body_needs_any_body(tmp_path):
    options = dict(onto=BODY / "biped_elephant.bvh", takes=[("bvhparser_walk_01.bvh", None)])
    with pytest.raises(ValueError, match="a two-legged body, and .* `any_body` retargets it anyway"):
        bvhview.compile_dataset(DATA / "bvh", tmp_path / "refused", **options)
    assert not (tmp_path / "refused").exists()
    manifest = bvhview.compile_dataset(DATA / "bvh", tmp_path / "made", any_body=True, **options)
    assert len(manifest["groups"]) == 1


def test_a_retarget_that_crosses_the_sides_is_refused_unless_forced():
    walk = bvhview.load(DATA / "bvh" / "bvhparser_walk_01.bvh")
    swapped = {"LeftUpLeg": "right_hip", "RightUpLeg": "left_hip"}
    with pytest.raises(ValueError, match="hips' sides are crossed .* `force` writes it anyway"):
        walk.retarget("smpl22", swapped)
    with pytest.warns(UserWarning, match="kept as force=True asks though its hips' sides are crossed"):
        forced = walk.retarget("smpl22", swapped, force=True)
    assert forced.joint_names[0] == "pelvis"
    # The report on the result: the same figures `bvhview retarget` prints.
    report = forced.retarget_check
    assert report["hips"]["turn"] > 170.0
    assert report["refusal"].startswith("its hips' sides are crossed")
    right = walk.retarget("smpl22").retarget_check
    assert right["refusal"] is None and right["hips"]["turn"] < 10.0
    assert right["bones_median"] < 5.0 and right["bones_p99"] < 20.0
    assert 0.98 < right["path"] < 1.02
    assert right["line"].startswith("check: sides held; hips ")
    # An edit is no longer what was measured; a loaded take was never retargeted.
    assert walk.retarget_check is None and walk.retarget("smpl22").trim(0, 10).retarget_check is None


def test_a_dataset_onto_a_skeleton_records_each_clips_check(tmp_path):
    folder = tmp_path / "takes"
    folder.mkdir()
    (folder / "walk.bvh").write_bytes((DATA / "bvh" / "bvhparser_walk_01.bvh").read_bytes())
    manifest = bvhview.compile_dataset(folder, tmp_path / "made", onto="smpl22")
    (clip,) = manifest["clips"]
    check = clip["retarget_check"]
    assert check["hips"]["turn"] < 10.0 and check["shoulders"]["turn"] < 10.0
    assert check["bones_median"] < 5.0
    # Without onto= nothing was retargeted, and no clip says it was.
    plain = bvhview.compile_dataset(folder, tmp_path / "plain")
    assert "retarget_check" not in plain["clips"][0]


def test_a_built_in_skeleton_loads_as_a_take_by_its_name():
    smpl22 = bvhview.load("smpl22")
    assert smpl22.frame_count == 1
    assert smpl22.joint_names[:3] == ["pelvis", "left_hip", "left_knee"]
    pelvis = smpl22.positions()[0, 0]
    assert pelvis.tolist() == [0.0, 97.0, 0.0]
