"""Compile a dataset on a Dask cluster: each worker compiles a piece of the folder's takes, and
the pieces are merged into the dataset one process would have written, byte for byte.

    from distributed import Client
    import bvhview.dask
    with Client("scheduler:8786") as client:
        bvhview.dask.compile_dataset("/shared/mocap", "/shared/mocap.ds", client=client)

The workers must see ``folder`` and the folder ``out`` goes into at the same paths (a shared
file system). Dask schedules the pieces; bvhview has no scheduler of its own.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path
from typing import Any

from ._bvhview import _compile_dataset, list_takes
from .dataset import StrPath, merge_datasets


def _compile_piece(folder: str, index: int, pieces: int, out: str, options: dict[str, Any]) -> str:
    _compile_dataset(folder, out, piece=(index, pieces), **options)
    return out


def compile_dataset(
    folder: StrPath,
    out: StrPath,
    *,
    client: Any = None,
    pieces: int | None = None,
    parquet: bool = False,
    **options: Any,
) -> dict[str, Any]:
    """``bvhview.compile_dataset`` on the workers of ``client`` (default: the current
    ``distributed`` client): the takes, in path order, are cut into ``pieces`` runs (default:
    four per worker thread), each compiled by a worker into a temporary folder beside ``out``,
    then merged. ``options`` are ``compile_dataset``'s (fps, rotations, root_relative,
    contact_height, contact_speed, and threads per piece, default 1). Returns the manifest."""
    if client is None:
        from distributed import get_client

        client = get_client()
    folder = os.fspath(folder)
    out_path = Path(out)
    # Refused before any work, as the merge at the end would refuse it.
    if out_path.exists() and (not out_path.is_dir() or any(out_path.iterdir())):
        raise ValueError(f"{out_path}: already exists; a dataset goes into a new (or empty) folder")
    # Each worker thread compiles a piece at a time: one thread each, unless told otherwise.
    options.setdefault("threads", 1)
    takes = list_takes(folder)
    if pieces is None:
        threads = sum(client.nthreads().values()) or 1
        pieces = 4 * threads
    # Each worker lists the folder again and compiles its run of the list: piece k of n, as
    # bvhview cuts it, so that the merge can check that the runs are one list's, whole.
    pieces = max(1, min(pieces, len(takes)))
    parent = out_path.parent if str(out_path.parent) else Path(".")
    work = Path(tempfile.mkdtemp(prefix=f".{out_path.name}.pieces.", dir=parent))
    try:
        paths = [str(work / f"piece_{k}") for k in range(pieces)]
        futures = client.map(
            _compile_piece,
            [folder] * pieces,
            range(pieces),
            [pieces] * pieces,
            paths,
            [options] * pieces,
            pure=False,
        )
        client.gather(futures)
        return merge_datasets(paths, out_path, parquet=parquet)
    finally:
        shutil.rmtree(work, ignore_errors=True)
