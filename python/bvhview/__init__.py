"""bvhview for Python: BVH and ASF/AMC motion capture as numpy arrays.

    import bvhview
    take = bvhview.load("walk.bvh")
    points = take.positions()          # frames x joints x 3, End Sites included

Loading, forward kinematics and writing are bvhview's Rust code; the GIL is released while
they run.
"""

# Every result is a numpy array: import numpy with the package, not on the first array made.
import numpy as _numpy  # noqa: F401

from ._bvhview import Motion, ParseError, __version__, load, load_many

__all__ = ["Motion", "ParseError", "__version__", "load", "load_many"]
