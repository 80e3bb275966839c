"""The Python package against the Rust CLI and against plain Python, on the repository's real files."""

import contextlib
import re
import subprocess
import threading

import numpy as np
import pytest

import bvhview
from conftest import (
    DATA,
    EDGE,
    REPO,
    CliFailed,
    cli_positions,
    files,
    plain_bvh_rows,
    whole_corpus_or_skip,
)

BVH_FILES = files(DATA / "bvh", ".bvh")
ASF = DATA / "asf_amc" / "heiden_12.asf"
AMC = DATA / "asf_amc" / "heiden_12_02_01.amc"


def ids(paths):
    return [p.name for p in paths]


def assert_same_positions(take: bvhview.Motion, names: list[str], expected: np.ndarray) -> None:
    """The CLI prints each float in its shortest round-trip form, so its points read back to the
    very floats the library computed: equal, not merely close."""
    assert take.point_names == names
    got = take.positions()[:, take.point_joints]
    assert got.shape == expected.shape
    np.testing.assert_array_equal(got, expected)


# Positions: the same floats as the CLI's export.


@pytest.mark.parametrize("path", BVH_FILES, ids=ids(BVH_FILES))
def test_positions_equal_the_cli_on_every_repository_file(cli, path):
    names, expected = cli_positions(cli, path)
    take = bvhview.load(path)
    assert_same_positions(take, names, expected)
    # BVH points are every joint in order, End Sites named <parent>_End.
    assert list(take.point_joints) == list(range(len(take.joint_names)))
    for index in np.flatnonzero(take.end_sites):
        parent = take.joint_names[take.parents[index]]
        assert take.point_names[index] == f"{parent}_End"


def test_positions_equal_the_cli_on_the_asf_amc_pair(cli):
    names, expected = cli_positions(cli, ASF, "--motion", str(AMC))
    take = bvhview.load(ASF, motion=AMC)
    assert take.frame_count == expected.shape[0] > 0
    assert take.frame_time == pytest.approx(1 / 120)
    assert take.motion_path == str(AMC)
    assert_same_positions(take, names, expected)


@pytest.mark.parametrize(
    "path",
    [EDGE / "position_channels_non_root.bvh", DATA / "bvh" / "makehuman_walk1.bvh"],
    ids=lambda p: p.name,
)
def test_offset_mode_add_equals_the_cli(cli, path):
    names, expected = cli_positions(cli, path, "--offset-mode", "add")
    added = bvhview.load(path, offset_mode="add")
    assert added.offset_mode == "add"
    assert_same_positions(added, names, expected)
    replaced = bvhview.load(path)
    assert not np.array_equal(added.positions(), replaced.positions())


def test_a_file_without_frames_gives_its_rest_pose(cli):
    path = EDGE / "no_motion.bvh"
    take = bvhview.load(path)
    assert take.frame_count == 0 == len(take)
    assert take.values.shape == (0, take.channel_count)
    names, expected = cli_positions(cli, path)
    assert_same_positions(take, names, expected)
    assert take.positions().shape == (1, len(take.joint_names), 3)
    # The rest pose is the sum of OFFSETs down the tree.
    rest = np.zeros((len(take.parents), 3), dtype=np.float32)
    for joint, parent in enumerate(take.parents):
        rest[joint] = take.offsets[joint] + (rest[parent] if parent >= 0 else 0)
    np.testing.assert_allclose(take.positions()[0], rest, rtol=0, atol=1e-4)


def test_whole_corpus_positions_equal_the_cli_or_fail_alike(cli):
    shared = whole_corpus_or_skip()
    items = [(path, None) for path in files(shared / "bvh", ".bvh")]
    asf_amc = shared / "asf_amc"
    for amc in files(asf_amc, ".amc"):
        skeleton = max(
            (asf for asf in files(asf_amc, ".asf") if amc.stem.startswith(asf.stem)),
            key=lambda asf: len(asf.stem),
        )
        items.append((skeleton, amc))
    for path, motion in items:
        extra = ["--motion", str(motion)] if motion else []
        try:
            names, expected = cli_positions(cli, path, *extra)
        except CliFailed as failure:
            with pytest.raises(bvhview.ParseError) as raised:
                bvhview.load(path, motion=motion)
            assert str(raised.value) == str(failure), path
            continue
        assert_same_positions(bvhview.load(path, motion=motion), names, expected)


# Values: the MOTION rows as plain Python reads them.


@pytest.mark.parametrize(
    "path",
    [
        EDGE / "article_base_crlf.bvh",  # CRLF
        DATA / "bvh" / "bvhanim_test_simple.bvh",
        DATA / "bvh" / "opencollar_run.bvh",  # lone CR line ends
        DATA / "bvh" / "opencollar_oc_stand_boy01.bvh",  # rows beyond Frames
        EDGE / "short_numbers.bvh",
    ]
    + BVH_FILES,
    ids=lambda p: p.name,
)
def test_values_equal_a_plain_python_parse_of_the_rows(path):
    frames, frame_time, rows = plain_bvh_rows(path)
    take = bvhview.load(path)
    assert take.frame_count == frames
    assert take.frame_time == frame_time
    # float() is the correctly rounded double; float32 then rounds it as the article's
    # (float)atof does.
    expected = np.array(rows, dtype=np.float64).astype(np.float32).reshape(frames, -1)
    assert take.values.dtype == np.float32
    np.testing.assert_array_equal(take.values, expected)
    assert sum(len(c) for c in take.channels) == take.channel_count == expected.shape[1]


def test_values_are_a_read_only_view_not_a_copy():
    take = bvhview.load(DATA / "bvh" / "assimp_01_01.bvh")
    first, second = take.values, take.values
    assert np.shares_memory(first, second)
    assert first.base is take
    assert not first.flags.writeable
    with pytest.raises(ValueError):
        first[0, 0] = 1.0
    with pytest.raises(ValueError):
        first.flags.writeable = True
    # The view keeps the take alive.
    values = bvhview.load(DATA / "bvh" / "bvhanim_test_simple.bvh").values
    assert values.shape == (2, 9) and values[1, 8] == values[1, 8]


# The skeleton's description.


def test_skeleton_arrays_describe_the_file():
    take = bvhview.load(DATA / "bvh" / "bvhanim_test_simple.bvh")
    # End Sites named as the CLI names them (a file calls them all "Site").
    assert take.joint_names == ["Base", "End", "End_End"]
    assert take.parents.dtype == np.int32
    assert list(take.parents) == [-1, 0, 1]
    assert list(take.end_sites) == [False, False, True]
    assert take.offsets.shape == (3, 3) and take.offsets.dtype == np.float32
    assert take.channels == [
        ["Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation"],
        ["Zrotation", "Xrotation", "Yrotation"],
        [],
    ]
    assert take.rotation_orders == ["ZXY", "ZXY", None]
    assert take.warnings == []
    assert "2 frames" in repr(take)


def test_rotation_orders_match_the_cli_info(cli):
    path = DATA / "bvh" / "opencollar_oc_stand_boy01.bvh"
    info = subprocess.run([str(cli), "info", str(path)], capture_output=True, check=True).stdout.decode()
    line = next(l for l in info.splitlines() if l.startswith("rotation orders:"))
    counts = dict(
        (order, int(count)) for order, count in re.findall(r"([XYZ]{3}) ×(\d+)", line)
    )
    take = bvhview.load(path)
    orders = [o for o in take.rotation_orders if o is not None]
    assert {o: orders.count(o) for o in set(orders)} == counts
    assert len(take.warnings) == 1 and "extra rows" in take.warnings[0]


# World matrices.


@pytest.mark.parametrize(
    "path", [DATA / "bvh" / "bvh11_131_01.bvh", DATA / "bvh" / "makehuman_dance1.bvh"], ids=lambda p: p.name
)
def test_world_matrices_carry_the_positions_and_rigid_rotations(path):
    take = bvhview.load(path)
    matrices = take.world_matrices()
    positions = take.positions()
    assert matrices.shape == (take.frame_count, len(take.joint_names), 4, 4)
    assert matrices.dtype == np.float32
    size = np.ptp(positions.reshape(-1, 3), axis=0).max()
    np.testing.assert_allclose(matrices[..., :3, 3], positions, rtol=0, atol=1e-4 * size)
    np.testing.assert_array_equal(matrices[..., 3, :], np.broadcast_to([0, 0, 0, 1], matrices[..., 3, :].shape))
    rotations = matrices[..., :3, :3].astype(np.float64)
    identity = np.einsum("...ij,...kj->...ik", rotations, rotations)
    np.testing.assert_allclose(identity, np.broadcast_to(np.eye(3), identity.shape), atol=1e-4)


def test_world_matrices_of_the_asf_take_match_its_positions():
    take = bvhview.load(ASF, motion=AMC)
    np.testing.assert_allclose(
        take.world_matrices(slice(0, 50))[..., :3, 3], take.positions(slice(0, 50)), atol=1e-3
    )


# Frame selection.


def test_frames_select_like_numpy():
    take = bvhview.load(DATA / "bvh" / "bvhparser_walk_01.bvh")
    every = take.positions()
    count = take.frame_count
    for frames, expected in [
        # One int: no frame axis, as numpy's every[3] (joints x 3).
        (3, every[3]),
        (-1, every[-1]),
        (np.int64(5), every[5]),
        ([3], every[[3]]),
        (slice(10, 40, 3), every[10:40:3]),
        (slice(None, None, -7), every[::-7]),
        ([5, 0, 5], every[[5, 0, 5]]),
        (np.arange(count - 9, count), every[count - 9 :]),
        (range(2, 20, 9), every[2:20:9]),
        ([], every[:0]),
    ]:
        np.testing.assert_array_equal(take.positions(frames), expected)
        leading = expected.shape[:-2]
        assert take.world_matrices(frames).shape == (*leading, len(take.joint_names), 4, 4)
        assert take.local_matrices(frames).shape == (*leading, len(take.joint_names), 4, 4)
        assert take.root_translations(frames).shape == (*leading, 3)
        for kind, shape in [("quat", (4,)), ("matrix", (3, 3)), ("6d", (6,)), ("euler", (3,))]:
            rotations = take.local_rotations(frames, kind=kind)
            assert rotations.shape == (*leading, len(take.joint_names), *shape)
    np.testing.assert_array_equal(take.world_matrices(7), take.world_matrices()[7])
    np.testing.assert_array_equal(take.root_translations(7), take.root_translations()[7])
    np.testing.assert_array_equal(take.local_rotations(7), take.local_rotations()[7])
    for bad in [count, -count - 1, "3", [0, 1.5], 2.0]:
        with pytest.raises(ValueError):
            take.positions(bad)
        with pytest.raises(ValueError):
            take.world_matrices(bad)
    # Ranges read as a person reads them: the last frame is in.
    with pytest.raises(ValueError, match=f"the take has frames 0 to {count - 1}$"):
        take.positions(count)


# Errors: exact places, the exceptions Python users expect, never a panic.

# The expected messages are the Rust tests' own table, read from tests/formats/bvh_errors.rs.
MALFORMED = re.findall(
    r'\(\s*"([^"]+\.bvh)",\s*(?:Some\(\s*"((?:[^"\\]|\\.)*)"\s*\)|None)',
    (REPO / "tests" / "formats" / "bvh_errors.rs").read_text(),
)


def test_the_error_table_was_read():
    assert len(MALFORMED) == len(files(DATA / "bvh_malformed", ".bvh")) == 10
    assert ("dali_test-invalid-hierarchy1.bvh", "3:3: expected '{' after 'root', found 'OFFSET'") in MALFORMED


@pytest.mark.parametrize("name,expected", MALFORMED, ids=[m[0] for m in MALFORMED])
def test_malformed_files_raise_parse_error_with_line_and_column(name, expected):
    path = DATA / "bvh_malformed" / name
    if not expected:
        assert len(bvhview.load(path).joint_names) == 3
        return
    with pytest.raises(bvhview.ParseError) as raised:
        bvhview.load(path)
    error = raised.value
    line, column, message = expected.split(":", 2)
    assert isinstance(error, ValueError)
    assert str(error) == f"{path}:{expected}"
    assert error.path == str(path)
    assert (error.line, error.column) == (int(line), int(column))
    assert error.message == message.strip()


def test_dali_hierarchy1_breaks_at_line_3_column_3():
    with pytest.raises(bvhview.ParseError, match=r":3:3: expected '\{' after 'root'") as raised:
        bvhview.load(DATA / "bvh_malformed" / "dali_test-invalid-hierarchy1.bvh")
    assert (raised.value.line, raised.value.column) == (3, 3)


def test_a_malformed_amc_raises_parse_error_with_its_place(tmp_path):
    broken = tmp_path / "broken.amc"
    lines = AMC.read_text().splitlines()
    # The first data line of frame 1 gets one value too many.
    index = next(i for i, l in enumerate(lines) if l.strip() == "1") + 1
    lines[index] += " 7"
    broken.write_text("\n".join(lines) + "\n")
    with pytest.raises(bvhview.ParseError) as raised:
        bvhview.load(ASF, motion=broken)
    assert raised.value.path == str(broken)
    assert raised.value.line == index + 1
    assert raised.value.column > 1


def test_missing_files_raise_file_not_found(tmp_path):
    missing = tmp_path / "nothing.bvh"
    with pytest.raises(FileNotFoundError) as raised:
        bvhview.load(missing)
    assert raised.value.filename == str(missing)
    assert "no such file" in str(raised.value)
    with pytest.raises(FileNotFoundError):
        bvhview.load(ASF, motion=tmp_path / "nothing.amc")
    with pytest.raises(FileNotFoundError):
        bvhview.load_many([DATA / "bvh" / "bvhio_example.bvh", missing])


def test_usage_errors_raise_value_error(tmp_path):
    notes = tmp_path / "notes.txt"
    notes.write_text("hello")
    path = DATA / "bvh" / "bvhio_example.bvh"
    for call in [
        lambda: bvhview.load(path, offset_mode="sideways"),
        lambda: bvhview.load(notes),
        lambda: bvhview.load(AMC),
        lambda: bvhview.load(path, motion=AMC),
        lambda: bvhview.load(ASF, motion=path),
        lambda: bvhview.load(path, frame_time=0),
        lambda: bvhview.load_many([path], errors="ignore"),
        lambda: bvhview.load(path).save(tmp_path / "out.txt"),
    ]:
        with pytest.raises(ValueError) as raised:
            call()
        assert not isinstance(raised.value, bvhview.ParseError)
    with pytest.raises(IsADirectoryError):
        bvhview.load(tmp_path)
    with pytest.raises(TypeError):
        bvhview.load(42)


def test_an_unwritable_output_raises_os_error(tmp_path):
    take = bvhview.load(DATA / "bvh" / "bvhio_example.bvh")
    with pytest.raises(FileNotFoundError):
        take.save(tmp_path / "no" / "such" / "out.bvh")
    folder = tmp_path / "folder.bvh"
    folder.mkdir()
    with pytest.raises(IsADirectoryError):
        take.save(folder)


def test_truncated_and_flipped_bytes_raise_python_errors_only(tmp_path):
    """A sweep of damaged copies of a real file: each loads or raises ParseError, never anything
    else (a panic would surface as pyo3's PanicException, a BaseException)."""
    original = (DATA / "bvh" / "bvhparser_simple.bvh").read_bytes()
    damaged = tmp_path / "damaged.bvh"
    for cut in range(0, len(original), 37):
        for variant in (original[:cut], original[:cut] + b"{" + original[cut + 1 :]):
            damaged.write_bytes(variant)
            try:
                take = bvhview.load(damaged)
            except bvhview.ParseError as error:
                assert error.line >= 1 and error.column >= 1
            else:
                take.positions()
                take.world_matrices()


# Many files at once.


def test_load_many_loads_the_whole_folder_in_order():
    takes = bvhview.load_many(BVH_FILES)
    assert [t.path for t in takes] == [str(p) for p in BVH_FILES]
    for take, path in zip(takes, BVH_FILES):
        alone = bvhview.load(path)
        assert take.joint_names == alone.joint_names
        np.testing.assert_array_equal(take.values, alone.values)
        np.testing.assert_array_equal(take.positions(), alone.positions())


def test_load_many_takes_pairs_and_returns_errors_when_asked():
    malformed = DATA / "bvh_malformed" / "dali_test-invalid-hierarchy4.bvh"
    entries = [BVH_FILES[0], (ASF, AMC), malformed, str(BVH_FILES[1])]
    with pytest.raises(bvhview.ParseError, match=r":11:7: "):
        bvhview.load_many(entries)
    takes = bvhview.load_many(entries, errors="return", offset_mode="add")
    assert isinstance(takes[2], bvhview.ParseError) and takes[2].line == 11
    assert takes[1].motion_path == str(AMC) and takes[1].frame_count > 0
    assert all(t.offset_mode == "add" for i, t in enumerate(takes) if i != 2)
    assert bvhview.load_many([]) == []


def test_python_threads_run_while_a_take_loads(tmp_path, monkeypatch):
    """The GIL is released: while one thread is inside load(), held there by the planted pause
    (decision 14: arranged, not timed), this thread runs Python and releases it. Were the GIL
    held, nothing could release the pause and load() would fail after 60 s."""
    monkeypatch.setenv("BVHVIEW_PLANT_PAUSE", "load")
    monkeypatch.setenv("BVHVIEW_PLANT_FOLDER", str(tmp_path))
    loaded = {}

    def work():
        try:
            loaded["take"] = bvhview.load(REPO / "assets" / "walk.bvh")
        except Exception as error:  # reported by the assertion below
            loaded["error"] = error

    worker = threading.Thread(target=work)
    worker.start()
    while not (tmp_path / "paused").exists() and worker.is_alive():
        pass
    assert (tmp_path / "paused").exists(), loaded
    # The worker is inside load(), without the GIL, until this thread says so.
    (tmp_path / "release").touch()
    worker.join()
    assert "error" not in loaded, loaded
    assert loaded["take"].frame_count > 0


def _in_forked_child(check, seconds=60):
    """Runs `check()` in a child made by `os.fork` and says how it ended: "ok" (it returned
    true), "wrong" (false, or it raised) or "hung" (still running after `seconds`)."""
    import os
    import signal

    child = os.fork()
    if child == 0:
        fine = False
        try:
            signal.alarm(seconds)
            fine = bool(check())
        finally:
            os._exit(0 if fine else 1)
    _, status = os.waitpid(child, 0)
    if os.WIFSIGNALED(status):
        return "hung"
    return "ok" if os.waitstatus_to_exitcode(status) == 0 else "wrong"


@contextlib.contextmanager
def _while_a_thread_repeats(work):
    """Runs `work()` over and over on another thread for as long as the block lasts."""
    stop = threading.Event()

    def repeat():
        while not stop.is_set():
            work()

    thread = threading.Thread(target=repeat)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        thread.join()


def test_a_forked_child_loads_and_computes_as_its_parent():
    """Python's multiprocessing forks by default on Linux: the child has none of the parent's
    helper threads, yet loads and computes the same values, on threads of its own, without
    waiting on helpers that are not there."""
    path = DATA / "bvh" / "assimp_01_01.bvh"
    take = bvhview.load(path)
    want = take.positions()

    def same_again():
        again = bvhview.load(path)
        return np.array_equal(again.values, take.values) and np.array_equal(
            again.positions(), want
        )

    assert _in_forked_child(same_again) == "ok"


def test_children_forked_while_another_thread_loads_and_saves_do_not_hang(tmp_path):
    """A thread that forks while another is inside a load or a save (the GIL is released there)
    gives a child in which that thread's locks stay held for good: the child must not wait for
    them."""
    small = DATA / "bvh" / "bvhparser_walk_01.bvh"  # several chunks: two threads, two buffers
    want = bvhview.load(small).positions()

    def load_compute_save():
        take = bvhview.load(small)
        take.positions()
        take.save(tmp_path / "busy.bvh")

    def same_in_the_child():
        take = bvhview.load(small)
        take.save(tmp_path / "child.bvh")
        again = bvhview.load(tmp_path / "child.bvh")
        return np.array_equal(take.positions(), want) and np.array_equal(
            again.values, take.values
        )

    endings = []
    with _while_a_thread_repeats(load_compute_save):
        while len(endings) < 200 and "hung" not in endings:
            endings.append(_in_forked_child(same_in_the_child, seconds=10))
    assert (endings.count("hung"), endings.count("wrong")) == (0, 0), f"of {len(endings)} children"


def _positions_of(path):
    return bvhview.load(path).positions()


def test_a_multiprocessing_pool_of_forked_workers_computes_what_the_parent_does():
    """The way scripts share a folder among processes: the parent has loaded (so it has helper
    threads and kept buffers), a thread of it keeps loading, and forked workers load too."""
    import multiprocessing

    paths = BVH_FILES[:6]
    want = [_positions_of(path) for path in paths]
    with _while_a_thread_repeats(lambda: _positions_of(paths[0])):
        with multiprocessing.get_context("fork").Pool(2) as pool:
            got = pool.map_async(_positions_of, paths).get(timeout=60)
    assert len(got) == len(want)
    for path, one, other in zip(paths, got, want):
        assert np.array_equal(one, other), path.name


def test_the_stubs_name_every_public_name_with_its_signature():
    """mypy's stubtest compares `_bvhview.pyi` with the module as built: a name, property or
    argument missing from the stubs (or only in them) fails."""
    pytest.importorskip("mypy")
    import sys

    run = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "bvhview"], capture_output=True, text=True
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert "Success: no issues found" in run.stdout


# Saving.


@pytest.mark.parametrize("path", BVH_FILES, ids=ids(BVH_FILES))
def test_save_round_trips_every_repository_file(tmp_path, path):
    take = bvhview.load(path)
    out = tmp_path / "copy.bvh"
    take.save(out)
    back = bvhview.load(out)
    # Names with whitespace are written with "_".
    assert back.joint_names == [re.sub(r"[\s{}]", "_", n) or "unnamed" for n in take.joint_names]
    assert back.channels == take.channels
    assert back.frame_time == take.frame_time
    np.testing.assert_array_equal(back.parents, take.parents)
    np.testing.assert_array_equal(back.offsets, take.offsets)
    np.testing.assert_array_equal(back.values, take.values)
    np.testing.assert_array_equal(back.positions(), take.positions())


def test_save_bakes_asf_axes_and_keeps_the_positions(tmp_path):
    take = bvhview.load(ASF, motion=AMC)
    out = tmp_path / "walk.bvh"
    take.save(str(out))
    back = bvhview.load(out)
    before = take.positions()
    height = np.ptp(before[0], axis=0).max()
    np.testing.assert_allclose(back.positions(), before, rtol=0, atol=1e-4 * height)


@pytest.mark.parametrize("extension", ["glb", "gltf", "fbx"])
def test_save_writes_the_same_gltf_and_fbx_as_the_cli(cli, tmp_path, extension):
    for path, motion in [(DATA / "bvh" / "opencollar_run.bvh", None), (ASF, AMC)]:
        ours = tmp_path / f"ours.{extension}"
        theirs = tmp_path / f"cli.{extension}"
        bvhview.load(path, motion=motion).save(ours)
        args = [str(cli), "convert", "-q", str(path)]
        if motion is not None:
            args += ["--motion", str(motion)]
        subprocess.run(args + ["-o", str(theirs)], check=True)
        assert ours.read_bytes() == theirs.read_bytes()
        start = {"glb": b"glTF", "gltf": b'{"ac', "fbx": b"Kayd"}[extension]
        assert ours.read_bytes()[:4] == start


def test_save_refuses_an_unknown_extension(tmp_path):
    take = bvhview.load(DATA / "bvh" / "opencollar_run.bvh")
    with pytest.raises(ValueError, match=r"save writes \.bvh, \.glb, \.gltf, \.fbx or \.npz files, not 'obj'"):
        take.save(tmp_path / "x.obj")
    assert list(tmp_path.iterdir()) == []


# Issue 26: outputs nobody can hijack or corrupt, inputs that cannot abort the process.


def test_saves_of_one_path_from_two_threads_each_leave_a_whole_file(tmp_path):
    """Row 2: the temporary name was the process id, shared by threads: one save found its
    temporary renamed away (FileNotFoundError) and the file left did not load."""
    take = bvhview.load(DATA / "bvh" / "bvhio_example.bvh")
    out = tmp_path / "same.bvh"
    failures = []

    def save_often():
        try:
            for _ in range(40):
                take.save(out)
        except Exception as error:  # noqa: BLE001 - any failure is the finding
            failures.append(error)

    threads = [threading.Thread(target=save_often) for _ in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert failures == []
    again = bvhview.load(out)
    np.testing.assert_array_equal(again.values, take.values)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["same.bvh"]


def test_a_result_larger_than_memory_is_a_memory_error():
    """Row 7: 10**8 frames of world matrices (243 GB) aborted the process; numpy raises
    MemoryError for such an array, and so does bvhview."""
    take = bvhview.load(DATA / "bvh" / "bvhio_example.bvh")
    with pytest.raises(MemoryError):
        take.world_matrices(np.zeros(10**8, int))
    # The process goes on.
    assert take.world_matrices([0]).shape == (1, len(take.joint_names), 4, 4)


def test_a_take_whose_values_overflow_is_refused_before_anything_is_written(tmp_path):
    """Point 2: an ASF bone of length 3.4e38 along a direction 1.0009 long (used as written:
    within 1e-3 of unit) loads as nothing (its offset is not a 32-bit number), and a file that
    cannot be written leaves no file."""
    asf = tmp_path / "huge.asf"
    asf.write_text(
        ":version 1.10\n:units\n  length 1\n  angle deg\n:root\n  order TX TY TZ RX RY RZ\n"
        "  axis XYZ\n  position 0 0 0\n  orientation 0 0 0\n:bonedata\n  begin\n    id 1\n"
        "    name a\n    direction 0 1.0009 0\n    length 3.4e38\n    axis 0 0 0 XYZ\n    dof rx\n"
        "  end\n:hierarchy\n  begin\n    root a\n  end\n"
    )
    with pytest.raises(bvhview.ParseError, match="too large for a 32-bit float"):
        bvhview.load(asf)


# Issue 28, point 1 (first part): what a motion-ML user asks a take.


def test_a_take_says_its_rate_length_axis_and_units_as_the_cli_does(cli):
    walk = bvhview.load(REPO / "assets" / "walk.bvh")
    assert walk.fps == pytest.approx(1 / walk.frame_time)
    assert walk.duration == pytest.approx(walk.frame_count * walk.frame_time)
    info = subprocess.run(
        [str(cli), "info", str(REPO / "assets" / "walk.bvh")], capture_output=True, text=True
    )
    assert info.returncode == 0, info.stderr
    assert f"up axis:          {walk.up_axis} (" in info.stdout
    assert f"units:            {walk.units} (" in info.stdout
    assert (walk.up_axis, walk.units, walk.metres_per_unit) == ("y", "centimetres", pytest.approx(0.01))
    makehuman = bvhview.load(DATA / "bvh" / "makehuman_walk1.bvh")
    assert (makehuman.up_axis, makehuman.units) == ("z", "decimetres")
    cmu = bvhview.load(ASF, AMC)
    assert cmu.units == "CMU units (1/0.45 inch)"
    assert cmu.metres_per_unit == pytest.approx(0.0254 / 0.45)
    assert isinstance(bvhview.__version__, str) and bvhview.__version__.count(".") == 2


def test_joints_are_found_by_name_and_their_children_listed():
    take = bvhview.load(DATA / "bvh" / "bvhio_example.bvh")
    names = take.joint_names
    assert len(set(names)) == len(names), "every name unique, End Sites included"
    for index, name in enumerate(names):
        assert take.index(name) == index
        assert take.children(index) == [i for i, p in enumerate(take.parents) if p == index]
    with pytest.raises(ValueError, match="no joint named"):
        take.index("Site")
    with pytest.raises(IndexError):
        take.children(len(names))
    assert take.point_names == [names[j] for j in take.point_joints]


def test_warnings_say_what_the_cli_warns_of():
    # MakeHuman's T-pose is written for the add mode: the CLI says so, and so does the take.
    take = bvhview.load(DATA / "bvh" / "makehuman_tpose.bvh")
    assert any("`offset_mode=add`" in w for w in take.warnings), take.warnings
    added = bvhview.load(DATA / "bvh" / "makehuman_tpose.bvh", offset_mode="add")
    assert not any("offset_mode" in w for w in added.warnings), added.warnings


def test_load_many_takes_a_folder_whole(tmp_path):
    # A string is one path, not a list of one-letter paths.
    takes = bvhview.load_many(str(DATA / "bvh"))
    assert [t.path for t in takes] == [str(p) for p in BVH_FILES]
    # ASF/AMC pairs by CMU's subject numbers; an AMC without a skeleton is left out.
    (tmp_path / "deep").mkdir()
    for name, source in [("07.asf", ASF), ("07_05.amc", AMC), ("08_01.amc", AMC)]:
        (tmp_path / "deep" / name).write_bytes(source.read_bytes())
    (tmp_path / "a.bvh").write_bytes((DATA / "bvh" / "bvhio_example.bvh").read_bytes())
    takes = bvhview.load_many(tmp_path)
    assert [(t.path, t.motion_path) for t in takes] == [
        (str(tmp_path / "a.bvh"), None),
        (str(tmp_path / "deep" / "07.asf"), str(tmp_path / "deep" / "07_05.amc")),
    ]
    # One file given alone is a list of one.
    (one,) = bvhview.load_many(DATA / "bvh" / "bvhio_example.bvh")
    assert one.frame_count == takes[0].frame_count


def test_a_take_pickles_whole_and_comes_back_equal():
    """multiprocessing, Dask and Ray pickle what they send: the skeleton and the values travel,
    not the path, and the take that arrives computes the same floats."""
    import pickle

    for take in [bvhview.load(p) for p in BVH_FILES[:4]] + [
        bvhview.load(ASF, AMC),
        bvhview.load(DATA / "bvh" / "makehuman_tpose.bvh", offset_mode="add"),
    ]:
        back = pickle.loads(pickle.dumps(take))
        assert type(back) is bvhview.Motion
        for field in ["path", "motion_path", "offset_mode", "joint_names", "channels",
                      "rotation_orders", "frame_time", "frame_count", "warnings", "units",
                      "up_axis", "point_names"]:
            assert getattr(back, field) == getattr(take, field), field
        for field in ["parents", "end_sites", "offsets", "values", "point_joints"]:
            np.testing.assert_array_equal(getattr(back, field), getattr(take, field))
        np.testing.assert_array_equal(back.positions(), take.positions())
        np.testing.assert_array_equal(back.world_matrices([0]), take.world_matrices([0]))
    with pytest.raises(ValueError, match="not a pickled bvhview.Motion"):
        bvhview._bvhview._from_state((99, "", None, "replace", [], False, None, [], 0.1, 0, b"", (None, None)))


def _frames_of(take):
    return take.frame_count, take.positions()[-1]


def test_takes_travel_to_worker_processes():
    import multiprocessing

    takes = bvhview.load_many(BVH_FILES[:3])
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        got = pool.map(_frames_of, takes, chunksize=1)
    for take, (count, last) in zip(takes, got):
        assert count == take.frame_count
        np.testing.assert_array_equal(last, take.positions()[-1])


@pytest.mark.parametrize(
    "edit, flags",
    [
        (lambda t: t.trim(2, 10), ["--frames", "2..10"]),
        # The walk has 40 frames: the last five.
        (lambda t: t.trim(-5), ["--frames", "35.."]),
        (lambda t: t.resample(24), ["--fps", "24"]),
        (lambda t: t.resample(47.3), ["--fps", "47.3"]),
        (lambda t: t.scale(0.01), ["--scale", "0.01"]),
        (lambda t: t.mirror(), ["--mirror"]),
        (lambda t: t.to_up("z"), ["--out-up", "z"]),
        (lambda t: t.to_up("-x"), ["--out-up", "-x"]),
        (lambda t: t.in_place(), ["--in-place"]),
        (lambda t: t.ground(), ["--ground"]),
    ],
    ids=[
        "trim", "trim-end", "resample", "resample-odd", "scale", "mirror", "to_up", "to_up_x",
        "in_place", "ground",
    ],
)
def test_edits_as_methods_are_the_cli_edits(cli, tmp_path, edit, flags):
    """Each method is `convert`'s edit: the take it returns has the very floats `convert`
    writes."""
    source = REPO / "assets" / "walk.bvh"
    out = tmp_path / "edited.bvh"
    run = subprocess.run(
        [str(cli), "convert", str(source), *flags, "-q", "-o", str(out)],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr
    ours = edit(bvhview.load(source))
    theirs = bvhview.load(out)
    assert ours.frame_count == theirs.frame_count
    assert ours.frame_time == pytest.approx(theirs.frame_time)
    np.testing.assert_array_equal(ours.values, theirs.values)
    np.testing.assert_array_equal(ours.positions(), theirs.positions())
    # A new take each time: the source is unchanged.
    assert bvhview.load(source).frame_count == 40


@pytest.mark.parametrize("path", BVH_FILES + [ASF], ids=ids(BVH_FILES) + ["heiden_12.asf"])
def test_local_transforms_multiply_down_the_tree_to_the_world_ones(path):
    """local_matrices, multiplied parent by parent, are world_matrices; every rotation kind says
    the same rotation; the Euler angles are the rotation channels; the root's translation is the
    translation of its local matrix."""
    take = bvhview.load(path, AMC) if path == ASF else bvhview.load(path)
    frames = [0, take.frame_count - 1] if take.frame_count else None
    local = take.local_matrices(frames).astype(np.float64)
    world = take.world_matrices(frames)
    product = np.empty_like(local)
    for j, parent in enumerate(take.parents):
        product[:, j] = local[:, j] if parent < 0 else product[:, parent] @ local[:, j]
    scale = max(1.0, float(np.abs(world[..., :3, 3]).max()))
    np.testing.assert_allclose(product, world, atol=1e-4 * scale)
    # positions() takes another road (the FK plan's quaternion lanes): the same points.
    np.testing.assert_allclose(product[..., :3, 3], take.positions(frames), atol=1e-4 * scale)
    matrix = take.local_rotations(frames, kind="matrix")
    np.testing.assert_allclose(matrix, local[..., :3, :3], atol=1e-5)
    w, x, y, z = np.moveaxis(take.local_rotations(frames, kind="quat").astype(np.float64), -1, 0)
    from_quat = np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
            np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
            np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )
    np.testing.assert_allclose(from_quat, matrix, atol=1e-5)
    six = take.local_rotations(frames, kind="6d")
    np.testing.assert_allclose(six[..., :3], matrix[..., :, 0], atol=1e-6)
    np.testing.assert_allclose(six[..., 3:], matrix[..., :, 1], atol=1e-6)
    euler = take.local_rotations(frames, kind="euler")
    assert len(take.channel_names) == take.channel_count
    for j, names in enumerate(take.channels):
        first = take.first_channels[j]
        if not names:
            assert first == -1
            continue
        rotations = [k for k, n in enumerate(names) if n.endswith("rotation")]
        if take.frame_count and rotations:
            want = take.values[frames][:, [first + k for k in rotations]]
            np.testing.assert_array_equal(euler[:, j, : len(rotations)], want)
        for k, n in enumerate(names):
            assert take.channel_names[first + k] == f"{take.joint_names[j]}_{n}"
    root = int(np.flatnonzero(take.parents < 0)[0])
    np.testing.assert_array_equal(take.root_translations(frames), take.local_matrices(frames)[:, root, :3, 3])
    with pytest.raises(ValueError, match="kind="):
        take.local_rotations(kind="axis-angle")


@pytest.mark.parametrize("kind", ["quat", "matrix", "6d", "euler"])
@pytest.mark.parametrize("path", BVH_FILES + [ASF], ids=ids(BVH_FILES) + ["heiden_12.asf"])
def test_a_take_built_from_its_own_arrays_moves_as_it_did(path, kind, tmp_path):
    """from_arrays(m, m.local_rotations(kind=k), m.root_translations()) reproduces positions()
    within 1e-5 of the figure's size, for every kind; saved as BVH it loads back the same."""
    take = bvhview.load(path, AMC) if path == ASF else bvhview.load(path)
    rotations = take.local_rotations(kind=kind)
    # A template whose rotation channels hold nothing of the take: every rotation written comes
    # from the arrays.
    identity = np.zeros(rotations.shape[:2] + (4,), np.float32)
    identity[..., 0] = 1
    blank = bvhview.Motion.from_arrays(take, identity, root_translations=take.root_translations())
    # (ASF bones turn about their own axes: the identity comes back within float rounding.)
    assert np.abs(blank.local_rotations(kind="euler")).max() < 1e-3, "the blank holds no angle"
    rebuilt = bvhview.Motion.from_arrays(
        blank, rotations.astype(np.float64), root_translations=take.root_translations(), fps=take.fps
    )
    assert rebuilt.frame_count == max(take.frame_count, 1)
    want = take.positions()
    size = float(want.max(axis=(0, 1)).max() - want.min(axis=(0, 1)).min()) or 1.0
    got = rebuilt.positions()[: len(want)]
    np.testing.assert_allclose(got, want, atol=1e-5 * size, rtol=0)
    if path != ASF:
        saved = tmp_path / "rebuilt.bvh"
        rebuilt.save(saved)
        np.testing.assert_allclose(bvhview.load(saved).positions(), rebuilt.positions(), atol=1e-5 * size, rtol=0)


def test_from_arrays_says_what_is_wrong_with_its_arrays():
    take = bvhview.load(REPO / "assets" / "walk.bvh")
    with pytest.raises(ValueError, match="joints"):
        bvhview.Motion.from_arrays(take, np.zeros((2, 3, 4)))
    with pytest.raises(ValueError, match="shape"):
        bvhview.Motion.from_arrays(take, np.zeros((2, 5)))
    with pytest.raises(ValueError, match="root_translations"):
        bvhview.Motion.from_arrays(
            take, take.local_rotations([0, 1]), root_translations=np.zeros((3, 3))
        )
    with pytest.raises(ValueError, match="fps"):
        bvhview.Motion.from_arrays(take, take.local_rotations([0]), fps=0)
    # Generated motion: the rest pose's rotations at 60 frames per second.
    rest = np.zeros((60, len(take.joint_names), 4), np.float32)
    rest[..., 0] = 1
    made = bvhview.Motion.from_arrays(take, rest, fps=60)
    assert (made.frame_count, made.fps) == (60, pytest.approx(60))


def test_values_as_a_dataframe():
    pandas = pytest.importorskip("pandas")
    take = bvhview.load(DATA / "bvh" / "bvhio_example.bvh")
    frame = take.to_dataframe()
    assert isinstance(frame, pandas.DataFrame)
    assert list(frame.columns) == take.channel_names
    assert frame.index.name == "frame" and list(frame.index) == list(range(take.frame_count))
    np.testing.assert_array_equal(frame.to_numpy(), take.values)
    assert list(take.to_dataframe([1]).index) == [1]


def test_mirror_swaps_left_and_right_and_keeps_names():
    """mirror() keeps every name, parent and channel and swaps the sides' motion: each joint's
    world position is its counterpart's reflected across x; twice gives the take back;
    mirror_names is the counterpart map."""
    take = bvhview.load(DATA / "bvh" / "bvhparser_walk_01.bvh")
    guess = take.mirror_names
    # CMU's names as cgspeed writes them, LHipJoint and LThumb included; Hips has no side.
    assert guess["LeftUpLeg"] == "RightUpLeg" and guess["RThumb"] == "LThumb"
    assert guess["LHipJoint"] == "RHipJoint" and "Hips" not in guess and "LowerBack" not in guess
    mirrored = take.mirror()
    assert mirrored.joint_names == take.joint_names
    assert mirrored.channel_names == take.channel_names
    np.testing.assert_array_equal(mirrored.parents, take.parents)
    partner = [take.index(guess.get(name, name)) if not take.end_sites[i] else None
               for i, name in enumerate(take.joint_names)]
    before, after = take.positions(), mirrored.positions()
    reflected = before * np.array([-1.0, 1.0, 1.0], dtype=np.float32)
    for i, k in enumerate(partner):
        if k is not None:
            np.testing.assert_allclose(after[:, i], reflected[:, k], atol=1e-3)
    back = mirrored.mirror()
    np.testing.assert_array_equal(back.values, take.values)
    np.testing.assert_array_equal(back.offsets, take.offsets)


def test_mirror_renames_when_asked_and_names_can_be_given():
    take = bvhview.load(DATA / "bvh" / "bvhio_example.bvh")
    renamed = take.mirror(rename=True)
    # Joints renamed by the guess where they are; End Sites keep theirs.
    for index, name in enumerate(take.joint_names):
        if not take.end_sites[index]:
            assert renamed.joint_names[index] == take.mirror_names.get(name, name)
    assert renamed.joint_names[take.index("LeftCollar")] == "RightCollar"
    given = take.mirror(names={"LeftCollar": "Collar_B", "RightCollar": "Collar_A"}, rename=True)
    assert given.joint_names[take.index("LeftCollar")] == "Collar_B"
    assert given.joint_names[take.index("LeftUpArm")] == "RightUpArm", "not listed: the guess"
    assert given.joint_names[take.index("Hips")] == "Hips"
    np.testing.assert_array_equal(given.positions(), renamed.positions())
    # The same world positions by name as the swap.
    swapped = take.mirror()
    np.testing.assert_allclose(
        renamed.positions()[:, renamed.index("RightHand")],
        swapped.positions()[:, swapped.index("RightHand")],
        atol=1e-3,
    )
    # In a swap, names are counterparts the skeleton has.
    with pytest.raises(ValueError, match="not a joint"):
        take.mirror(names={"LeftCollar": "Collar_B"})
    odd = take.mirror(names={"LeftCollar": "RightCollar"})
    np.testing.assert_array_equal(odd.values, swapped.values)


def test_mirror_reads_names_from_a_map_file_per_skeleton(tmp_path):
    """names= may be a map file's path, as `convert --mirror-names FILE` reads it: a
    [skeleton.FINGERPRINT] section applies to that skeleton only."""
    take = bvhview.load(DATA / "bvh" / "bvhio_example.bvh")
    swapped = take.mirror()
    path = tmp_path / "sides.toml"
    path.write_text('"LeftCollar" = "RightCollar"\n\n'
                    '[skeleton.000000000000]\n"LeftCollar" = "Nowhere"\n')
    np.testing.assert_array_equal(take.mirror(names=str(path)).values, swapped.values)
    with pytest.raises(ValueError, match="Nowhere"):
        take.mirror(names={"LeftCollar": "Nowhere"})


def test_ground_and_to_up_work_in_the_takes_own_offset_mode():
    take = bvhview.load(DATA / "bvh" / "makehuman_tpose.bvh", offset_mode="add")
    assert take.up_axis == "z"
    grounded = take.ground()
    assert float(grounded.positions()[..., 2].min()) == pytest.approx(0, abs=1e-4)
    assert take.to_up("y").up_axis == "y"


def test_a_joint_of_two_channels_bent_past_a_right_angle_comes_back(tmp_path):
    """A joint with two rotation channels: the angles of its rotation are found again even when
    it bends past 90 degrees about its second axis."""
    path = tmp_path / "elbow.bvh"
    path.write_text(
        "HIERARCHY\nROOT Root\n{\n OFFSET 0 0 0\n CHANNELS 3 Xposition Yposition Zposition\n"
        " JOINT Elbow\n {\n  OFFSET 0 10 0\n  CHANNELS 2 Xrotation Zrotation\n"
        "  End Site\n  {\n   OFFSET 0 10 0\n  }\n }\n}\nMOTION\nFrames: 4\nFrame Time: 0.1\n"
        "0 0 0 30 120\n0 0 0 -45 -150\n0 0 0 170 95\n0 0 0 10 20\n"
    )
    take = bvhview.load(path)
    for kind in ["quat", "matrix", "6d"]:
        rebuilt = bvhview.Motion.from_arrays(take, take.local_rotations(kind=kind))
        np.testing.assert_allclose(rebuilt.positions(), take.positions(), atol=1e-4)


@pytest.mark.parametrize(
    "joints, frame_time, data, said",
    [
        ([("a", -1, [0, 0, 0], ["Xrotation"], False, None)], 0.1, b"\0" * 3, "values"),
        ([("a", -1, [0, 0, 0], ["Xrotation", "Yrotation"], False, None)], 0.1, b"\0" * 12, "values"),
        ([("a", -1, [0, 0, 0], ["Twist"], False, None)], 0.1, b"", "channel"),
        ([("a", 1, [0, 0, 0], [], False, None)], 0.1, b"", "parent"),
        (
            [
                ("r", -1, [0, 0, 0], [], False, None),
                ("a", 0, [0, 0, 0], [], False, None),
                ("b", 0, [0, 0, 0], [], False, None),
                ("c", 1, [0, 0, 0], [], False, None),
            ],
            0.1,
            b"",
            "pre-order",
        ),
        ([("a", -1, [0, 0, 0], ["Xrotation"], True, None)], 0.1, b"", "End Site"),
        ([("a", -1, [float("nan"), 0, 0], [], False, None)], 0.1, b"", "OFFSET"),
        ([("a", -1, [0, 0, 0], [], False, None)], float("nan"), b"", "frame time"),
    ],
)
def test_a_state_that_no_take_pickles_is_refused(joints, frame_time, data, said):
    channels = sum(len(j[3]) for j in joints)
    state = (3, "x.bvh", None, "replace", [], False, None, joints, frame_time, channels, data, (None, None))
    with pytest.raises(ValueError, match=said):
        bvhview._bvhview._from_state(state)


def test_from_arrays_refuses_numbers_that_are_not_finite():
    take = bvhview.load(REPO / "assets" / "walk.bvh")
    rotations = take.local_rotations([0, 1])
    rotations[1, 3, 2] = np.nan
    with pytest.raises(ValueError, match=r"rotations\[1, 3\]"):
        bvhview.Motion.from_arrays(take, rotations)
    with pytest.raises(ValueError, match="root_translations"):
        bvhview.Motion.from_arrays(
            take, take.local_rotations([0]), root_translations=np.full((1, 3), np.inf)
        )


def test_errors_name_python_arguments_not_cli_options():
    """Issue 44: a message says `fps=`, not `--fps`, and an AMC file alone is pointed to the call."""
    amc = DATA / "asf_amc" / "heiden_12_02_01.amc"
    with pytest.raises(ValueError, match=r'give its skeleton: bvhview\.load\("SKELETON\.asf", motion=".*heiden_12_02_01\.amc"\)$'):
        bvhview.load(amc)
    take = bvhview.load(DATA / "bvh" / "bvh11_131_01.bvh")
    with pytest.raises(ValueError, match=r"^(?!.*--)fps=0: expected frames per second"):
        take.resample(0)


def test_units_given_replace_the_guess_and_travel_in_a_pickle():
    import pickle

    path = DATA / "bvh" / "bvhparser_simple.bvh"
    guessed = bvhview.load(path)
    given = bvhview.load(path, units="cm")
    assert guessed.units == "inches"
    assert (given.units, given.metres_per_unit) == ("centimetres", pytest.approx(0.01))
    back = pickle.loads(pickle.dumps(given))
    assert (back.units, back.metres_per_unit) == ("centimetres", pytest.approx(0.01))
    assert bvhview.load(path, units=0.5).metres_per_unit == 0.5
    with pytest.raises(ValueError, match="units="):
        bvhview.load(path, units="parsecs")


def test_an_up_axis_given_replaces_the_guess_and_travels_in_a_pickle():
    import pickle

    path = DATA / "bvh" / "makehuman_walk1.bvh"
    assert bvhview.load(path).up_axis == "z"
    given = bvhview.load(path, up="y")
    assert given.up_axis == "y"
    assert pickle.loads(pickle.dumps(given)).up_axis == "y"
    assert given.to_up("z").up_axis == "z"
    with pytest.raises(ValueError, match="up="):
        bvhview.load(path, up="w")


def test_in_units_is_convert_out_units(cli, tmp_path):
    """Motion.in_units is `convert --out-units`: the same floats, positions in those units."""
    source = DATA / "bvh" / "bvhparser_walk_01.bvh"
    out = tmp_path / "m.bvh"
    run = subprocess.run(
        [str(cli), "convert", str(source), "--out-units", "m", "-q", "-o", str(out)],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr
    walk = bvhview.load(source)
    ours = walk.in_units("m")
    np.testing.assert_array_equal(ours.values, bvhview.load(out).values)
    assert (ours.units, ours.metres_per_unit) == ("metres", 1.0)
    np.testing.assert_allclose(
        ours.positions(), walk.positions() * walk.metres_per_unit, rtol=1e-5, atol=1e-6
    )
    with pytest.raises(ValueError, match="units="):
        walk.in_units("furlongs")


@pytest.mark.parametrize("axis", ["x", "-x", "-y", "-z"])
def test_any_signed_up_axis_stands_a_take_turned_to_it_back_up(axis, tmp_path):
    """A walk turned to stand along `axis` (`to_up`, as `convert --out-up`), saved and loaded
    with up=axis, is the walk again: turned to y as it is read, and said in its warnings."""
    walk = bvhview.load(DATA / "bvh" / "bvhparser_walk_01.bvh")
    turned = walk.to_up(axis)
    assert np.abs(turned.positions() - walk.positions()).max() > 10
    path = tmp_path / "turned.bvh"
    turned.save(path)
    back = bvhview.load(path, up=axis)
    assert back.up_axis == "y"
    assert any(f"up={axis}: turned to stand along +y" in w for w in back.warnings)
    np.testing.assert_allclose(back.positions(), walk.positions(), atol=1e-4 * 25.4)


def test_a_target_loaded_with_units_and_up_keeps_them_on_the_take_put_on_it(tmp_path):
    """A target Motion loaded with units= and up= is the target as the user says it is
    (`--onto-units`, `--onto-up`): the take put on it is in those units and stands that way."""
    walk = bvhview.load(DATA / "bvh" / "bvhparser_walk_01.bvh")
    small = bvhview.load(DATA / "bvh" / "bvhpython_test_freebvh.bvh").scale(0.35)
    small.save(tmp_path / "small.bvh")
    guessed = walk.retarget(bvhview.load(tmp_path / "small.bvh"))
    assert guessed.units == "inches"
    given = walk.retarget(bvhview.load(tmp_path / "small.bvh", units="cm", up="y"))
    assert (given.units, given.up_axis) == ("centimetres", "y")
    np.testing.assert_array_equal(given.values, guessed.values)
    assert given.in_units("m").positions()[:, :, 1].max() < 0.7


def test_load_many_says_what_every_take_is_as_load_does():
    """load_many(units=, up=) gives every take what load(units=, up=) gives one."""
    paths = [DATA / "bvh" / "bvhparser_walk_01.bvh", DATA / "bvh" / "makehuman_walk1.bvh"]
    many = bvhview.load_many(paths, units="cm", up="-z")
    for path, take in zip(paths, many):
        one = bvhview.load(path, units="cm", up="-z")
        assert (take.units, take.up_axis) == ("centimetres", "y")
        np.testing.assert_array_equal(take.positions(), one.positions())
        assert take.warnings == one.warnings
    with pytest.raises(ValueError, match="up="):
        bvhview.load_many(paths, up="w")
