"""Datasets of motion for training: a folder of takes compiled into arrays, and read back.

    import bvhview
    bvhview.compile_dataset("mocap/", "walks.ds", fps=30, rotations="6d")
    data = bvhview.Dataset("walks.ds", window=64, stride=32)
    item = data[0]           # dict of numpy arrays: positions (64, joints, 3), rotations, ...
    mine = data.shard(rank, world_size)

The compile is bvhview's Rust code on every core (the command `bvhview dataset` is the same
code). The layout on disk is in docs/PYTHON.md.
"""

from __future__ import annotations

import contextlib
import json
import mmap
import os
import secrets
import signal
import stat
import threading
import warnings
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any, Literal

import numpy as np

from ._bvhview import (
    Motion,
    _compile_dataset,
    _dataset_manifest,
    _dataset_motion,
    _merge_datasets,
    _open_dataset,
)

#: The arrays of every group, as the manifest lists them (besides ``offsets`` and
#: ``rest_offsets``).
ARRAYS = ("positions", "rotations", "translations", "root_translations", "velocities", "foot_contacts")

StrPath = str | os.PathLike[str]



def _clips(count: int) -> str:
    """`1 clip`, `3 clips`."""
    return f"{count} clip" if count == 1 else f"{count} clips"

class SkippedTake(UserWarning):
    """A take ``compile_dataset`` could not compile; the message is its ``path:line:column``
    and reason, as the manifest's ``skipped`` list keeps it."""


def _checked(dataset: StrPath) -> tuple[dict[str, Any], list[dict[str, np.ndarray]], list[list[int]]]:
    """The dataset checked whole by bvhview's reader (which trusts nothing in the folder: no
    links, only regular files of the sizes their headers and the manifest give, clip ranges in
    order and inside the arrays), with every array mapped from the very file that was checked."""
    text, groups, offsets = _open_dataset(os.fspath(dataset))
    mapped: list[dict[str, np.ndarray]] = []
    try:
        for group in groups:
            arrays = {}
            for name, fd, dtype, shape in group:
                size = int(np.prod(shape, dtype=np.int64)) * np.dtype(dtype).itemsize
                if size == 0:
                    arrays[name] = np.zeros(shape, dtype=dtype)
                else:
                    # The map keeps the file open; the descriptor is closed below either way.
                    buffer = mmap.mmap(fd, 0, access=mmap.ACCESS_READ)
                    arrays[name] = np.ndarray(shape, dtype=dtype, buffer=buffer, offset=128)
            mapped.append(arrays)
    finally:
        for group in groups:
            for _, fd, _, _ in group:
                os.close(fd)
    manifest: dict[str, Any] = json.loads(text)
    return manifest, mapped, offsets


def _read_manifest(dataset: StrPath) -> dict[str, Any]:
    manifest: dict[str, Any] = json.loads(_dataset_manifest(os.fspath(dataset)))
    return manifest


class _Terminated(BaseException):
    """SIGTERM or SIGHUP arrived during a compile or merge: raised by the handler
    ``_ended_cleanly`` installs, as Ctrl-C raises KeyboardInterrupt (a BaseException, so that an
    ``except Exception`` does not swallow it)."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


@contextlib.contextmanager
def _ended_cleanly() -> Iterator[None]:
    """SIGTERM and SIGHUP (where Python leaves them at their default, which ends the process at
    once) stop the work in the block as Ctrl-C does: the compile stops between takes and removes
    its temporary ``.OUT.*`` folder (a merge or a Parquet file finishes first). The process then
    ends by the same signal, as it would have without the cleanup. Only Python's main thread can
    take signals: elsewhere this does nothing."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def stop(signum: int, frame: object) -> None:
        raise _Terminated(signum)

    installed = {}
    for number in (signal.SIGTERM, signal.SIGHUP):
        if signal.getsignal(number) == signal.SIG_DFL:
            installed[number] = signal.signal(number, stop)
    try:
        yield
    except _Terminated as ended:
        for number, old in installed.items():
            signal.signal(number, old)
        installed.clear()
        os.kill(os.getpid(), ended.signum)
        raise SystemExit(128 + ended.signum) from None
    finally:
        for number, old in installed.items():
            signal.signal(number, old)


def compile_dataset(
    folder: StrPath,
    out: StrPath,
    *,
    fps: float | None = None,
    rotations: Literal["quat", "matrix", "6d", "euler", "axis_angle"] = "6d",
    root_relative: bool = False,
    feet: Sequence[str] | None = None,
    contact_height: float = 0.05,
    contact_speed: float = 0.5,
    takes: Sequence[tuple[StrPath, StrPath | None]] | None = None,
    threads: int | None = None,
    parquet: bool = False,
    onto: StrPath | None = None,
    ground: bool = False,
    quat_continuous: bool = False,
    names: dict[str, str] | StrPath | None = None,
    lock_feet: bool = False,
    features: Literal["arrays", "humanml3d"] = "arrays",
    any_body: bool = False,
    force: bool = False,
    units: str | float | None = None,
    up: Literal["y", "z", "x", "-y", "-z", "-x"] | None = None,
    out_units: str | float | None = None,
) -> dict[str, Any]:
    """Compile every take under ``folder`` (or the ``takes`` listed, as ``list_takes`` gives
    them) into the new dataset folder ``out``; returns its manifest, whose ``"skipped"`` lists
    the takes that could not be compiled (each also warned about as a ``SkippedTake``).

    Every take is turned to Y up and metres (by its guessed up axis and units), resampled to
    ``fps``, and written as world ``positions``, local ``rotations`` (``"quat"``, ``"matrix"``,
    ``"6d"``, ``"euler"`` or ``"axis_angle"``), ``translations`` (the local translation of every
    joint with position channels), ``root_translations`` (the world position of the joint that
    carries the travel), ``velocities`` (m/s) and ``foot_contacts`` (a foot point within
    ``contact_height`` metres of the floor, the lowest foot point within a second, and slower
    than ``contact_speed`` m/s). ``feet`` names the foot points (default: each leg's ankle and
    toe as the reading of the body finds them, ``info``'s ``body:`` line; a body without two
    feet gets the rest pose's lowest points, with a warning in the manifest). ``ground``: each
    clip's lowest foot point over the clip on y = 0. ``quat_continuous`` (with ``rotations=
    "quat"``): each frame's quaternion sign chosen against the previous frame's, so that they
    run continuously along time; by default every quaternion has w ≥ 0 and may flip sign between
    neighbouring frames. ``lock_feet``: each take's planted feet held where they landed first,
    as ``bvhview convert --lock-feet`` holds them. A take that fails is skipped with its ``path:line:column``; a
    folder of which no take compiles raises ValueError naming every reason, and writes nothing.
    ``parquet``: also write ``group_K/frames.parquet`` (needs pyarrow). Ctrl-C and SIGTERM stop
    the compile between takes, leaving nothing behind (SIGTERM and SIGHUP when Python has them
    at their default and this runs in the main thread; the process then ends by that signal). A
    process killed outright (SIGKILL) leaves its temporary ``.OUT.*`` folder beside ``out``.
    What the folder walk skipped (a loop, a link out of the folder, a take reached twice) is
    said as a UserWarning each. ``onto``: retarget every take onto this skeleton first (a file, or
    the built-in ``"smpl22"``), as ``Motion.retarget`` does, so the folder makes one group; a take
    whose map misses a required role is skipped with the reason; ``names`` overrides every take's
    guessed map as ``Motion.retarget``'s does ({source joint: target joint}, ``""`` leaves one
    out), or is a map file's path, whose ``[skeleton.FINGERPRINT]`` pairs apply to the takes of
    that skeleton only (``bvhview info`` prints the fingerprint); a take whose body is not
    two-legged like the target's (or the reverse) is skipped with the reason unless
    ``any_body``. Each retargeted take is measured against its source as ``Motion.retarget``
    measures it (each clip's ``"retarget_check"`` in the manifest); one whose sides cross or
    whose widths collapse is skipped with the reason unless ``force`` (then kept, with a
    warning in its clip's ``"warnings"``). The manifest records ``onto`` and ``names``; ``merge_datasets`` refuses datasets made
    with other ones. ``fps`` defaults to 30. ``units`` ("mm", "cm", "m", "in", "ft" or metres per
    unit) says what every take's lengths are in, over the guess; each clip's ``"units_given"``
    in the manifest records it; ``up`` ("y", "z", "x", "-y", "-z" or "-x") the axis every take
    stands along, over the guess (``"up_given"`` per clip; a take said to stand along x, -y, -z
    or -x is turned to y as it is read). ``out_units`` writes every length (positions,
    translations, velocities, OFFSETs, each group's ``skeleton.bvh``) in those units instead of
    metres, recorded as the manifest's ``"units"`` and ``"metres_per_unit"``; contact thresholds
    and metrics stay in metres, and ``features="humanml3d"`` is metres by its definition.

    ``features="humanml3d"`` (with ``onto="smpl22"``; ``fps`` then defaults to HumanML3D's 20)
    writes HumanML3D's representation in its folder layout instead of the arrays: per take
    ``new_joint_vecs/ID.npy`` (frames − 1 vectors of 263 values, as its own pipeline makes
    them), ``new_joints/ID.npy`` (the joint positions they stand for), and over the set
    ``Mean.npy``, ``Std.npy`` and ``all.txt`` (the IDs: each take's place in the folder's list,
    six digits; the manifest names each ID's source)."""
    if parquet:
        _need_pyarrow()
        if features != "arrays":
            raise ValueError("parquet=True writes the arrays' frames; features=\"humanml3d\" has none")
    with _ended_cleanly():
        _, _, _, skipped = _compile_dataset(
            os.fspath(folder),
            os.fspath(out),
            fps=fps,
            rotations=rotations,
            root_relative=root_relative,
            feet=None if feet is None else [str(f) for f in feet],
            contact_height=contact_height,
            contact_speed=contact_speed,
            takes=None if takes is None else [(p, m) for p, m in takes],
            threads=threads,
            onto=None if onto is None else os.fspath(onto),
            ground=ground,
            quat_continuous=quat_continuous,
            names=names if names is None or isinstance(names, dict) else os.fspath(names),
            lock_feet=lock_feet,
            features=features,
            any_body=any_body,
            units=units,
            up=up,
            out_units=out_units,
            force=force,
        )
        for _, _, reason in skipped:
            warnings.warn(f"skipped {reason}", SkippedTake, stacklevel=2)
        if parquet:
            write_parquet(out)
    return _read_manifest(out)


def _need_pyarrow() -> None:
    try:
        import pyarrow  # type: ignore[import-untyped,import-not-found,unused-ignore]  # noqa: F401
    except ImportError:
        raise ImportError("parquet=True needs pyarrow (pip install pyarrow)") from None


def merge_datasets(
    pieces: Sequence[StrPath], out: StrPath, *, join: str = "pieces", parquet: bool = False
) -> dict[str, Any]:
    """Merge datasets into ``out`` and return its manifest. ``join="pieces"`` (the default):
    pieces of one compile (``bvhview.dask`` makes them), every take of its list once, given in
    order, with no gap; the result is byte for byte the dataset one ``compile_dataset`` of the
    whole folder writes. ``join="folders"``: datasets of any folders made with the same
    options, their clips one after the other, grouped by skeleton topology."""
    if parquet:
        _need_pyarrow()
    with _ended_cleanly():
        _merge_datasets([os.fspath(p) for p in pieces], os.fspath(out), join=join)
        if parquet:
            write_parquet(out)
    return _read_manifest(out)


def _plain_folder(root: Path, name: object) -> int:
    """A group's folder opened without following a link (its descriptor): ``name`` must be a
    plain name of a real folder inside ``root``."""
    if not isinstance(name, str) or name in ("", ".", "..") or "/" in name or "\0" in name:
        raise ValueError(f"{root}: group name {name!r} is not a plain folder name")
    folder = root / name
    if folder.is_symlink():
        raise ValueError(f"{folder}: is a symbolic link; a dataset's folders are never followed out")
    return os.open(folder, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW)


def _refuse_link(folder: Path, name: str, dir_fd: int) -> None:
    try:
        mode = os.lstat(name, dir_fd=dir_fd).st_mode
    except FileNotFoundError:
        return
    if stat.S_ISLNK(mode):
        raise ValueError(f"{folder / name}: is a symbolic link; not written or read through")
    if not stat.S_ISREG(mode):
        # A FIFO would wait for a writer for good.
        raise ValueError(f"{folder / name}: not a regular file")


def write_parquet(dataset: StrPath) -> list[Path]:
    """Write ``group_K/frames.parquet`` beside each group's arrays: a row per frame with its
    ``clip`` (index into ``manifest["clips"]``) and ``frame``, and each array's numbers of that
    frame as a fixed-size list column. Needs pyarrow. The dataset is read through bvhview's
    checked reader (a folder or array that is a link is refused, ValueError), a
    ``frames.parquet`` that is a link or not a regular file is refused, and each file is
    written under an exclusive random temporary name, then renamed."""
    import pyarrow as pa  # type: ignore[import-untyped,import-not-found,unused-ignore]
    import pyarrow.parquet as pq  # type: ignore[import-untyped,import-not-found,unused-ignore]

    root = Path(dataset)
    manifest, mapped, _ = _checked(root)
    written = []
    for k, group in enumerate(manifest["groups"]):
        folder = root / str(group["name"])
        dir_fd = _plain_folder(root, group["name"])
        try:
            clips = [i for i, c in enumerate(manifest["clips"]) if c["group"] == k]
            frames = np.array([manifest["clips"][i]["frames"] for i in clips], dtype=np.int64)
            columns: dict[str, Any] = {
                "clip": pa.array(np.repeat(np.array(clips, dtype=np.int32), frames)),
                "frame": pa.array(
                    np.concatenate([np.arange(n, dtype=np.int32) for n in frames])
                    if len(frames)
                    else np.zeros(0, np.int32)
                ),
            }
            for name in ARRAYS:
                array = mapped[k][name]
                width = int(np.prod(array.shape[1:]))
                if width == 0:
                    # A skeleton without feet has no contacts: Arrow has no list of 0 items.
                    continue
                flat = pa.array(array.reshape(-1))
                columns[name] = pa.FixedSizeListArray.from_arrays(flat, width)
            _refuse_link(folder, "frames.parquet", dir_fd)
            # Written under a random name made exclusively (never through a link planted under
            # a name guessed in advance), then renamed: a reader never sees half a file.
            while True:
                partial = f".frames.parquet.{secrets.token_hex(6)}.partial"
                try:
                    fd = os.open(
                        partial,
                        os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC,
                        0o666,
                        dir_fd=dir_fd,
                    )
                    break
                except FileExistsError:
                    continue
            try:
                with os.fdopen(fd, "wb") as file:
                    pq.write_table(pa.table(columns), file)
                os.replace(partial, "frames.parquet", src_dir_fd=dir_fd, dst_dir_fd=dir_fd)
            finally:
                with contextlib.suppress(FileNotFoundError):
                    os.unlink(partial, dir_fd=dir_fd)
        finally:
            os.close(dir_fd)
        written.append(folder / "frames.parquet")
    return written


class Dataset:
    """A compiled dataset read back as a map-style dataset of numpy arrays (PyTorch's
    ``DataLoader`` takes it as it is; bvhview never imports torch).

    The folder is checked whole when it is opened, as input from anyone: bvhview's reader
    refuses links inside it, files that are not regular, names it does not make, ``.npy``
    headers or sizes that are not what the manifest says, and clip ranges that are out of
    order or outside the arrays (a ``ValueError`` saying which).

    Item ``i`` is a dict: each array of one window (``window`` frames; a whole clip when
    ``window`` is None) and ``clip`` (index into ``manifest["clips"]``) and ``start`` (its first
    frame in the clip). Windows start every ``stride`` frames (default: ``window``); a clip
    shorter than ``window`` gives none. The arrays are memory-mapped: only the windows read are
    loaded. ``group`` picks one skeleton topology (its index or name); a dataset with one group
    needs none. ``rest_offsets`` (clips x points x 3) holds each clip's bone offsets."""

    def __init__(
        self,
        path: StrPath,
        window: int | None = None,
        stride: int | None = None,
        *,
        group: int | str | None = None,
        arrays: Sequence[str] = ARRAYS,
    ) -> None:
        self.path = Path(path)
        manifest, _, _ = self._load()
        groups = manifest["groups"]
        if not groups:
            raise ValueError(f"{self.path}: the dataset has no clips")
        if group is None:
            if len(groups) != 1:
                listed = ", ".join(f"{g['name']} ({_clips(g['clips'])})" for g in groups)
                raise ValueError(
                    f"{self.path}: {len(groups)} skeleton topologies ({listed}): "
                    "choose one with group="
                )
            index = 0
        elif isinstance(group, str):
            names = [g["name"] for g in groups]
            if group not in names:
                raise ValueError(f"group={group!r}: expected one of {names}")
            index = names.index(group)
        else:
            if isinstance(group, bool) or not 0 <= group < len(groups):
                raise IndexError(f"group={group}: the dataset has {len(groups)}")
            index = group
        for name, value in (("window", window), ("stride", stride)):
            if value is not None and (isinstance(value, bool) or not isinstance(value, int) or value < 1):
                raise ValueError(f"{name}={value!r}: expected a whole number of frames, at least 1")
        if window is None and stride is not None:
            raise ValueError(f"stride={stride}: a stride needs a window (without one, items are whole clips)")
        if stride is None:
            stride = window or 1
        unknown = [a for a in arrays if a not in ARRAYS]
        if unknown:
            raise ValueError(f"arrays={unknown}: expected some of {list(ARRAYS)}")
        self.index = index
        self.window = window
        self.stride = stride
        self._names = tuple(arrays)
        self._open()
        self.clips = [i for i, c in enumerate(self.manifest["clips"]) if c["group"] == index]
        windows = []
        for k, clip in enumerate(self.clips):
            frames = int(self.offsets[k + 1] - self.offsets[k])
            if window is None:
                windows.append((clip, int(self.offsets[k]), 0, frames))
            else:
                for start in range(0, frames - window + 1, stride):
                    windows.append((clip, int(self.offsets[k]), start, window))
        self._windows = windows

    def _load(self) -> tuple[dict[str, Any], list[dict[str, np.ndarray]], list[list[int]]]:
        return _checked(self.path)

    def _open(self) -> None:
        manifest, mapped, offsets = self._load()
        self.manifest = manifest
        self.group = manifest["groups"][self.index]
        self.arrays = {name: mapped[self.index][name] for name in self._names}
        self.rest_offsets = mapped[self.index]["rest_offsets"]
        self.offsets = np.array(offsets[self.index], dtype=np.int64)

    def __getstate__(self) -> dict[str, Any]:
        # A DataLoader worker started by spawn gets the dataset pickled: the folder is checked
        # and mapped again there, not copied into the pickle.
        state = self.__dict__.copy()
        for opened in ("arrays", "rest_offsets", "manifest", "group", "offsets"):
            del state[opened]
        return state

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.__dict__.update(state)
        self._open()

    def __len__(self) -> int:
        return len(self._windows)

    def __getitem__(self, index: int) -> dict[str, Any]:
        if not -len(self) <= index < len(self):
            raise IndexError(f"index {index}: the dataset has {len(self)} items")
        clip, row, start, length = self._windows[index]
        item: dict[str, Any] = {
            name: np.array(array[row + start : row + start + length])
            for name, array in self.arrays.items()
        }
        item["clip"] = clip
        item["start"] = start
        return item

    def stats(self, array: str) -> tuple[np.ndarray, np.ndarray]:
        """The group's mean and standard deviation of ``array`` over every frame, each shaped
        as one frame of it (a number that never changes has a deviation of 0: add a small
        epsilon before dividing by it)."""
        for entry in self.group["stats"]:
            if entry["name"] == array:
                shape = next(a["shape"][1:] for a in self.group["arrays"] if a["name"] == array)
                mean = np.array(entry["mean"], dtype=np.float32).reshape(shape)
                std = np.array(entry["std"], dtype=np.float32).reshape(shape)
                return mean, std
        names = [entry["name"] for entry in self.group["stats"]]
        raise ValueError(f"array={array!r}: statistics are kept for {names}")

    def to_motion(
        self,
        rotations: Any,
        translations: Any = None,
        root_translations: Any = None,
        *,
        clip: int | None = None,
        kind: str | None = None,
        fps: float | None = None,
    ) -> Motion:
        """Arrays in this group's layout (a clip's, or a model's output shaped like them) as a
        ``bvhview.Motion`` on the group's skeleton, to ``save`` as BVH or glTF.

        ``rotations``: frames x rotated joints x the rotation kind's numbers (the dataset's
        kind unless ``kind`` says another: ``"quat"``, ``"matrix"``, ``"6d"``, ``"euler"``,
        ``"axis_angle"``). ``translations``: frames x translated joints x 3, the local
        translations of the joints with position channels; without them those joints stand at
        their rest offsets, but for ``root_translations`` (frames x 3), the world position of
        the travel joint when it is a root. ``clip`` (an index into ``manifest["clips"]``) gives
        the bone lengths and travel joint (default: the group's first clip's); ``fps`` defaults
        to the dataset's."""
        def as_array(values: Any) -> np.ndarray | None:
            return None if values is None else np.ascontiguousarray(values, dtype=np.float32)

        return _dataset_motion(
            os.fspath(self.path),
            self.index,
            np.ascontiguousarray(rotations, dtype=np.float32),
            kind or self.manifest["options"]["rotations"],
            translations=as_array(translations),
            root_translations=as_array(root_translations),
            clip=clip,
            fps=fps,
        )

    def shard(self, rank: int, world_size: int, *, pad: bool = False) -> Dataset:
        """The items of process ``rank`` among ``world_size``: every ``world_size``-th item from
        ``rank`` on, as PyTorch's ``DistributedSampler`` deals them out. Without ``pad`` the
        shards are disjoint and together the whole dataset, and their lengths may differ by
        one; with ``pad``, items from the start are dealt again so that every shard has the
        same length (``DistributedSampler``'s default, which keeps collective operations of
        distributed training in step)."""
        if world_size < 1 or not 0 <= rank < world_size:
            raise ValueError(f"rank={rank}, world_size={world_size}: expected 0 <= rank < world_size")
        windows = self._windows
        if pad and windows:
            total = -(-len(windows) // world_size) * world_size
            windows = (windows * (total // len(windows) + 1))[:total]
        shard = object.__new__(Dataset)
        shard.__dict__.update(self.__dict__)
        shard._windows = windows[rank::world_size]
        return shard

    def __repr__(self) -> str:
        return (
            f"Dataset({str(self.path)!r}, {self.group['name']}: {_clips(len(self.clips))}, "
            f"{len(self)} items of {self.window or 'whole clip'} frames)"
        )
