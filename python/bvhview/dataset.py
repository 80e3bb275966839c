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
import os
import secrets
import signal
import stat
import threading
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ._bvhview import _compile_dataset, _merge_datasets

#: The arrays of every group, as the manifest lists them (besides ``offsets``).
ARRAYS = ("positions", "rotations", "root_translations", "velocities", "foot_contacts")

StrPath = str | os.PathLike[str]


def _read_manifest(dataset: StrPath) -> dict[str, Any]:
    with open(Path(dataset) / "manifest.json", encoding="utf-8") as file:
        manifest: dict[str, Any] = json.load(file)
    return manifest


def _want_parquet(parquet: bool | None) -> bool:
    if parquet is False:
        return False
    try:
        import pyarrow  # type: ignore[import-untyped,import-not-found,unused-ignore]  # noqa: F401
    except ImportError:
        if parquet:
            raise ImportError("parquet=True needs pyarrow (pip install pyarrow)") from None
        return False
    return True


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
    fps: float = 30.0,
    rotations: str = "6d",
    root_relative: bool = False,
    contact_height: float = 0.05,
    contact_speed: float = 0.5,
    takes: Sequence[tuple[StrPath, StrPath | None]] | None = None,
    threads: int | None = None,
    parquet: bool | None = None,
) -> dict[str, Any]:
    """Compile every take under ``folder`` (or the ``takes`` listed, as ``list_takes`` gives
    them) into the new dataset folder ``out``; returns its manifest.

    Every take is turned to Y up and metres (by its guessed up axis and units), resampled to
    ``fps``, and written as world ``positions``, local ``rotations`` (``"quat"``, ``"matrix"``,
    ``"6d"`` or ``"euler"``), ``root_translations``, ``velocities`` (m/s) and ``foot_contacts``
    (a foot point within ``contact_height`` metres of its lowest point in the take, slower than
    ``contact_speed`` m/s). A take that fails is skipped and listed in ``manifest["skipped"]``
    with its ``path:line:column``; a folder of which no take compiles raises ValueError and
    writes nothing (a piece given as ``takes`` may compile none). ``parquet``: also write
    ``group_K/frames.parquet`` (default: when pyarrow is installed). Ctrl-C stops the compile
    between takes, leaving nothing behind; so do SIGTERM and SIGHUP (then the process ends by
    that signal) when Python has them at their default and this runs in the main thread; a
    process killed outright (SIGKILL) leaves its temporary ``.OUT.*`` folder beside ``out``.
    What the folder walk skipped (a loop, a link out of the folder, a take reached twice) is
    said as a UserWarning each."""
    with _ended_cleanly():
        _compile_dataset(
            os.fspath(folder),
            os.fspath(out),
            fps=fps,
            rotations=rotations,
            root_relative=root_relative,
            contact_height=contact_height,
            contact_speed=contact_speed,
            takes=None if takes is None else [(p, m) for p, m in takes],
            threads=threads,
        )
        if _want_parquet(parquet):
            write_parquet(out)
    return _read_manifest(out)


def merge_datasets(
    pieces: Sequence[StrPath], out: StrPath, *, parquet: bool | None = None
) -> dict[str, Any]:
    """Merge datasets compiled from consecutive pieces of one folder's ``list_takes`` (in
    order) into ``out``: byte for byte the dataset one ``compile_dataset`` of the whole folder
    writes. Returns its manifest."""
    with _ended_cleanly():
        _merge_datasets([os.fspath(p) for p in pieces], os.fspath(out))
        if _want_parquet(parquet):
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
    frame as a fixed-size list column. Needs pyarrow. A group folder, array or
    ``frames.parquet`` that is a symbolic link is refused (ValueError); each file is written
    under an exclusive random temporary name, then renamed."""
    import pyarrow as pa  # type: ignore[import-untyped,import-not-found,unused-ignore]
    import pyarrow.parquet as pq  # type: ignore[import-untyped,import-not-found,unused-ignore]

    root = Path(dataset)
    manifest = _read_manifest(root)
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
                _refuse_link(folder, f"{name}.npy", dir_fd)
                array = np.load(folder / f"{name}.npy", mmap_mode="r")
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

    Item ``i`` is a dict: each array of one window (``window`` frames; a whole clip when
    ``window`` is None) and ``clip`` (index into ``manifest["clips"]``) and ``start`` (its first
    frame in the clip). Windows start every ``stride`` frames (default: ``window``); a clip
    shorter than ``window`` gives none. The arrays are memory-mapped: only the windows read are
    loaded. ``group`` picks one skeleton topology (its index or name); a dataset with one group
    needs none."""

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
        self.manifest = _read_manifest(self.path)
        groups = self.manifest["groups"]
        if not groups:
            raise ValueError(f"{self.path}: the dataset has no clips")
        if group is None:
            if len(groups) != 1:
                listed = ", ".join(f"{g['name']} ({g['clips']} clips)" for g in groups)
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
            if not 0 <= group < len(groups):
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
        self.group = groups[index]
        self.window = window
        self.stride = stride
        self._names = tuple(arrays)
        self._open()
        self.offsets = np.load(self.path / self.group["name"] / "offsets.npy")
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

    def _open(self) -> None:
        folder = self.path / self.group["name"]
        self.arrays = {name: np.load(folder / f"{name}.npy", mmap_mode="r") for name in self._names}

    def __getstate__(self) -> dict[str, Any]:
        # A DataLoader worker started by spawn gets the dataset pickled: the memory maps are
        # opened again there, not copied into the pickle.
        state = self.__dict__.copy()
        del state["arrays"]
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
            f"Dataset({str(self.path)!r}, {self.group['name']}: {len(self.clips)} clips, "
            f"{len(self)} items of {self.window or 'whole clip'} frames)"
        )
