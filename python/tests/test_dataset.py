"""compile_dataset, Dataset, Parquet and the Dask helper, on the repository's takes: against the
CLI's `bvhview dataset`, against forward kinematics done here in numpy, and pieces on a Dask
cluster against one process."""

import filecmp
import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import bvhview
from conftest import DATA


@pytest.fixture(scope="module")
def compiled(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("compiled") / "ds"
    bvhview.compile_dataset(DATA, out, parquet=False)
    return out


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
    assert manifest["format"] == "bvhview-dataset 1"
    assert manifest["options"] == {
        "fps": 30.0,
        "rotations": "6d",
        "root_relative": False,
        "contact_height_m": 0.05,
        "contact_speed_m_per_s": 0.5,
        "up": "y",
        "units": "metres",
    }
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


@pytest.mark.parametrize("kind", ["quat", "matrix", "6d", "euler"])
def test_rotations_rebuild_the_positions_by_forward_kinematics_in_numpy(tmp_path, kind):
    """The stored local rotations, with the take's offsets in metres and Y up and the root
    translations, give the stored positions again through FK written here (no bvhview code),
    within 1e-5 of the figure's height, for every clip of the repository whose only position
    channels are the root's."""
    out = tmp_path / kind
    manifest = bvhview.compile_dataset(DATA, out, rotations=kind, parquet=False)
    checked = 0
    for clip in manifest["clips"]:
        group = manifest["groups"][clip["group"]]
        source = DATA / clip["path"]
        take = bvhview.load(source, DATA / clip["motion"] if clip["motion"] else None)
        channels = take.channels
        if any(any(c.endswith("position") for c in channels[j]) for j in range(1, len(channels))):
            continue
        if take.offset_mode != "replace" or clip["offset_mode"] != "replace":
            continue
        # An ASF bone's Euler angles are its AMC values, about the bone's own axes (C · R · C⁻¹):
        # the other kinds hold the whole local rotation.
        if kind == "euler" and clip["motion"]:
            continue
        # The clip's own OFFSETs in metres, Y up, as the dataset keeps them.
        index = [c for c in manifest["clips"] if c["group"] == clip["group"]].index(clip)
        offsets = np.load(out / group["name"] / "rest_offsets.npy")[index]
        parents = np.array(group["parents"])
        rotations = clip_rows(out, manifest, clip, "rotations")
        roots = clip_rows(out, manifest, clip, "root_translations")
        positions = clip_rows(out, manifest, clip, "positions")
        frames = clip["frames"]
        matrices = np.tile(np.eye(3, dtype=np.float64), (frames, len(parents), 1, 1))
        if kind == "quat":
            w, x, y, z = np.moveaxis(rotations.astype(np.float64), -1, 0)
            m = np.stack(
                [
                    1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                    2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                    2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y),
                ],
                axis=-1,
            ).reshape(frames, -1, 3, 3)
        elif kind == "matrix":
            m = rotations.astype(np.float64)
        elif kind == "6d":
            a, b = rotations[..., :3].astype(np.float64), rotations[..., 3:].astype(np.float64)
            m = np.stack([a, b, np.cross(a, b)], axis=-1)
        else:
            # Each joint's rotation channels in its file order, degrees: R = R1 · R2 · R3.
            m = np.tile(np.eye(3), (frames, len(group["rotated"]), 1, 1))
            for slot, joint in enumerate(group["rotated"]):
                axes = group["rotation_orders"][slot]
                assert axes == "".join(c[0] for c in channels[joint] if c.endswith("rotation"))
                for k, axis in enumerate(axes):
                    angle = np.radians(rotations[:, slot, k].astype(np.float64))
                    c, s = np.cos(angle), np.sin(angle)
                    r = np.tile(np.eye(3), (frames, 1, 1))
                    i, j = {"X": (1, 2), "Y": (2, 0), "Z": (0, 1)}[axis]
                    r[:, i, i], r[:, i, j], r[:, j, i], r[:, j, j] = c, -s, s, c
                    m[:, slot] = m[:, slot] @ r
        matrices[:, group["rotated"]] = m
        world_r = np.zeros_like(matrices)
        world_t = np.zeros((frames, len(parents), 3))
        for j, parent in enumerate(parents):
            if parent < 0:
                world_r[:, j], world_t[:, j] = matrices[:, j], roots
            else:
                world_r[:, j] = world_r[:, parent] @ matrices[:, j]
                world_t[:, j] = world_t[:, parent] + np.einsum("fij,j->fi", world_r[:, parent], offsets[j])
        height = np.ptp(positions[..., 1], axis=1).max()
        assert np.abs(world_t - positions).max() <= 1e-5 * height, clip["path"]
        checked += 1
    assert checked >= 12


def test_windows_strides_shards_and_groups(compiled):
    manifest = json.loads((compiled / "manifest.json").read_text())
    with pytest.raises(ValueError, match="17 skeleton topologies.*choose one with group="):
        bvhview.Dataset(compiled, window=8)
    group = next(k for k, g in enumerate(manifest["groups"]) if g["clips"] == 3)
    data = bvhview.Dataset(compiled, window=2, stride=1, group=group)
    clips = [c for c in manifest["clips"] if c["group"] == group]
    assert len(data) == sum(max(0, c["frames"] - 2 + 1) for c in clips)
    item = data[0]
    assert set(item) == {"positions", "rotations", "root_translations", "velocities", "foot_contacts", "clip", "start"}
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
    manifest = bvhview.compile_dataset(DATA, out)
    assert pa is not None
    for k, group in enumerate(manifest["groups"]):
        table = pq.read_table(out / group["name"] / "frames.parquet")
        assert table.num_rows == group["frames"]
        clips = [i for i, c in enumerate(manifest["clips"]) if c["group"] == k]
        assert sorted(set(table["clip"].to_pylist())) == clips
        for name in ("positions", "rotations", "velocities", "root_translations", "foot_contacts"):
            array = np.load(out / group["name"] / f"{name}.npy")
            if array[0].size == 0:
                assert name not in table.column_names
                continue
            column = np.stack(table[name].to_numpy(zero_copy_only=False))
            np.testing.assert_array_equal(column.reshape(array.shape), array)
    with pytest.raises(ValueError, match="already exists"):
        bvhview.compile_dataset(DATA, out)


def test_dask_workers_compile_pieces_that_merge_into_the_single_process_dataset(tmp_path):
    distributed = pytest.importorskip("distributed")
    pytest.importorskip("pyarrow")
    import bvhview.dask

    single = tmp_path / "single"
    bvhview.compile_dataset(DATA, single, threads=1)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        manifest = bvhview.dask.compile_dataset(DATA, tmp_path / "cluster", client=client, pieces=5)
        assert len(client.nthreads()) == 2
        # An existing dataset is refused before any piece is compiled.
        with pytest.raises(ValueError, match="already exists"):
            bvhview.dask.compile_dataset(DATA, tmp_path / "single", client=client)
    same_tree(single, tmp_path / "cluster")
    assert len(manifest["clips"]) == 20
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
    at_30 = bvhview.compile_dataset(folder, scratch / "ours30", takes=[(n, None) for n in names], parquet=False)
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
        manifest = bvhview.compile_dataset(folder, out, fps=own_fps, takes=[(name, None)], parquet=False)
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
    # pybvh refuses 6 of the 26: rows past Frames:, a hierarchy opened by JOINT, position
    # channels on a joint (Bandai's, MakeHuman's T-pose).
    assert len(compared) == 20, compared


def test_datasets_pickle_as_memory_maps_and_refuse_odd_windows(compiled):
    import pickle

    manifest = json.loads((compiled / "manifest.json").read_text())
    group = max(range(len(manifest["groups"])), key=lambda k: manifest["groups"][k]["frames"])
    data = bvhview.Dataset(compiled, window=8, group=group)
    blob = pickle.dumps(data)
    # A spawned DataLoader worker gets the paths and windows, and maps the files itself.
    assert len(blob) < 50_000 < data.arrays["positions"].nbytes
    again = pickle.loads(blob)
    assert isinstance(again.arrays["positions"], np.memmap)
    np.testing.assert_array_equal(again[3]["positions"], data[3]["positions"])
    for bad in (dict(window=True), dict(window=0), dict(stride=2), dict(window=4, stride=0)):
        with pytest.raises(ValueError):
            bvhview.Dataset(compiled, group=group, **bad)
    # Padded shards are all as long, as DistributedSampler's.
    shards = [data.shard(rank, 3, pad=True) for rank in range(3)]
    assert len({len(s) for s in shards}) == 1 and 3 * len(shards[0]) >= len(data)


def test_nothing_to_compile_and_pieces_out_of_order_are_refused(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    with pytest.raises(ValueError, match="no .bvh, .asf or .amc files"):
        bvhview.compile_dataset(empty, tmp_path / "a")
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "x.bvh").write_text("HIERARCHY\nROOT")
    with pytest.raises(ValueError, match="no take could be compiled"):
        bvhview.compile_dataset(broken, tmp_path / "b")
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()
    takes = bvhview.list_takes(DATA)
    first = bvhview.compile_dataset(DATA, tmp_path / "p0", takes=takes[:5], parquet=False)
    second = bvhview.compile_dataset(DATA, tmp_path / "p1", takes=takes[5:], parquet=False)
    assert len(first["clips"]) + len(second["clips"]) == 20
    with pytest.raises(ValueError, match="comes after"):
        bvhview.merge_datasets([tmp_path / "p1", tmp_path / "p0"], tmp_path / "m")
    assert not (tmp_path / "m").exists()
