"""bvhview for Python: BVH and ASF/AMC motion capture as numpy arrays.

    import bvhview
    take = bvhview.load("walk.bvh")
    points = take.positions()          # frames x joints x 3, End Sites included

    bvhview.compile_dataset("mocap/", "mocap.ds")          # a folder into training arrays
    data = bvhview.Dataset("mocap.ds", window=64)          # for torch's DataLoader

Loading, forward kinematics, the dataset compile and writing are bvhview's Rust code; the GIL is
released while they run. ``bvhview.dask`` compiles a dataset on a Dask cluster.
"""

# Every result is a numpy array: import numpy with the package, not on the first array made.
import numpy as _numpy  # noqa: F401

from ._bvhview import (
    Character,
    Motion,
    ParseError,
    __version__,
    humanml3d_features,
    list_takes,
    load,
    load_character,
    load_many,
    metrics,
)
from .dataset import Dataset, SkippedTake, compile_dataset, merge_datasets, write_parquet

__all__ = [
    "Character",
    "Dataset",
    "Motion",
    "ParseError",
    "SkippedTake",
    "__version__",
    "compile_dataset",
    "humanml3d_features",
    "list_takes",
    "load",
    "load_character",
    "load_many",
    "merge_datasets",
    "metrics",
    "write_parquet",
]
