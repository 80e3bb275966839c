"""Issue 35, "Writing and walking": folder walks that loop or lead out (list_takes, load_many,
compile_dataset), write_parquet and planted links, SIGTERM during a compile, and the numbers
from_arrays and unpickling refuse."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import bvhview
from conftest import DATA, REPO

TAKE = DATA / "bvh" / "bvhparser_simple.bvh"
# Every walk here ends in well under a second; past this it loops.
LIMIT = 60


def trapped_folder(tmp_path: Path) -> Path:
    """takes/a.bvh, takes/sub/b.bvh, and links that looped or led out before: two links back up,
    a link to /, a second way to sub/, a second name of a.bvh."""
    takes = tmp_path / "takes"
    (takes / "sub").mkdir(parents=True)
    (takes / "a.bvh").write_bytes(TAKE.read_bytes())
    (takes / "sub" / "b.bvh").write_bytes(TAKE.read_bytes())
    os.symlink(".", takes / "x")
    os.symlink(".", takes / "y")
    os.symlink("/", takes / "root")
    os.symlink("sub", takes / "zsub")
    os.symlink("a.bvh", takes / "c.bvh")
    return takes


def in_child(code: str, *args: str) -> dict:
    """Runs `code` in a fresh Python (so that a walk that loops fails by the time limit rather
    than hanging pytest); `code` prints one JSON line, with the warnings it raised."""
    script = (
        "import json, sys, warnings\n"
        "import bvhview\n"
        "with warnings.catch_warnings(record=True) as said:\n"
        "    warnings.simplefilter('always')\n"
        + "".join(f"    {line}\n" for line in code.splitlines())
        + "    result['warnings'] = [str(w.message) for w in said if w.category is UserWarning]\n"
        "print(json.dumps(result))\n"
    )
    run = subprocess.run(
        [sys.executable, "-c", script, *args], capture_output=True, text=True, timeout=LIMIT
    )
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout.splitlines()[-1])


def test_list_takes_on_a_looping_folder_lists_each_take_once_and_warns(tmp_path):
    takes = trapped_folder(tmp_path)
    listed = "result = {'takes': [[str(p), m] for p, m in bvhview.list_takes(sys.argv[1])]}"
    result = in_child(listed, str(takes))
    assert result["takes"] == [["a.bvh", None], [str(Path("sub") / "b.bvh"), None]]
    said = "\n".join(result["warnings"])
    assert "takes/x: a link back to" in said and "(a loop)" in said
    assert "takes/root: a link to /, outside" in said
    assert "takes/zsub: the folder" in said
    assert "takes/c.bvh: the file" in said
    assert len(result["warnings"]) == 5


def test_load_many_on_a_looping_folder_loads_each_take_once_and_warns(tmp_path):
    takes = trapped_folder(tmp_path)
    loaded = "result = {'paths': [m.path for m in bvhview.load_many(sys.argv[1])]}"
    result = in_child(loaded, str(takes))
    assert result["paths"] == [str(takes / "a.bvh"), str(takes / "sub" / "b.bvh")]
    assert len(result["warnings"]) == 5


def test_compile_dataset_on_a_looping_folder_compiles_each_take_once_and_warns(tmp_path):
    takes = trapped_folder(tmp_path)
    out = tmp_path / "walk.ds"
    result = in_child(
        "manifest = bvhview.compile_dataset(sys.argv[1], sys.argv[2], parquet=False)\n"
        "result = {'clips': [c['path'] for c in manifest['clips']]}",
        str(takes),
        str(out),
    )
    assert result["clips"] == ["a.bvh", "sub/b.bvh"]
    assert len(result["warnings"]) == 5


@pytest.fixture
def two_datasets(tmp_path):
    pytest.importorskip("pyarrow")
    mine, theirs = tmp_path / "mine.ds", tmp_path / "theirs.ds"
    bvhview.compile_dataset(DATA / "bvh", mine, parquet=False)
    bvhview.compile_dataset(DATA / "bvh", theirs, parquet=False)
    return mine, theirs


def test_write_parquet_writes_through_no_planted_link(two_datasets):
    mine, theirs = two_datasets
    # The old temporary name, planted as a link to another file: not followed.
    victim = theirs / "group_0" / "positions.npy"
    before = victim.read_bytes()
    os.symlink(victim, mine / "group_0" / f".frames.parquet.{os.getpid()}")
    written = bvhview.write_parquet(mine)
    assert victim.read_bytes() == before
    assert (mine / "group_0" / "frames.parquet").is_file()
    assert not (mine / "group_0" / "frames.parquet").is_symlink()
    assert written[0] == mine / "group_0" / "frames.parquet"
    leftovers = [p.name for p in (mine / "group_0").iterdir() if p.name.endswith(".partial")]
    assert leftovers == []

    # frames.parquet a link into another dataset: refused, the other untouched.
    target = theirs / "group_0" / "frames.parquet"
    target.write_bytes(b"theirs")
    parquet = mine / "group_0" / "frames.parquet"
    parquet.unlink()
    os.symlink(target, parquet)
    with pytest.raises(ValueError, match="frames.parquet: is a symbolic link"):
        bvhview.write_parquet(mine)
    assert target.read_bytes() == b"theirs"

    # A group folder that is a link to another dataset's: refused.
    parquet.unlink()
    group = mine / "group_1"
    for child in group.iterdir():
        child.unlink()
    group.rmdir()
    os.symlink(theirs / "group_1", group)
    with pytest.raises(ValueError, match="group_1: a symbolic link"):
        bvhview.write_parquet(mine)
    assert not (theirs / "group_1" / "frames.parquet").exists()


def test_write_parquet_refuses_group_names_that_are_not_plain(two_datasets):
    mine, theirs = two_datasets
    manifest = json.loads((mine / "manifest.json").read_text())
    for name in ("../theirs.ds/group_0", str(theirs / "group_0"), ".."):
        manifest["groups"][0]["name"] = name
        (mine / "manifest.json").write_text(json.dumps(manifest))
        with pytest.raises(ValueError, match="bvhview names it group_0"):
            bvhview.write_parquet(mine)
    assert not (theirs / "group_0" / "frames.parquet").exists()


def test_sigterm_during_compile_dataset_leaves_nothing_behind(tmp_path):
    takes = tmp_path / "takes"
    takes.mkdir()
    for k in range(3):
        (takes / f"t{k:02}.bvh").write_bytes((REPO / "assets" / "walk.bvh").read_bytes())
    out = tmp_path / "out.ds"
    # The planted pause holds the compile after its first take, its temporary folder made, until
    # a signal comes: the signal arrives mid-compile however fast the machine (decision 14).
    child = subprocess.Popen(
        [
            sys.executable,
            "-c",
            "import sys, bvhview\n"
            "bvhview.compile_dataset(sys.argv[1], sys.argv[2], threads=1, parquet=False)\n"
            "print('finished')",
            str(takes),
            str(out),
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "BVHVIEW_PLANT_PAUSE": "_compile_dataset"},
    )
    started = time.monotonic()
    while not any(p.name.startswith(".out.ds.") for p in tmp_path.iterdir()):
        assert child.poll() is None, child.communicate()
        assert time.monotonic() - started < LIMIT, "the compile never started"
        time.sleep(0.02)
    child.send_signal(signal.SIGTERM)
    stdout, stderr = child.communicate(timeout=LIMIT)
    # Ended by the signal, as without the cleanup, and before the compile finished.
    assert child.returncode == -signal.SIGTERM, (child.returncode, stdout, stderr)
    assert "finished" not in stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == ["takes"]


def test_from_arrays_refuses_rotations_that_are_none():
    take = bvhview.load(REPO / "assets" / "walk.bvh")
    joints = len(take.joint_names)
    quat = take.local_rotations([0, 1], kind="quat")
    for bad in (0.0, 1e-40):
        rotations = quat.copy()
        rotations[1, 2] = bad
        with pytest.raises(ValueError, match=r"rotations\[1, 2\] .*quaternion of length"):
            bvhview.Motion.from_arrays(take, rotations)
    # A quaternion that is merely not of length 1 is normalised, as before.
    bvhview.Motion.from_arrays(take, quat * 3)

    matrix = take.local_rotations([0], kind="matrix")
    scaled, mirrored = np.diag([2.0, 2.0, 2.0]), np.diag([1.0, 1.0, -1.0])
    for bad in (scaled, mirrored, np.zeros((3, 3)), np.ones((3, 3))):
        rotations = matrix.copy()
        rotations[0, 1] = bad
        with pytest.raises(ValueError, match=r"rotations\[0, 1\] .*not a rotation matrix"):
            bvhview.Motion.from_arrays(take, rotations)
    near = matrix.copy()
    near[0, 1] = np.eye(3) + 1e-5
    bvhview.Motion.from_arrays(take, near)

    six = take.local_rotations([0], kind="6d")
    for bad in ([0, 0, 0, 0, 1, 0], [1, 0, 0, 2, 0, 0]):
        rotations = six.copy()
        rotations[0, 1] = bad
        with pytest.raises(ValueError, match=r"rotations\[0, 1\] .*6D pair"):
            bvhview.Motion.from_arrays(take, rotations)
    assert quat.shape == (2, joints, 4)


@pytest.mark.parametrize("fps", [1e7, 1001, 0.001, float("inf"), float("nan"), -30])
def test_from_arrays_takes_the_rates_convert_takes(fps):
    take = bvhview.load(REPO / "assets" / "walk.bvh")
    with pytest.raises(ValueError, match="fps=.*expected frames per second from 0.01 to 1000"):
        bvhview.Motion.from_arrays(take, take.local_rotations([0]), fps=fps)


def test_from_arrays_at_the_fastest_rate_saves_and_unpickles(tmp_path):
    import pickle

    take = bvhview.load(REPO / "assets" / "walk.bvh")
    made = bvhview.Motion.from_arrays(take, take.local_rotations([0, 1]), fps=1000)
    made.save(tmp_path / "fast.bvh")
    assert pickle.loads(pickle.dumps(made)).frame_count == 2


def test_unpickling_refuses_nan_axes_and_values():
    folder = DATA / "asf_amc"
    take = bvhview.load(folder / "heiden_12.asf", motion=folder / "heiden_12_02_01.amc")
    _, (state,) = take.__reduce__()
    joints = state[7]
    axis_joint = next(k for k, j in enumerate(joints) if j[5] is not None)

    def with_axis(axis):
        changed = list(joints)
        name, parent, offset, channels, end_site, _ = changed[axis_joint]
        changed[axis_joint] = (name, parent, offset, channels, end_site, axis)
        return state[:7] + (changed,) + state[8:]

    for axis in ([float("nan")] * 4, [0.0, 0.0, 0.0, float("nan")], [float("inf"), 0, 0, 0]):
        with pytest.raises(ValueError, match="axis"):
            bvhview._bvhview._from_state(with_axis(axis))
    values = bytearray(state[10])
    for bad in (np.nan, np.inf, -np.inf):
        values[4:8] = np.float32(bad).tobytes()
        with pytest.raises(ValueError, match="not a finite number"):
            bvhview._bvhview._from_state(state[:10] + (bytes(values),) + state[11:])
    assert bvhview._bvhview._from_state(state).frame_count == take.frame_count


def test_a_missing_folder_is_file_not_found_and_load_picks_a_take(tmp_path):
    """Issue 44: a missing folder raised ValueError; load() had no take= for FBX and glTF."""
    with pytest.raises(FileNotFoundError):
        bvhview.compile_dataset(tmp_path / "nowhere", tmp_path / "out.ds")
    with pytest.raises(FileNotFoundError):
        bvhview.list_takes(tmp_path / "nowhere")
    glb = REPO / "tests" / "data" / "gltf" / "bvh11_131_01.glb"
    first = bvhview.load(glb)
    assert np.array_equal(bvhview.load(glb, take=0).positions(), first.positions())
    with pytest.raises(ValueError, match="take"):
        bvhview.load(glb, take="no such take")
    with pytest.raises(ValueError, match="take"):
        bvhview.load(REPO / "assets" / "walk.bvh", take=0)


def test_canonical_layout_keeps_every_joint_where_it_was():
    take = bvhview.load(REPO / "tests" / "data" / "bvh" / "bvhpython_test_freebvh.bvh")
    with pytest.warns(UserWarning, match="lost their prefix"):
        canonical = take.canonical(channels="root6,rot3", order="XYZ", strip_prefix=True)
    assert canonical.joint_names[0] == "Hips"
    assert np.abs(canonical.positions() - take.positions()).max() < 1e-3
    with pytest.raises(ValueError, match="expected one of ZYX"):
        take.canonical(order="ABC")
    with pytest.warns(UserWarning, match="family's names"):
        named = take.canonical(names="smpl22")
    assert named.joint_names[0] == "pelvis"
    walk = bvhview.load(REPO / "tests" / "data" / "bvh" / "bvh11_131_01.bvh")
    with pytest.warns(UserWarning, match="T-pose"):
        tposed = walk.canonical(rest="tpose")
    height = np.ptp(walk.positions()[..., 1])
    assert np.abs(tposed.positions() - walk.positions()).max() < 1e-4 * height


def test_save_writes_the_units_asked_for(tmp_path):
    walk = bvhview.load(REPO / "tests" / "data" / "bvh" / "bvh11_131_01.bvh").trim(0, 5)
    metres = walk.positions() * walk.metres_per_unit
    for name in ("m.bvh", "m.fbx"):
        walk.save(tmp_path / name, units="m")
        back = bvhview.load(tmp_path / name)
        assert np.abs(back.positions() * back.metres_per_unit - metres).max() < 1e-5
    with pytest.raises(ValueError, match="units="):
        walk.save(tmp_path / "x.bvh", units="furlongs")
