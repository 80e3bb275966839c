"""compile_dataset, Dataset, Parquet and the Dask helper, on the repository's takes: against the
CLI's `bvhview dataset`, against forward kinematics done here in numpy, and pieces on a Dask
cluster against one process."""

import filecmp
import json
import mmap
import os
import re
import shutil
import subprocess
import warnings
from pathlib import Path

import numpy as np
import pytest

import bvhview
from conftest import DATA, REPO, SMPL22_ORDER


@pytest.fixture(scope="module")
def compiled(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("compiled") / "ds"
    with pytest.warns(bvhview.SkippedTake):
        bvhview.compile_dataset(DATA, out)
    return out


def quietly(*args, **kwargs) -> dict:
    """compile_dataset without its warnings for skipped takes (the repository holds 8)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", bvhview.SkippedTake)
        return bvhview.compile_dataset(*args, **kwargs)


def fk_example() -> dict:
    """The numpy FK block of docs/PYTHON.md, run as it is written there."""
    text = (REPO / "docs" / "PYTHON.md").read_text()
    marker = "<!-- the numpy FK example: python/tests/test_dataset.py runs this block -->"
    block = text.split(marker, 1)[1].split("```python\n", 1)[1].split("```", 1)[0]
    namespace: dict = {}
    exec(compile(block, "docs/PYTHON.md", "exec"), namespace)
    return namespace


def same_tree(a: Path, b: Path) -> None:
    """Every file of two folders, byte for byte."""
    names_a = sorted(p.relative_to(a) for p in a.rglob("*") if p.is_file())
    names_b = sorted(p.relative_to(b) for p in b.rglob("*") if p.is_file())
    assert names_a == names_b
    for name in names_a:
        assert filecmp.cmp(a / name, b / name, shallow=False), name


def clip_rows(dataset: Path, manifest: dict, clip: dict, array: str) -> np.ndarray:
    group = manifest["groups"][clip["group"]]
    data = np.load(dataset / group["name"] / f"{array}.npy", mmap_mode="r")
    return np.array(data[clip["start"] : clip["start"] + clip["frames"]])


def test_the_package_writes_what_the_command_writes(compiled, cli, tmp_path):
    out = tmp_path / "by_cli"
    run = subprocess.run([str(cli), "dataset", str(DATA), "-o", str(out)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    same_tree(compiled, out)
    manifest = json.loads((compiled / "manifest.json").read_text())
    assert manifest["format"] == "bvhview-dataset 2"
    assert manifest["options"] == {
        "fps": 30.0,
        "rotations": "6d",
        "root_relative": False,
        "feet": None,
        "contact_height_m": 0.05,
        "contact_speed_m_per_s": 0.5,
        "floor_window_s": 1.0,
        "up": "y",
        "units": "metres",
        "ground": False,
        "quat_continuous": False,
        "onto": None,
        "lock_feet": False,
        "map": {"all": [], "by_skeleton": []},
    }
    # 70 takes: the three characters of tests/data/characters (issue 49) are takes too, and the
    # three AMASS files of tests/data/smpl.
    assert manifest["takes"]["listed"] == manifest["takes"]["count"] == 70
    # Skipped takes: each named with its path:line:column, as the command said them.
    # The manifest names paths relative to the folder, the command's stderr as given.
    for skipped in manifest["skipped"]:
        assert f"skipped {DATA}/{skipped['error']}" in run.stderr
    first = manifest["skipped"][0]
    assert first["path"] == "bvh_malformed/dali_test-empty.bvh"
    assert first["error"] == "bvh_malformed/dali_test-empty.bvh:1:1: expected HIERARCHY, found end of file"
    assert manifest["bvhview"] == bvhview.__version__


def test_list_takes_is_the_folder_in_path_order_with_asf_amc_pairs():
    takes = bvhview.list_takes(DATA)
    assert takes[0] == (Path("asf_amc/heiden_12.asf"), Path("asf_amc/heiden_12_02_01.amc"))
    keys = [motion or path for path, motion in takes]
    assert keys == sorted(keys)
    loaded = bvhview.load_many(DATA, errors="return")
    loaded_paths = [m.path for m in loaded if isinstance(m, bvhview.Motion)]
    listed = [str(DATA / p) for p, _ in takes]
    assert all(path in listed for path in loaded_paths)


def check_fk(out: Path, manifest: dict, kind: str) -> int:
    """Every clip's positions rebuilt by the documented numpy FK from the dataset's arrays
    alone, within 1e-5 of the figure's height; returns the clips checked."""
    fk = fk_example()["forward_kinematics"]
    rest = {g["name"]: np.load(out / g["name"] / "rest_offsets.npy") for g in manifest["groups"]}
    for clip in manifest["clips"]:
        group = manifest["groups"][clip["group"]]
        index = [c for c in manifest["clips"] if c["group"] == clip["group"]].index(clip)
        rotations = clip_rows(out, manifest, clip, "rotations")
        translations = clip_rows(out, manifest, clip, "translations")
        positions = clip_rows(out, manifest, clip, "positions")
        world = fk(group, kind, rotations, translations, rest[group["name"]][index])
        height = np.ptp(positions[..., 1], axis=1).max()
        assert np.abs(world - positions).max() <= 1e-5 * height, (clip["path"], kind)
    return len(manifest["clips"])


@pytest.mark.parametrize("kind", ["quat", "matrix", "6d", "euler", "axis_angle"])
def test_the_arrays_rebuild_the_positions_by_the_documented_numpy_fk(tmp_path, kind):
    """Rotations, translations and rest offsets alone give the stored positions again through
    the FK in docs/PYTHON.md (no bvhview code), on every clip of the repository: position
    channels below the root included."""
    out = tmp_path / kind
    manifest = quietly(DATA, out, rotations=kind)
    assert check_fk(out, manifest, kind) == 59


def test_the_whole_corpus_rebuilds_by_numpy_fk(tmp_path):
    from conftest import whole_corpus_or_skip

    corpus = whole_corpus_or_skip()
    manifest = quietly(corpus, tmp_path / "corpus")
    assert check_fk(tmp_path / "corpus", manifest, "6d") == len(manifest["clips"]) >= 30


def moving_below_a_static_root(folder: Path) -> None:
    """Takes whose travel is in joints below the root: Bandai's layout (the root still, `Hips`
    moving with position channels) and a Neuron-like one (a spine joint sliding)."""
    folder.mkdir()
    rows_bandai, rows_neuron = [], []
    for f in range(90):
        t = f / 30.0
        rows_bandai.append(f"0 0 0 0 0 0 {100 * t:.4f} {90 + 2 * np.sin(6 * t):.4f} {5 * t:.4f} {10 * np.sin(t):.4f} {20 * t:.4f} 3 "
                           f"{30 * np.sin(3 * t):.4f} 0 0 0 0 0")
        rows_neuron.append(f"{40 * t:.4f} 95 0 0 {15 * t:.4f} 0 0 {3 * np.sin(5 * t):.4f} 10 0 {25 * np.sin(2 * t):.4f} 0 "
                           f"{10 * np.sin(4 * t):.4f} 5 0")
    bandai = """HIERARCHY
ROOT joint_Root
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Hips
  {
    OFFSET 0 90 0
    CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
    JOINT UpperLeg_L
    {
      OFFSET 10 -5 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT LowerLeg_L
      {
        OFFSET 0 -42 0
        CHANNELS 3 Zrotation Xrotation Yrotation
        End Site
        {
          OFFSET 0 -40 0
        }
      }
    }
  }
}
MOTION
Frames: 90
Frame Time: 0.0333333
""" + "\n".join(rows_bandai) + "\n"
    neuron = """HIERARCHY
ROOT Hips
{
  OFFSET 0 95 0
  CHANNELS 6 Xposition Yposition Zposition Yrotation Xrotation Zrotation
  JOINT Spine
  {
    OFFSET 0 10 0
    CHANNELS 6 Xposition Yposition Zposition Yrotation Xrotation Zrotation
    JOINT Head
    {
      OFFSET 0 50 0
      CHANNELS 3 Yrotation Xrotation Zrotation
      End Site
      {
        OFFSET 0 20 0
      }
    }
  }
}
MOTION
Frames: 90
Frame Time: 0.0333333
""" + "\n".join(rows_neuron) + "\n"
    (folder / "bandai_walk.bvh").write_text(bandai)
    (folder / "neuron_slide.bvh").write_text(neuron)


def test_joints_moving_below_a_static_root_are_in_the_arrays(tmp_path, cli):
    folder = tmp_path / "takes"
    moving_below_a_static_root(folder)
    for kind in ("6d", "quat"):
        out = tmp_path / f"ds_{kind}"
        manifest = quietly(folder, out, rotations=kind)
        assert check_fk(out, manifest, kind) == 2
    manifest = json.loads((tmp_path / "ds_6d" / "manifest.json").read_text())
    bandai = next(c for c in manifest["clips"] if c["path"] == "bandai_walk.bvh")
    # The travel is Hips', which root_translations follow and root-relative frames remove.
    assert bandai["travel_joint"] == "Hips"
    roots = clip_rows(tmp_path / "ds_6d", manifest, bandai, "root_translations")
    assert np.ptp(roots[:, 0]) > 2.5
    relative = quietly(folder, tmp_path / "relative", root_relative=True)
    clip = next(c for c in relative["clips"] if c["path"] == "bandai_walk.bvh")
    positions = clip_rows(tmp_path / "relative", relative, clip, "positions")
    hips = relative["groups"][clip["group"]]["joints"].index("Hips")
    assert np.abs(positions[:, hips, [0, 2]]).max() == 0.0
    # in_place takes the travel from Hips too.
    take = bvhview.load(folder / "bandai_walk.bvh")
    still = take.in_place().positions()
    hips = take.joint_names.index("Hips")
    assert np.ptp(take.positions()[:, hips, 0]) > 250
    assert np.ptp(still[:, hips, 0]) < 1e-3 and np.ptp(still[:, hips, 2]) < 1e-3
    # info names the joint that carries the travel.
    run = subprocess.run([str(cli), "info", str(folder / "bandai_walk.bvh")], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert re.search(r"travel:\s+Hips", run.stdout), run.stdout


@pytest.mark.parametrize("kind", ["quat", "matrix", "6d", "euler", "axis_angle"])
def test_to_motion_saves_takes_that_load_back_to_the_datasets_positions(tmp_path, kind):
    """compile -> a clip's arrays -> Dataset.to_motion -> save (BVH and glTF for one kind) ->
    load -> positions within 1e-5 of the height of the dataset's, every clip of a group."""
    folder = tmp_path / "takes"
    moving_below_a_static_root(folder)
    for source in ("bvh/bvh11_131_01.bvh", "bvh/makehuman_walk1.bvh", "asf_amc/heiden_12.asf"):
        if (DATA / source).exists():
            shutil.copyfile(DATA / source, folder / Path(source).name)
    amc = DATA / "asf_amc" / "heiden_12_02_01.amc"
    shutil.copyfile(amc, folder / amc.name)
    out = tmp_path / "ds"
    manifest = quietly(folder, out, rotations=kind)
    checked = 0
    for g, group in enumerate(manifest["groups"]):
        data = bvhview.Dataset(out, group=g)
        for k in range(len(data)):
            item = data[k]
            clip = manifest["clips"][item["clip"]]
            take = data.to_motion(item["rotations"], item["translations"], clip=item["clip"])
            assert take.frame_count == clip["frames"] and take.fps == pytest.approx(30.0)
            saved = tmp_path / f"back_{g}_{k}.bvh"
            take.save(saved)
            back = bvhview.load(saved).positions()
            height = np.ptp(item["positions"][..., 1], axis=1).max()
            assert np.abs(back - item["positions"]).max() <= 1e-5 * height, (clip["path"], kind)
            if kind == "6d":
                glb = tmp_path / f"back_{g}_{k}.glb"
                take.save(glb)
                assert glb.stat().st_size > 0
            checked += 1
    assert checked == len(manifest["clips"]) >= 3


def test_to_motion_takes_root_translations_and_refuses_what_is_no_take(compiled, tmp_path):
    manifest = json.loads((compiled / "manifest.json").read_text())
    group = next(k for k, g in enumerate(manifest["groups"]) if g["translated"] == [0])
    data = bvhview.Dataset(compiled, group=group)
    item = data[0]
    # Without translations, the root's comes from root_translations (its world position).
    take = data.to_motion(item["rotations"], root_translations=item["root_translations"], clip=item["clip"])
    height = np.ptp(item["positions"][..., 1], axis=1).max()
    assert np.abs(take.positions() - item["positions"]).max() <= 1e-5 * height
    rotations = item["rotations"].copy()
    with pytest.raises(ValueError, match="rotations: .* numbers where"):
        data.to_motion(rotations[:, :-1])
    # Issue 44: numbers of another kind are named, with the argument that says so.
    quats = take.local_rotations(kind="quat")[:, : rotations.shape[1]]
    if manifest["options"]["rotations"] != "quat":
        with pytest.raises(ValueError, match='they fit quat numbers: name their kind \\(kind="quat"\\)'):
            data.to_motion(quats)
    rotations[0, 0] = 0.0
    with pytest.raises(ValueError, match="no rotation"):
        data.to_motion(rotations)
    rotations[0, 0] = np.nan
    with pytest.raises(ValueError, match="not finite"):
        data.to_motion(rotations)
    with pytest.raises(ValueError, match=r"^(?!.*--).*fps=\S+: expected frames per second"):
        data.to_motion(item["rotations"], fps=1e7)


def test_windows_strides_shards_and_groups(compiled):
    manifest = json.loads((compiled / "manifest.json").read_text())
    with pytest.raises(ValueError, match="38 skeleton topologies.*choose one with group="):
        bvhview.Dataset(compiled, window=8)
    group = next(k for k, g in enumerate(manifest["groups"]) if g["clips"] == 3)
    data = bvhview.Dataset(compiled, window=2, stride=1, group=group)
    clips = [c for c in manifest["clips"] if c["group"] == group]
    assert len(data) == sum(max(0, c["frames"] - 2 + 1) for c in clips)
    item = data[0]
    assert set(item) == {
        "positions", "rotations", "translations", "root_translations", "velocities", "foot_contacts", "clip", "start"
    }
    joints = len(manifest["groups"][group]["joints"])
    assert item["positions"].shape == (2, joints, 3) and item["positions"].dtype == np.float32
    assert item["foot_contacts"].dtype == np.uint8
    # Every item is its clip's frames start..start+window.
    for index in range(len(data)):
        item = data[index]
        clip = manifest["clips"][item["clip"]]
        rows = clip_rows(compiled, manifest, clip, "positions")
        np.testing.assert_array_equal(item["positions"], rows[item["start"] : item["start"] + 2])
    np.testing.assert_array_equal(data[-1]["positions"], data[len(data) - 1]["positions"])
    with pytest.raises(IndexError):
        data[len(data)]
    # Whole clips when no window is given; a clip shorter than the window gives nothing.
    whole = bvhview.Dataset(compiled, group=manifest["groups"][group]["name"])
    assert [whole[i]["positions"].shape[0] for i in range(len(whole))] == [c["frames"] for c in clips]
    longest = max(c["frames"] for c in clips)
    assert len(bvhview.Dataset(compiled, window=longest + 1, group=group)) == 0
    # Shards: disjoint, together the whole, dealt out as DistributedSampler deals.
    shards = [data.shard(rank, 3) for rank in range(3)]
    seen = sorted((s[i]["clip"], s[i]["start"]) for s in shards for i in range(len(s)))
    assert seen == sorted((data[i]["clip"], data[i]["start"]) for i in range(len(data)))
    assert [shards[1][0]["start"], shards[1][0]["clip"]] == [data[1]["start"], data[1]["clip"]]
    with pytest.raises(ValueError):
        data.shard(3, 3)


def test_parquet_holds_the_arrays_row_per_frame(tmp_path):
    pa = pytest.importorskip("pyarrow")
    pq = pytest.importorskip("pyarrow.parquet")
    out = tmp_path / "ds"
    assert not (quietly(DATA, tmp_path / "plain") and (tmp_path / "plain" / "group_0" / "frames.parquet").exists())
    manifest = quietly(DATA, out, parquet=True)
    assert pa is not None
    for k, group in enumerate(manifest["groups"]):
        table = pq.read_table(out / group["name"] / "frames.parquet")
        assert table.num_rows == group["frames"]
        clips = [i for i, c in enumerate(manifest["clips"]) if c["group"] == k]
        assert sorted(set(table["clip"].to_pylist())) == clips
        for name in bvhview.dataset.ARRAYS:
            array = np.load(out / group["name"] / f"{name}.npy")
            if array[0].size == 0:
                assert name not in table.column_names
                continue
            column = np.stack(table[name].to_numpy(zero_copy_only=False))
            np.testing.assert_array_equal(column.reshape(array.shape), array)
    with pytest.raises(ValueError, match="already exists"):
        quietly(DATA, out)


def test_dask_workers_compile_pieces_that_merge_into_the_single_process_dataset(tmp_path):
    distributed = pytest.importorskip("distributed")
    pytest.importorskip("pyarrow")
    import bvhview.dask

    single = tmp_path / "single"
    quietly(DATA, single, threads=1)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        manifest = bvhview.dask.compile_dataset(DATA, tmp_path / "cluster", client=client, pieces=5)
        assert len(client.nthreads()) == 2
        # An existing dataset is refused before any piece is compiled.
        with pytest.raises(ValueError, match="already exists"):
            bvhview.dask.compile_dataset(DATA, tmp_path / "single", client=client)
    same_tree(single, tmp_path / "cluster")
    assert len(manifest["clips"]) == 59
    # Only the dataset is left: the pieces' folder is gone.
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cluster", "single"]


def peer_positions(folder: Path, name: str, target_fps, scratch: Path):
    """pybvh-ml's world positions of every point (frames × points × 3, the file's units and
    axes) for one file, and its point names with End Sites named as ours; None when pybvh does
    not load the file. pybvh-ml packs one skeleton per dataset, so it gets one file at a time."""
    import glob
    import warnings

    import pybvh_ml

    out = scratch / f"{name}.{target_fps}.npz"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            pybvh_ml.preprocess_directory(
                folder, out, file_pattern=glob.escape(name), representation="euler",
                center_root=False, include_positions=True, position_space="node",
                position_centering="world", skip_errors=False, target_fps=target_fps,
            )
        except Exception:  # noqa: BLE001 - pybvh refuses the file: not compared
            return None
        data = pybvh_ml.load_preprocessed(out)
    info = data["skeleton_info"]
    nodes = list(info["node_names"])
    parents = [-1] * len(nodes)
    for child, parent in info["node_edges"]:
        parents[child] = parent
    ends = set(info["end_site_indices"] or [])
    names = [f"{nodes[parents[i]]}_End" if i in ends else n for i, n in enumerate(nodes)]
    return data["clips"][0]["node_pos"].astype(np.float64), names


def compare_with_pybvh_ml(folder: Path, scratch: Path) -> list[str]:
    """Every BVH file of `folder` both load: our dataset's positions, turned back to the file's
    units and axes, against pybvh-ml's at the file's own rate (within 1e-5 of the figure's
    height), and the frame counts both make at 30 fps. Returns the files compared."""
    pytest.importorskip("pybvh_ml")
    names = sorted(p.name for p in folder.glob("*.bvh"))
    at_30 = quietly(folder, scratch / "ours30", takes=[(n, None) for n in names])
    ours_30 = {c["path"]: c for c in at_30["clips"]}
    compared = []
    for name in names:
        if name not in ours_30:
            continue
        own_fps = 1.0 / ours_30[name]["source_frame_time"]
        theirs = peer_positions(folder, name, None, scratch)
        if theirs is None:
            continue
        peer, peer_names = theirs
        out = scratch / f"ours_{name}"
        manifest = quietly(folder, out, fps=own_fps, takes=[(name, None)])
        clip = manifest["clips"][0]
        assert manifest["groups"][0]["joints"] == peer_names, name
        ours = clip_rows(out, manifest, clip, "positions").astype(np.float64) / clip["metres_per_unit"]
        if clip["up"] == "z":  # stored as (x, z, -y)
            ours = np.stack([ours[..., 0], -ours[..., 2], ours[..., 1]], axis=-1)
        assert ours.shape == peer.shape, name
        height = float(np.ptp(peer[0], axis=0).max())
        assert np.abs(ours - peer).max() <= 1e-5 * height, name
        peer_30 = peer_positions(folder, name, 30.0, scratch)
        assert peer_30 is not None
        assert ours_30[name]["frames"] == peer_30[0].shape[0], name
        compared.append(name)
    return compared


def test_positions_and_frame_counts_agree_with_pybvh_ml_on_the_repository(tmp_path):
    compared = compare_with_pybvh_ml(DATA / "bvh", tmp_path)
    # pybvh refuses two of the 17 files (rows past Frames:, position channels on a joint).
    assert len(compared) == 15, compared


def test_positions_and_frame_counts_agree_with_pybvh_ml_on_the_whole_corpus(tmp_path):
    from conftest import whole_corpus_or_skip

    compared = compare_with_pybvh_ml(whole_corpus_or_skip() / "bvh", tmp_path)
    # pybvh refuses 6 of the 27: rows past Frames:, a hierarchy opened by JOINT, position
    # channels on a joint (Bandai's, MakeHuman's T-pose); its own Z-up test take agrees.
    assert len(compared) == 21, compared
    assert "pybvh_bvh_test1.bvh" in compared


def test_datasets_pickle_as_memory_maps_and_refuse_odd_windows(compiled):
    import pickle

    manifest = json.loads((compiled / "manifest.json").read_text())
    # The group whose positions are largest (frames × joints).
    groups = manifest["groups"]
    group = max(range(len(groups)), key=lambda k: groups[k]["frames"] * len(groups[k]["joints"]))
    data = bvhview.Dataset(compiled, window=8, group=group)
    blob = pickle.dumps(data)
    # A spawned DataLoader worker gets the paths and windows, and maps the files itself.
    assert len(blob) < 50_000 < data.arrays["positions"].nbytes
    again = pickle.loads(blob)
    assert isinstance(again.arrays["positions"].base, mmap.mmap)
    np.testing.assert_array_equal(again[3]["positions"], data[3]["positions"])
    for bad in (dict(window=True), dict(window=0), dict(stride=2), dict(window=4, stride=0)):
        with pytest.raises(ValueError):
            bvhview.Dataset(compiled, group=group, **bad)
    # Padded shards are all as long, as DistributedSampler's.
    shards = [data.shard(rank, 3, pad=True) for rank in range(3)]
    assert len({len(s) for s in shards}) == 1 and 3 * len(shards[0]) >= len(data)


def test_nothing_to_compile_is_refused_with_every_reason_and_pieces_must_be_whole(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(ValueError, match=r"no takes \(.bvh, .asf, .amc, .fbx, .gltf, .glb or .npz files\)"):
        bvhview.compile_dataset(empty, tmp_path / "a")
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "x.bvh").write_text("HIERARCHY\nROOT")
    (broken / "y.bvh").write_text("HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Xrotation\n}\nMOTION\nFrames: 1\nFrame Time: 0\n0\n")
    with pytest.raises(ValueError, match="no take could be compiled") as raised:
        bvhview.compile_dataset(broken, tmp_path / "b")
    assert "x.bvh:2:5" in str(raised.value) and "y.bvh: Frame Time 0" in str(raised.value)
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()
    # Skipped takes are warned about, one warning each, and listed in the manifest.
    shutil.copyfile(DATA / "bvh" / "bvh11_131_01.bvh", broken / "z.bvh")
    with pytest.warns(bvhview.SkippedTake) as caught:
        manifest = bvhview.compile_dataset(broken, tmp_path / "c")
    assert len(caught) == 2 and len(manifest["skipped"]) == 2
    takes = bvhview.list_takes(DATA)
    first = quietly(DATA, tmp_path / "p0", takes=takes[:5])
    second = quietly(DATA, tmp_path / "p1", takes=takes[5:])
    assert len(first["clips"]) + len(second["clips"]) == 59
    # Lists of takes of their own are two compiles: joined as folders, not as pieces.
    with pytest.raises(ValueError, match="another compile"):
        bvhview.merge_datasets([tmp_path / "p0", tmp_path / "p1"], tmp_path / "m")
    assert not (tmp_path / "m").exists()
    joined = bvhview.merge_datasets([tmp_path / "p0", tmp_path / "p1"], tmp_path / "m", join="folders")
    assert len(joined["clips"]) == 59
    # Pieces of one compile: a gap or a piece given twice is refused.
    from bvhview._bvhview import _compile_dataset

    for k in range(3):
        _compile_dataset(str(DATA), str(tmp_path / f"q{k}"), piece=(k, 3))
    with pytest.raises(ValueError, match="in no piece given"):
        bvhview.merge_datasets([tmp_path / "q0", tmp_path / "q2"], tmp_path / "gap")
    with pytest.raises(ValueError, match="the rest of the list is missing"):
        bvhview.merge_datasets([tmp_path / "q0", tmp_path / "q1"], tmp_path / "short")
    with pytest.raises(ValueError, match="an earlier piece holds"):
        bvhview.merge_datasets([tmp_path / "q0", tmp_path / "q0"], tmp_path / "twice")
    whole = bvhview.merge_datasets([tmp_path / f"q{k}" for k in range(3)], tmp_path / "whole")
    assert len(whole["clips"]) == 59
    assert not any((tmp_path / n).exists() for n in ("gap", "short", "twice"))


def test_statistics_feet_and_floor(compiled, tmp_path):
    manifest = json.loads((compiled / "manifest.json").read_text())
    group = next(k for k, g in enumerate(manifest["groups"]) if g["clips"] == 3)
    data = bvhview.Dataset(compiled, group=group)
    for name in ("positions", "rotations", "velocities"):
        mean, std = data.stats(name)
        every = np.load(compiled / data.group["name"] / f"{name}.npy").astype(np.float64)
        np.testing.assert_allclose(mean, every.mean(axis=0), rtol=1e-5, atol=1e-6)
        np.testing.assert_allclose(std, every.std(axis=0), rtol=1e-4, atol=1e-6)
    with pytest.raises(ValueError, match="statistics are kept for"):
        data.stats("foot_contacts")
    # Feet named by the user; a name the skeleton lacks skips the take with the reason.
    named = quietly(DATA / "bvh", tmp_path / "named", feet=["LeftToeBase_End", "RightToeBase_End"])
    cmu = next(c for c in named["clips"] if c["path"] == "assimp_01_01.bvh")
    group = named["groups"][cmu["group"]]
    assert [group["joints"][i] for i in group["feet"]] == ["LeftToeBase_End", "RightToeBase_End"]
    assert any(": feet names " in s["error"] for s in named["skipped"])


def hostile_cases(good: Path, outside: Path):
    """(name, how the copy of `good` is changed): every way a downloaded dataset was found to
    mislead the reader, and more of the same kind."""
    import shutil

    def manifest_edit(change):
        def apply(ds: Path) -> None:
            manifest = json.loads((ds / "manifest.json").read_text())
            change(manifest)
            (ds / "manifest.json").write_text(json.dumps(manifest))

        return apply

    def replace_with_link(relative: str, target: Path):
        def apply(ds: Path) -> None:
            path = ds / relative
            if path.is_dir():
                shutil.rmtree(path)
            else:
                path.unlink()
            path.symlink_to(target)

        return apply

    def npy_edit(name: str, change):
        def apply(ds: Path) -> None:
            path = ds / "group_0" / name
            path.write_bytes(change(path.read_bytes()))

        return apply

    def offsets(values):
        def change(data: bytes) -> bytes:
            header = data[:128]
            return header + np.array(values, dtype="<i8").tobytes()

        return change

    def fifo(ds: Path) -> None:
        (ds / "manifest.json").unlink()
        os.mkfifo(ds / "manifest.json")

    def as_float64(data: bytes) -> bytes:
        array = np.load(__import__("io").BytesIO(data))
        buffer = __import__("io").BytesIO()
        np.save(buffer, array.astype(np.float64))
        return buffer.getvalue()

    def set_clip(field, value):
        def change(manifest):
            manifest["clips"][1][field] = value

        return change

    return [
        ("group named /abs", manifest_edit(lambda m: m["groups"][0].update(name=str(outside)))),
        ("group named ../", manifest_edit(lambda m: m["groups"][0].update(name="../secret"))),
        ("array file elsewhere", manifest_edit(lambda m: m["groups"][0]["arrays"][0].update(file="../x.npy"))),
        ("group folder linked out", replace_with_link("group_0", outside)),
        ("positions linked out", replace_with_link("group_0/positions.npy", outside / "positions.npy")),
        ("manifest linked to /dev/zero", replace_with_link("manifest.json", Path("/dev/zero"))),
        ("manifest a FIFO", fifo),
        ("offsets past the arrays", npy_edit("offsets.npy", offsets([0, 10**12]))),
        ("offsets negative", npy_edit("offsets.npy", offsets([-5, 5]))),
        ("three arrays listed", manifest_edit(lambda m: m["groups"][0].update(arrays=m["groups"][0]["arrays"][:3]))),
        ("a clip starting at 2**63", manifest_edit(set_clip("start", 2**63))),
        ("a clip starting at 0 again", manifest_edit(set_clip("start", 0))),
        ("a clip of group 7", manifest_edit(set_clip("group", 7))),
        ("more frames than the arrays", manifest_edit(lambda m: m["groups"][0].update(frames=m["groups"][0]["frames"] + 1))),
        ("positions as float64", npy_edit("positions.npy", as_float64)),
        ("positions cut short", npy_edit("positions.npy", lambda b: b[:-4])),
        ("a header of another shape", npy_edit("velocities.npy", lambda b: b.replace(b"'shape': (", b"'shape': (1, ", 1)[:128] + b[128:])),
        ("a parent after its child", manifest_edit(lambda m: m["groups"][0]["parents"].__setitem__(1, 5))),
        ("feet out of range", manifest_edit(lambda m: m["groups"][0].update(feet=[10**6]))),
        ("another format", manifest_edit(lambda m: m.update(format="bvhview-dataset 9"))),
        ("fps of 1e7", manifest_edit(lambda m: m["options"].update(fps=1e7))),
        ("skeleton.bvh linked out", replace_with_link("group_0/skeleton.bvh", outside / "skeleton.bvh")),
        ("manifest not JSON", lambda ds: (ds / "manifest.json").write_text("{\"format\": ")),
    ]


def test_a_dataset_folder_is_untrusted_input(tmp_path):
    """Each mutation of a good dataset is refused with a ValueError (or OSError for what cannot
    be opened) by Dataset, merge_datasets and write_parquet, quickly, reading nothing outside
    the folder and writing nothing anywhere."""
    import shutil
    import time

    source = tmp_path / "one"
    source.mkdir()
    (source / "walk.bvh").write_bytes((DATA / "bvh" / "assimp_01_01.bvh").read_bytes())
    (source / "walk_again.bvh").write_bytes((DATA / "bvh" / "assimp_01_01.bvh").read_bytes())
    good = tmp_path / "good"
    quietly(source, good)
    outside = tmp_path / "outside"
    shutil.copytree(good / "group_0", outside)
    before = sorted(p.stat().st_mtime_ns for p in outside.iterdir())
    assert len(bvhview.Dataset(good)) == 2
    for name, apply in hostile_cases(good, outside):
        ds = tmp_path / f"case_{name.replace('/', '_').replace(' ', '_')}"
        shutil.copytree(good, ds, symlinks=True)
        apply(ds)
        started = time.monotonic()
        for attempt in (
            lambda: bvhview.Dataset(ds),
            lambda: bvhview.merge_datasets([ds], tmp_path / "merged"),
            lambda: bvhview.write_parquet(ds),
        ):
            with pytest.raises((ValueError, OSError)) as raised:
                attempt()
            assert not isinstance(raised.value, bvhview.ParseError) or "manifest.json" in str(raised.value), name
        assert time.monotonic() - started < 10, name
        assert not (tmp_path / "merged").exists(), name
        assert not list(ds.rglob("*.parquet")), name
    assert sorted(p.stat().st_mtime_ns for p in outside.iterdir()) == before
    assert not list(outside.glob("*.parquet"))


@pytest.mark.parametrize(
    "entry",
    ["_open_dataset", "_merge_datasets", "_compile_dataset", "_dataset_motion", "load", "load_many", "positions",
     "mirror", "from_arrays", "__reduce__", "_from_state", "list_takes"],
)
def test_a_panic_inside_becomes_a_runtime_error(tmp_path, entry):
    """A Rust panic (a bug) reaches Python as a RuntimeError, which `except Exception` catches,
    never as pyo3's PanicException (a BaseException)."""
    good = tmp_path / "good"
    quietly(DATA / "asf_amc", good)
    calls = {
        "_open_dataset": lambda: bvhview.Dataset(good),
        "_merge_datasets": lambda: bvhview.merge_datasets([good], tmp_path / "m"),
        "_compile_dataset": lambda: quietly(DATA / "asf_amc", tmp_path / "c"),
        "_dataset_motion": lambda: None,
    }
    data = bvhview.Dataset(good)
    item = data[0]
    calls["_dataset_motion"] = lambda: data.to_motion(item["rotations"], item["translations"])
    take = bvhview.load(DATA / "bvh" / "assimp_01_01.bvh")
    import pickle

    blob = pickle.dumps(take)
    calls.update(
        load=lambda: bvhview.load(DATA / "bvh" / "assimp_01_01.bvh"),
        load_many=lambda: bvhview.load_many([DATA / "bvh" / "assimp_01_01.bvh"]),
        positions=lambda: take.positions(0),
        mirror=lambda: take.mirror(),
        from_arrays=lambda: bvhview.Motion.from_arrays(take, take.local_rotations()),
        __reduce__=lambda: pickle.dumps(take),
        _from_state=lambda: pickle.loads(blob),
        list_takes=lambda: bvhview.list_takes(DATA / "asf_amc"),
    )
    os.environ["BVHVIEW_PLANT_PANIC"] = entry
    try:
        with pytest.raises(RuntimeError, match=f"internal error in bvhview \\({entry}\\)"):
            try:
                calls[entry]()
            except Exception:
                raise
    finally:
        del os.environ["BVHVIEW_PLANT_PANIC"]
    assert not (tmp_path / "m").exists() and not (tmp_path / "c").exists()


def test_humanml3d_features_compile_in_its_layout_and_on_a_dask_cluster(tmp_path):
    """compile_dataset(features="humanml3d") as `bvhview dataset --features humanml3d`: HumanML3D's
    layout, each take's vectors those bvhview.humanml3d_features makes of the positions of the
    arrays compile (onto smpl22, 20 fps), Mean/Std as HumanML3D's cal_mean_variance computes
    them; on a Dask cluster, pieces merge into the same files."""
    folder = tmp_path / "takes"
    folder.mkdir()
    for name in ["bvhparser_walk_01.bvh", "bvh11_131_01.bvh", "opencollar_run.bvh"]:
        shutil.copy(DATA / "bvh" / name, folder / name)
    out = tmp_path / "h3"
    manifest = quietly(folder, out, onto="smpl22", features="humanml3d")
    assert manifest["options"]["features"] == "humanml3d" and manifest["options"]["fps"] == 20
    ids = (out / "all.txt").read_text().split()
    assert ids == [clip["id"] for clip in manifest["clips"]] == ["000000", "000001", "000002"]
    arrays = tmp_path / "arrays"
    quietly(folder, arrays, onto="smpl22", fps=20)
    dataset = bvhview.Dataset(arrays)
    names = dataset.manifest["groups"][0]["joints"]
    order = [names.index(n) for n in SMPL22_ORDER]
    everything = []
    for k, clip_id in enumerate(ids):
        vectors = np.load(out / "new_joint_vecs" / f"{clip_id}.npy")
        joints = np.load(out / "new_joints" / f"{clip_id}.npy")
        expected, expected_joints = bvhview.humanml3d_features(dataset[k]["positions"][:, order])
        # Within float32 rounding: the compile picks the frames before retargeting them.
        np.testing.assert_allclose(vectors, expected, atol=1e-5)
        np.testing.assert_allclose(joints, expected_joints, atol=1e-5)
        everything.append(vectors)
    # HumanML3D's cal_mean_variance: numpy's mean and std, the std then one number per part.
    data = np.concatenate(everything).astype(np.float64)
    std = data.std(axis=0)
    for start, end in [(0, 1), (1, 3), (3, 4), (4, 67), (67, 193), (193, 259), (259, 263)]:
        std[start:end] = std[start:end].mean()
    np.testing.assert_allclose(np.load(out / "Mean.npy"), data.mean(axis=0), atol=1e-6)
    np.testing.assert_allclose(np.load(out / "Std.npy"), std, atol=1e-6)
    # The arrays' reader says what the folder is; a dataset of vectors has no Parquet rows.
    with pytest.raises(ValueError, match="HumanML3D's layout"):
        bvhview.Dataset(out)
    with pytest.raises(ValueError, match="parquet"):
        quietly(folder, tmp_path / "pq", onto="smpl22", features="humanml3d", parquet=True)
    with pytest.raises(ValueError, match="20 fps"):
        quietly(folder, tmp_path / "fps", onto="smpl22", features="humanml3d", fps=30)

    distributed = pytest.importorskip("distributed")
    from bvhview.dask import compile_dataset as compile_on_cluster

    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        compile_on_cluster(
            folder, tmp_path / "cluster", client=client, pieces=2, onto="smpl22",
            features="humanml3d",
        )
    same_tree(out, tmp_path / "cluster")


def test_humanml3d_features_of_its_own_positions_are_its_published_vectors():
    """bvhview.humanml3d_features on HumanML3D's processed positions (tests/humanml3d) gives its
    published vectors, but for the last frames: its last frame is not published, and the
    facing is smoothed over 80 frames (tests/dataset/humanml3d_features.rs rebuilds it and checks every one)."""
    root = DATA.parent / "humanml3d"
    joints = np.load(root / "new_joints_012314.npy")
    published = np.load(root / "new_joint_vecs_012314.npy")
    vectors, positions = bvhview.humanml3d_features(joints)
    assert vectors.shape == (169, 263) and positions.shape == (169, 22, 3)
    np.testing.assert_allclose(vectors[:80], published[:80], atol=1e-5)
    np.testing.assert_allclose(positions[:80], joints[:80], atol=1e-5)
    with pytest.raises(ValueError, match="22"):
        bvhview.humanml3d_features(joints[:, :21])
    with pytest.raises(ValueError, match="one frame"):
        bvhview.humanml3d_features(joints[:1])


def test_datasets_compiled_with_a_map_merge(tmp_path):
    """A dataset compiled onto a skeleton with names= merges (the merge once checked its options
    again without the skeleton, and refused the map)."""
    folder = tmp_path / "takes"
    folder.mkdir()
    shutil.copy(DATA / "bvh" / "bvhparser_walk_01.bvh", folder)
    one = tmp_path / "one"
    quietly(folder, one, onto="smpl22", names={"Head": "head"})
    merged = bvhview.merge_datasets([one, one], tmp_path / "two", join="folders")
    assert len(merged["clips"]) == 2
    assert merged["options"]["map"]["all"] == [["Head", "head"]]


def test_out_units_write_every_length_in_them(tmp_path, compiled):
    """compile_dataset(out_units="cm") as `dataset --out-units cm`: every length in centimetres,
    the rest as in metres, the units in the manifest; HumanML3D's metres are refused."""
    out = tmp_path / "cm"
    manifest = quietly(DATA, out, out_units="cm")
    metres = json.loads((compiled / "manifest.json").read_text())
    assert (manifest["options"]["units"], manifest["options"]["metres_per_unit"]) == (
        "centimetres",
        pytest.approx(0.01),
    )
    assert "metres_per_unit" not in metres["options"]
    for clip, before in zip(manifest["clips"], metres["clips"]):
        for array in ["positions", "velocities", "root_translations"]:
            np.testing.assert_allclose(
                clip_rows(out, manifest, clip, array),
                clip_rows(compiled, metres, before, array) * np.float32(100),
                rtol=1e-6,
                atol=1e-6,
            )
        for array in ["rotations", "foot_contacts"]:
            np.testing.assert_array_equal(
                clip_rows(out, manifest, clip, array), clip_rows(compiled, metres, before, array)
            )
    dataset = bvhview.Dataset(out, group=0)
    first = [c for c in manifest["clips"] if c["group"] == 0]
    assert len(dataset) == len(first)
    np.testing.assert_array_equal(dataset[0]["positions"], clip_rows(out, manifest, first[0], "positions"))
    with pytest.raises(ValueError, match="HumanML3D's vectors are in metres"):
        quietly(DATA, tmp_path / "h", out_units="cm", features="humanml3d", onto="smpl22")
